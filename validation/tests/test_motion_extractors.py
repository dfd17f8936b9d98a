"""Extractors of moving-body runs on hand-made steps.csv and motion.csv: the oscillating
sphere's force parts come back from a force built of them; a fall's velocity, path angle
and release acceleration come back from a path built of them, turned into the earth axes."""
import math
import tempfile
import unittest
from pathlib import Path

import support  # noqa: F401
import numpy as np

from harness.errors import HarnessError
from harness.extract import EXTRACT
from harness.references import DERIVED
from harness.reference import ReferenceFile

REFERENCE_ROOT = support.ROOT / "reference_data"


class Ctx:
    def __init__(self, directory, inputs):
        self.directory, self.inputs = Path(directory), inputs

    def run_dir(self, run_id):
        return self.directory / run_id

    def input_value(self, run_id, dotted):
        node = self.inputs[run_id]
        for part in dotted.split("."):
            node = node[part]
        return node


def write_csv(path, header, rows):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(",".join(header) + "\n" + "".join(",".join(f"{v:.17g}" for v in r) + "\n" for r in rows))


class OscillationForce(unittest.TestCase):
    OMEGA, AMPLITUDE, RE, AREA = 100.0, 0.01, 2.0, 2.0

    def inputs(self):
        return {"run": {"flow": {"reynolds": self.RE}, "output": {"reference_area": self.AREA},
                        "motion": {"type": "prescribed",
                                   "oscillation": [{"dof": "x", "amplitude": self.AMPLITUDE,
                                                    "angular_frequency": self.OMEGA, "phase": -90.0}]}}}

    def write(self, d, drag_ratio, mass_ratio, periods=4, step_rounding=1.0):
        R, w, A = 0.5, self.OMEGA, self.AMPLITUDE
        a = drag_ratio * 6 * math.pi * R / self.RE
        b = mass_ratio * 0.5 * 4 / 3 * math.pi * R ** 3
        t = np.linspace(0, periods * 2 * math.pi / w * step_rounding, 48 * periods + 1)[1:]
        u, du = A * w * np.sin(w * t), A * w * w * np.cos(w * t)  # phase -90: displacement -A cos(w t)
        force = -(a * u + b * du) + 0.3 + 5.0 * np.exp(-t * w)  # a constant and a start-up transient
        write_csv(Path(d) / "run" / "steps.csv", ["step", "time", "subiterations", "drop", "body_cfx", "body_cfy"],
                  [(n + 1, t[n], 5, 1e-5, force[n] / (0.5 * self.AREA), 0.0) for n in range(t.size)])

    def test_the_parts_a_force_is_built_of_come_back(self):
        with tempfile.TemporaryDirectory() as d:
            self.write(d, 6.0, 1.9)
            fn = EXTRACT["oscillation_force"][0]
            ctx = Ctx(d, self.inputs())
            self.assertAlmostEqual(fn(ctx, {"part": "drag", "periods": 2}, "run"), 6.0, delta=2e-3)
            self.assertAlmostEqual(fn(ctx, {"part": "mass", "periods": 2}, "run"), 1.9, delta=2e-3)

    def test_a_run_shorter_than_the_fit_is_an_error(self):
        with tempfile.TemporaryDirectory() as d:
            self.write(d, 6.0, 1.9, periods=2)
            with self.assertRaisesRegex(HarnessError, "periods"):
                EXTRACT["oscillation_force"][0](Ctx(d, self.inputs()), {"part": "drag", "periods": 2}, "run")

    def test_a_step_written_short_by_its_last_digit_still_covers_its_periods(self):
        # A case file's step 2 pi / (48 w) written to 14 digits ends three periods 6e-14 short.
        with tempfile.TemporaryDirectory() as d:
            self.write(d, 6.0, 1.9, periods=3, step_rounding=1.0 - 5e-14)
            value = EXTRACT["oscillation_force"][0](Ctx(d, self.inputs()), {"part": "drag", "periods": 2}, "run")
            self.assertAlmostEqual(value, 6.0, delta=2e-3)

    def test_a_rotation_is_not_a_translational_oscillation(self):
        inputs = self.inputs()
        inputs["run"]["motion"]["oscillation"][0]["dof"] = "pitch"
        with tempfile.TemporaryDirectory() as d:
            self.write(d, 6.0, 1.9)
            with self.assertRaisesRegex(HarnessError, "translation"):
                EXTRACT["oscillation_force"][0](Ctx(d, inputs), {"part": "drag"}, "run")

    def test_the_reference_file_holds_stokes_closed_form(self):
        ref = ReferenceFile(REFERENCE_ROOT, "sphere/sphere_oscillating_stokes.csv")
        for r in ref.column("R_over_delta"):
            row = ref.rows_where({"R_over_delta": float(r)})
            self.assertAlmostEqual(float(ref.column("drag_over_stokes", row)[0]), 1 + r, places=12)
            self.assertAlmostEqual(float(ref.column("mass_over_added", row)[0]), 1 + 4.5 / r, places=12)


def quaternion_about(axis, angle):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    return np.concatenate([[math.cos(angle / 2)], math.sin(angle / 2) * axis])


def rotation(e):
    e0, e1, e2, e3 = e
    return np.array([[1 - 2 * (e2 * e2 + e3 * e3), 2 * (e1 * e2 - e0 * e3), 2 * (e1 * e3 + e0 * e2)],
                     [2 * (e1 * e2 + e0 * e3), 1 - 2 * (e1 * e1 + e3 * e3), 2 * (e2 * e3 - e0 * e1)],
                     [2 * (e1 * e3 - e0 * e2), 2 * (e2 * e3 + e0 * e1), 1 - 2 * (e1 * e1 + e2 * e2)]])


class Fall(unittest.TestCase):
    HEADER = ["step", "time", "x", "y", "z", "e0", "e1", "e2", "e3", "roll_deg", "pitch_deg", "yaw_deg",
              "u", "v", "w", "p", "q", "r", "X", "Y", "Z", "K", "M", "N", "subiterations", "coupling_change"]

    def write(self, d, earth_velocity_of, times, turned=0.7):
        """Rows whose body velocities, turned by a quaternion, are earth_velocity_of(t)."""
        e = quaternion_about([0.3, -0.5, 0.8], turned)
        rows = []
        for n, t in enumerate(times):
            uvw = rotation(e).T @ earth_velocity_of(t)
            rows.append([n + 1, t, 0, 0, 0, *e, 0, 0, 0, *uvw, *([0.0] * 9), 4, 1e-7])
        write_csv(Path(d) / "run" / "motion.csv", self.HEADER, rows)

    def inputs(self, gravity):
        return {"run": {"motion": {"type": "free", "gravity": gravity}}}

    def test_an_oblique_steady_fall_gives_its_speeds_and_angle(self):
        down = np.array([1.0, 0.0, 0.0])  # the earth axes are the grid's
        fall = 1.356 * down + np.array([0.0, 0.1245 * 0.6, 0.1245 * 0.8])
        with tempfile.TemporaryDirectory() as d:
            self.write(d, lambda t: fall, np.arange(1, 401) * 0.1)
            ctx, fn = Ctx(d, self.inputs([2.0, 0.0, 0.0])), EXTRACT["fall_velocity"][0]
            self.assertAlmostEqual(fn(ctx, {"part": "vertical", "window": 5}, "run"), -1.356, places=10)
            self.assertAlmostEqual(fn(ctx, {"part": "horizontal", "window": 5}, "run"), 0.1245, places=10)
            self.assertAlmostEqual(fn(ctx, {"part": "angle", "window": 5}, "run"),
                                   math.degrees(math.atan2(0.1245, 1.356)), places=8)

    def test_release_acceleration_comes_back_through_the_history_force(self):
        a0, c = 0.5, 0.2  # fall speed a0 t - c t^1.5 (a Basset-like start)
        down = np.array([0.0, 0.0, 1.0])
        with tempfile.TemporaryDirectory() as d:
            self.write(d, lambda t: (a0 * t - c * t ** 1.5) * down, np.arange(1, 11) * 0.002)
            got = EXTRACT["release_acceleration"][0](Ctx(d, self.inputs([0.0, 0.0, 2.0])), {"steps": 10}, "run")
            self.assertAlmostEqual(got, a0 / 2.0, places=10)

    def test_the_axis_angle_from_vertical_follows_the_attitude(self):
        # Turned 70 degrees about y from the grid's axes: the body's x axis is 70 degrees
        # from the earth's x, along which gravity points here.
        e = quaternion_about([0.0, 1.0, 0.0], math.radians(70.0))
        rows = [[1, 0.1, 0, 0, 0, *e] + [0.0] * 17]
        with tempfile.TemporaryDirectory() as d:
            write_csv(Path(d) / "run" / "motion.csv", self.HEADER, rows)
            got = EXTRACT["axis_from_vertical"][0](Ctx(d, self.inputs([-2.0, 0.0, 0.0])), {}, "run")
            self.assertAlmostEqual(got, 70.0, places=10)

    def test_a_coasting_body_has_no_speed_rise_and_an_oscillating_one_has(self):
        times = np.arange(1, 41) * 0.1
        with tempfile.TemporaryDirectory() as d:
            self.write(d, lambda t: np.array([0.5 / (1 + t), 0.0, 0.0]), times)
            ctx = Ctx(d, self.inputs([0.0, 0.0, 0.0]))
            self.assertLess(EXTRACT["speed_rise"][0](ctx, {"from_time": 0.5}, "run"), 0.0)
            self.write(d, lambda t: np.array([0.5 / (1 + t) * (1 + 0.05 * (-1) ** round(t / 0.1)), 0, 0]), times)
            self.assertGreater(EXTRACT["speed_rise"][0](ctx, {"from_time": 0.5}, "run"), 0.05)
            self.assertEqual(EXTRACT["motion_extreme"][0](ctx, {"column": "coupling_change"}, "run"), 1e-7)
            with self.assertRaisesRegex(HarnessError, "no column"):
                EXTRACT["motion_extreme"][0](ctx, {"column": "drift"}, "run")

    def test_zero_gravity_is_an_error(self):
        with tempfile.TemporaryDirectory() as d:
            self.write(d, lambda t: np.zeros(3), np.arange(1, 11) * 0.1)
            with self.assertRaisesRegex(HarnessError, "gravity is zero"):
                EXTRACT["release_acceleration"][0](Ctx(d, self.inputs([0.0, 0.0, 0.0])), {"steps": 5}, "run")

    def test_theory_for_a_sphere_uses_lamb_s_half(self):
        ref = ReferenceFile(REFERENCE_ROOT, "spheroid/spheroid_added_mass_lamb.csv")
        got = DERIVED["release_acceleration"](ref, {"ratio": 1.0, "density_ratio": 1.5})
        self.assertAlmostEqual(got, 0.5 / 2.0, places=12)  # (1.5 - 1) / (1.5 + 1/2)


class StandardDragFall(unittest.TestCase):
    def setUp(self):
        self.ref = ReferenceFile(REFERENCE_ROOT, "sphere/sphere_drag_correlations.csv")

    def test_weight_less_buoyancy_equals_the_curve_s_drag(self):
        ga = 600.0
        u = -DERIVED["fall_velocity_standard_drag"](self.ref, {"galileo": ga})
        re, cd = self.ref.column("Re"), self.ref.column("CD_CliftGraceWeber")
        cd_at = math.exp(np.interp(math.log(ga * u), np.log(re), np.log(cd)))
        self.assertAlmostEqual(u * u * cd_at, 4.0 / 3.0, places=10)
        self.assertTrue(900.0 < ga * u < 1100.0)  # Re about 1000 at Ga = 600

    def test_the_curve_holds_for_uhlmann_and_dusek_s_chaotic_fall(self):
        # Their Ga = 250 sphere (regime D) falls at a mean -1.4604 u_g: a free sphere's mean
        # drag is the fixed sphere's, to the curve's own accuracy (a few percent in C_D).
        fall = ReferenceFile(REFERENCE_ROOT, "sphere/sphere_freefall_uhlmann_dusek2014.csv")
        rows = fall.rows_where({"case": "D_L", "quantity": "mean_vertical_velocity"})
        measured = float(fall.column("value", rows)[0])
        predicted = DERIVED["fall_velocity_standard_drag"](self.ref, {"galileo": 250.0})
        self.assertLess(abs(predicted / measured - 1.0), 0.02)

    def test_a_galileo_number_off_the_table_is_an_error(self):
        with self.assertRaisesRegex(HarnessError, "outside the table|no terminal velocity"):
            DERIVED["fall_velocity_standard_drag"](self.ref, {"galileo": 1.0e6})


if __name__ == "__main__":
    unittest.main()


class PathThroughTheWater(unittest.TestCase):
    """A body held in a stream of 1 along +x (it heads into it, towards -x), gravity +z:
    its path through the water is its grid position less the stream's carry."""
    HEADER = Fall.HEADER

    def write(self, d, run, times, position_of):
        rows = [[n + 1, t, *position_of(t), 1, 0, 0, 0] + [0.0] * 17 for n, t in enumerate(times)]
        write_csv(Path(d) / run / "motion.csv", self.HEADER, rows)

    def inputs(self, *runs, farfield=None):
        motion = {"type": "free", "gravity": [0.0, 0.0, 4.59], "origin": [0.46, 0.0, 0.0]}
        bc = {"farfield": {"type": "farfield", **({"velocity": farfield} if farfield else {})}}
        return {r: {"motion": motion, "bc": bc} for r in runs}

    def test_rise_and_travel_come_back_from_a_path_built_of_them(self):
        # Through the water: travel 1.0 t (and, held in the stream, x stays), rise 0.1 sin(t)
        # (z down): a rise to 0.1 at t = pi/2, back to 0 at pi, down to -0.1 at 3 pi / 2.
        times = np.arange(1, 501) * 0.01
        with tempfile.TemporaryDirectory() as d:
            self.write(d, "run", times, lambda t: (0.46, 0.0, -0.1 * math.sin(t)))
            ctx, fn = Ctx(d, self.inputs("run")), EXTRACT["path"][0]
            self.assertAlmostEqual(fn(ctx, {"part": "rise", "reduce": "max"}, "run"), 0.1, places=6)
            self.assertAlmostEqual(fn(ctx, {"part": "rise", "reduce": "min"}, "run"), -0.1, places=6)
            self.assertAlmostEqual(fn(ctx, {"part": "rise", "reduce": "end"}, "run"), 0.1 * math.sin(5.0), places=12)
            self.assertAlmostEqual(fn(ctx, {"part": "travel", "reduce": "end"}, "run"), 5.0, places=12)
            # Slowing in the stream (drifting aft, +x, at 0.1) it travels 10 % less.
            self.write(d, "run", times, lambda t: (0.46 + 0.1 * t, 0.0, 0.0))
            self.assertAlmostEqual(fn(ctx, {"part": "travel", "reduce": "end"}, "run"), 4.5, places=12)
            # A far field given moves the water with it.
            ctx = Ctx(d, self.inputs("run", farfield=[0.5, 0.0, 0.0]))
            self.assertAlmostEqual(fn(ctx, {"part": "travel", "reduce": "end"}, "run"), 2.0, places=12)
            with self.assertRaisesRegex(HarnessError, "part must be"):
                fn(ctx, {"part": "depth"}, "run")

    def test_two_time_steps_paths_differ_by_their_largest_distance(self):
        with tempfile.TemporaryDirectory() as d:
            self.write(d, "coarse", np.arange(1, 251) * 0.02, lambda t: (0.46, 0.0, -0.1 * math.sin(t)))
            self.write(d, "fine", np.arange(1, 501) * 0.01, lambda t: (0.46, 0.0, -0.1 * math.sin(t) - 0.004 * t))
            ctx, fn = Ctx(d, self.inputs("coarse", "fine")), EXTRACT["path_difference"][0]
            # The fine path sinks 0.004 t more; linear interpolation of a sine on 0.01 errs by < 2e-6.
            self.assertAlmostEqual(fn(ctx, {"other": "fine"}, "coarse"), 0.02, delta=2e-6)
            self.assertAlmostEqual(fn(ctx, {"other": "coarse"}, "fine"), 0.02, delta=2e-6)
            # Compared up to the shorter run's end.
            self.write(d, "fine", np.arange(1, 101) * 0.01, lambda t: (0.46, 0.0, -0.1 * math.sin(t) - 0.004 * t))
            self.assertAlmostEqual(fn(ctx, {"other": "fine"}, "coarse"), 0.004, delta=2e-6)

    def test_a_run_turned_by_a_flow_angle_must_give_its_water(self):
        with tempfile.TemporaryDirectory() as d:
            self.write(d, "run", [0.1], lambda t: (0.46, 0.0, 0.0))
            inputs = self.inputs("run")
            inputs["run"]["flow"] = {"angle_of_attack": 4.0}
            with self.assertRaisesRegex(HarnessError, "give bc.farfield.velocity"):
                EXTRACT["path"][0](Ctx(d, inputs), {"part": "rise"}, "run")


class SideView(unittest.TestCase):
    def test_two_paths_and_the_time_histories_of_rise_are_drawn(self):
        from harness import report
        with tempfile.TemporaryDirectory() as d:
            rung_dir = Path(d)
            writer = PathThroughTheWater()
            for run, dt in (("coarse", 0.02), ("fine", 0.01)):
                times = np.arange(1, round(5.0 / dt) + 1) * dt
                rows = []
                for n, t in enumerate(times):
                    # The release attitude (x_B = -x: 180 degrees about z) pitched about y_B,
                    # nose down by 11 degrees at the end.
                    pitch = -0.2 * t / 5.0
                    e = [0.0, -math.sin(pitch / 2), 0.0, math.cos(pitch / 2)]
                    rows.append([n + 1, t, 0.46, 0.0, -0.1 * math.sin(t), *e] + [0.0] * 17)
                write_csv(rung_dir / "runs" / run / "motion.csv", writer.HEADER, rows)
            frame = {"origin": [0.46, 0.0, 0.0], "stream": [1.0, 0.0, 0.0], "down": [0.0, 0.0, 1.0]}
            pic = {"kind": "side_view", "run": "coarse", "beside": "fine", "title": "blow", "frame": frame}
            self.assertTrue(report._plot_picture(rung_dir, pic, rung_dir / "side.png"))
            self.assertGreater((rung_dir / "side.png").stat().st_size, 1000)
            pic = dict(pic, kind="plan_view")
            self.assertTrue(report._plot_picture(rung_dir, pic, rung_dir / "plan.png"))
            pic = {"kind": "time_history", "run": "fine", "column": "motion:rise", "title": "rise", "frame": frame}
            series = report._time_history(rung_dir, pic)
            self.assertAlmostEqual(float(np.max(series[1])), 0.1, places=6)
            self.assertTrue(report._plot_picture(rung_dir, pic, rung_dir / "rise.png"))


class RunJsonTables(unittest.TestCase):
    def test_a_field_may_walk_into_run_json_s_tables(self):
        with tempfile.TemporaryDirectory() as d:
            (Path(d) / "run").mkdir()
            (Path(d) / "run" / "run.json").write_text('{"wall_seconds": 12.5, "trim": {"weight": -3e-5}}')
            ctx, fn = Ctx(d, {}), EXTRACT["run_json"][0]
            self.assertEqual(fn(ctx, {"field": "trim.weight"}, "run"), -3e-5)
            self.assertEqual(fn(ctx, {"field": "wall_seconds"}, "run"), 12.5)
            for missing in ("trim.moment", "wall_seconds.x", "ballast"):
                with self.assertRaisesRegex(HarnessError, "no field"):
                    fn(ctx, {"field": missing}, "run")


class Manoeuvres(unittest.TestCase):
    """A turning circle and zig-zags built of known figures, on a body held in a stream of
    1 along +x (heading -x at release; starboard is -y, down +z)."""
    HEADER = Fall.HEADER

    def write(self, d, rows):
        write_csv(Path(d) / "run" / "motion.csv", self.HEADER, rows)

    def inputs(self):
        return {"run": {"motion": {"type": "free", "gravity": [0.0, 0.0, 4.59], "origin": [0.46, 0.0, 0.0]},
                        "bc": {"farfield": {"type": "farfield"}}}}

    def test_a_circle_s_advance_transfer_tactical_diameter_and_rate_come_back(self):
        radius, rate = 1.7, 0.25  # rad per unit time: 14.3 degrees per L/U
        rows = []
        for n, t in enumerate(np.arange(1, 1601) * 0.01):
            psi = rate * t
            ahead, starboard = radius * math.sin(psi), radius * (1.0 - math.cos(psi))
            x, y = 0.46 - ahead + t, -starboard  # through the water, plus the stream's carry
            rows.append([n + 1, t, x, y, 0.0, 1, 0, 0, 0, 0.0, 0.0, math.degrees(psi)] + [0.0] * 14)
        with tempfile.TemporaryDirectory() as d:
            self.write(d, rows)
            ctx, fn = Ctx(d, self.inputs()), EXTRACT["turning_circle"][0]
            self.assertAlmostEqual(fn(ctx, {"part": "advance"}, "run"), radius, places=4)
            self.assertAlmostEqual(fn(ctx, {"part": "transfer"}, "run"), radius, places=4)
            self.assertAlmostEqual(fn(ctx, {"part": "tactical_diameter"}, "run"), 2.0 * radius, places=4)
            self.assertAlmostEqual(fn(ctx, {"part": "turn_rate", "window": 2.0}, "run"), math.degrees(rate), places=8)
            # Turned past 360 degrees: the heading unwraps (the yaw column wraps at 180).
            for r in rows:
                r[11] = (r[11] + 180.0) % 360.0 - 180.0
            self.write(d, rows)
            self.assertAlmostEqual(fn(ctx, {"part": "tactical_diameter"}, "run"), 2.0 * radius, places=4)
            self.write(d, rows[:500])  # 72 degrees: no tactical diameter yet
            with self.assertRaisesRegex(HarnessError, "not the 180"):
                fn(ctx, {"part": "tactical_diameter"}, "run")

    def test_a_zigzag_s_overshoots_are_its_extremes_beyond_the_switching_angle(self):
        # Heading swinging as 13 sin(t) then 16 sin(t): extremes 13 (first, after the first
        # reversal at 10) and -16 (second).
        rows = []
        for n, t in enumerate(np.arange(1, 701) * 0.01):
            yaw = (13.0 if t < math.pi else 16.0) * math.sin(t)
            rows.append([n + 1, t, 0.46, 0, 0, 1, 0, 0, 0, 0.0, 0.0, yaw] + [0.0] * 14)
        with tempfile.TemporaryDirectory() as d:
            self.write(d, rows)
            ctx, fn = Ctx(d, self.inputs()), EXTRACT["zigzag_overshoot"][0]
            self.assertAlmostEqual(fn(ctx, {"column": "yaw_deg", "switch_at": 10.0, "which": 1}, "run"), 3.0, places=3)
            self.assertAlmostEqual(fn(ctx, {"column": "yaw_deg", "switch_at": 10.0, "which": 2}, "run"), 6.0, places=3)
            with self.assertRaisesRegex(HarnessError, "reversal 3 needs 3"):
                fn(ctx, {"column": "yaw_deg", "switch_at": 10.0, "which": 3}, "run")
            with self.assertRaisesRegex(HarnessError, "column must be"):
                fn(ctx, {"column": "roll_deg", "switch_at": 10.0}, "run")
