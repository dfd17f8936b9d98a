"""Captive-sweep extractors on hand-made run.json files: coefficients summed over wall
groups in body axes, the derivative against v' = -sin(beta) with its standard error, the
oddness of a symmetric configuration's side force, each point's iteration band from its
history.csv, and the refusals."""
import json
import math
import unittest

import numpy as np
from support import rung_in_temp_dir

from harness.captive import linear_fit
from harness.errors import HarnessError
from harness.extract import Context, extract
from harness.runner import effective_input

RUNG = """
[rung]
title = "t"
tiers = ["quick"]

[[sweep]]
id = "drift"
input = "in.toml"
variable = "flow.drift_angle"
values = [-8, -4, 0, 4, 8]

[[check]]
name = "c"
extract = { kind = "sweep_oddness", sweep = "drift", component = "Y", groups = ["body", "sail"] }
comparator = "max"
tolerance = 1e-6
rationale = "because"
"""

INPUT = """
[grid]
length = 2.0
[output]
reference_area = 4.0
reference_length = 2.0
"""


WINDOW = 4  # settings.force_window of the made-up runs


def swing(beta_deg):
    """The half-amplitude by which the made-up runs' side force still swings at the end."""
    return 1e-6 * (1.0 + abs(beta_deg))


def write_history(d, forces, half):
    """history.csv in grid axes (x_B = -x, y_B = -y, z_B = z): an early row far off (before
    the last WINDOW iterations, which the band must ignore), then WINDOW rows in which the
    body group's side force swings by +-half about its final value."""
    columns = [f"{g}_{c}" for g in forces for c in ("cfx", "cfy", "cfz", "cmx", "cmy", "cmz")]
    sign = {"cfx": -1, "cfy": -1, "cfz": 1, "cmx": -1, "cmy": -1, "cmz": 1}
    names = {"cfx": "X", "cfy": "Y", "cfz": "Z", "cmx": "K", "cmy": "M", "cmz": "N"}
    lines = ["iteration,wall_s,cfl," + ",".join(columns)]
    offsets = [1.0] + [half * w for w in (1.0, -1.0, 0.5, 0.0)]
    for it, off in enumerate(offsets, 1):
        row = []
        for col in columns:
            g, c = col.rsplit("_", 1)
            value = sign[c] * forces[g]["body_axes"][names[c]]
            row.append(value + (sign[c] * off if (g == "body" and c == "cfy") else 0.0))
        lines.append(f"{it},{it}.0,1.0," + ",".join(repr(v) for v in row))
    (d / "history.csv").write_text("\n".join(lines) + "\n")


def side_force(beta_deg):
    """Y' of a made-up hull: linear in v' plus a cubic term (cross-flow drag)."""
    v = -math.sin(math.radians(beta_deg))
    return -0.03 * v + 0.1 * v ** 3


class CaptiveSweeps(unittest.TestCase):
    def setUp(self):
        self.dir, self.rung = rung_in_temp_dir(RUNG, INPUT)

    def context(self, split=(0.75, 0.25), inputs=None):
        """Runs whose hull and sail carry `split` of Y' (and of the other components, scaled)."""
        dirs, effective = {}, {}
        value = {rid: v for sweep in self.rung.sweeps for rid, v in zip(sweep.run_ids, sweep.values)}
        for run in self.rung.runs:
            d = self.dir / "runs" / run.id
            d.mkdir(parents=True, exist_ok=True)
            y = side_force(value[run.id])
            forces = {g: {"body_axes": {"X": -0.001 * s, "Y": y * s, "Z": 0.0, "K": 0.1 * y * s, "M": 0.0,
                                        "N": 0.5 * y * s}} for g, s in zip(("body", "sail"), split)}
            (d / "run.json").write_text(json.dumps({"forces": forces, "force_span": 1e-7 * (1 + abs(value[run.id])),
                                                    "settings": {"force_window": WINDOW}}))
            write_history(d, forces, swing(value[run.id]))
            dirs[run.id] = d
            effective[run.id] = effective_input(run) if inputs is None else inputs
        return Context(self.rung, dirs, effective)

    def test_coefficients_are_summed_over_the_groups_against_the_swept_values(self):
        curve = extract(self.context(), {"kind": "sweep_coefficient", "sweep": "drift", "component": "Y",
                                         "groups": ["body", "sail"]})
        self.assertEqual(curve.x.tolist(), [-8.0, -4.0, 0.0, 4.0, 8.0])
        for b, y in zip(curve.x, curve.y):
            self.assertAlmostEqual(y, side_force(b), places=15)

    def test_each_point_carries_half_its_range_over_the_force_window_as_its_iteration_band(self):
        curve = extract(self.context(), {"kind": "sweep_coefficient", "sweep": "drift", "component": "Y",
                                         "groups": ["body", "sail"]})
        # The body's side force swings by +-swing in the window; the row before it (1.0 off)
        # is outside and the sail's is steady.
        for b, band in zip(curve.x, curve.yerr):
            self.assertAlmostEqual(band, swing(b), places=15)
        steady = extract(self.context(), {"kind": "sweep_coefficient", "sweep": "drift", "component": "N",
                                          "groups": ["body", "sail"]})
        self.assertEqual(steady.yerr.tolist(), [0.0] * 5)

    def test_the_derivative_s_iteration_error_is_the_worst_case_of_the_points_bands(self):
        spec = {"kind": "sweep_derivative", "sweep": "drift", "component": "Y", "groups": ["body", "sail"],
                "against": "v", "max_angle": 4.0, "statistic": "iteration_error"}
        # Points at v = -sin(b) for b = -4, 0, 4: |dx| = v4, 0, v4; sum dx^2 = 2 v4^2.
        v4 = math.sin(math.radians(4.0))
        self.assertAlmostEqual(extract(self.context(), spec), 2 * v4 * swing(4.0) / (2 * v4 * v4), places=12)
        self.assertEqual(extract(self.context(), {**spec, "component": "N"}), 0.0)

    def test_the_iterations_a_retreat_undid_are_not_in_the_band(self):
        ctx = self.context()
        path = ctx.run_dir("drift_4") / "run.json"
        data = json.loads(path.read_text())
        spec = {"kind": "sweep_coefficient", "sweep": "drift", "component": "Y", "groups": ["body"]}
        # Iteration 3 (a swing of -swing) diverged and the run went back to iteration 2's state;
        # the band is then that of the rows 1, 2, 4, 5: the far-off first row comes in.
        data["retreats"] = [{"diverged_at": 3, "back_to": 2, "cfl_ceiling": 1.0, "reason": "made up"}]
        path.write_text(json.dumps(data))
        band = extract(ctx, spec).yerr[3]
        self.assertAlmostEqual(band, 0.5 * (1.0 - 0.0), places=12)

    def test_an_iteration_band_needs_the_window_and_the_columns(self):
        ctx = self.context()
        path = ctx.run_dir("drift_4") / "run.json"
        data = json.loads(path.read_text())
        data["settings"] = {}
        path.write_text(json.dumps(data))
        spec = {"kind": "sweep_coefficient", "sweep": "drift", "component": "Y", "groups": ["body"]}
        with self.assertRaises(HarnessError) as cm:
            extract(ctx, spec)
        self.assertIn("settings.force_window", str(cm.exception))
        ctx = self.context()
        (ctx.run_dir("drift_0") / "history.csv").write_text("iteration,wall_s\n1,1.0\n2,2.0\n")
        with self.assertRaises(HarnessError) as cm:
            extract(ctx, spec)
        self.assertIn("no column 'body_cfy'", str(cm.exception))

    def test_one_run_s_coefficient_is_its_groups_sum(self):
        value = extract(self.context(), {"kind": "run_coefficient", "run": "drift_4", "component": "N",
                                         "groups": ["body", "sail"]})
        self.assertAlmostEqual(value, 0.5 * side_force(4.0), places=15)
        with self.assertRaises(HarnessError):
            extract(self.context(), {"kind": "run_coefficient", "run": "drift_4", "component": "Q", "groups": ["body"]})

    def test_the_derivative_against_v_is_the_linear_term_with_the_cubics_scatter_as_its_error(self):
        ctx = self.context()
        spec = {"kind": "sweep_derivative", "sweep": "drift", "component": "Y", "groups": ["body", "sail"],
                "against": "v", "max_angle": 4.0}
        slope = extract(ctx, spec)
        # Three points in v' = 0, +-sin 4 deg: the line through them has slope
        # -0.03 + 0.1 * (2 v^3) v / (2 v^2) = -0.03 + 0.1 v^2 exactly (odd data, symmetric points).
        v = math.sin(math.radians(4.0))
        self.assertAlmostEqual(slope, -0.03 + 0.1 * v * v, places=14)
        # Odd data on symmetric points lie on the fitted line: the scatter is zero.
        self.assertAlmostEqual(extract(ctx, {**spec, "statistic": "standard_error"}), 0.0, places=14)
        wide = extract(ctx, {**spec, "max_angle": 8.0, "statistic": "standard_error"})
        self.assertGreater(wide, 0.0)

    def test_the_oddness_of_an_odd_sweep_is_round_off_and_an_offset_shows(self):
        spec = {"kind": "sweep_oddness", "sweep": "drift", "component": "N", "groups": ["body", "sail"]}
        self.assertLess(extract(self.context(), spec), 1e-17)
        ctx = self.context()
        path = ctx.run_dir("drift_0") / "run.json"
        data = json.loads(path.read_text())
        data["forces"]["sail"]["body_axes"]["N"] = 1e-5
        path.write_text(json.dumps(data))
        self.assertAlmostEqual(extract(ctx, spec), 2e-5, places=18)

    def test_the_magnitude_is_the_largest_size_over_the_sweep(self):
        spec = {"kind": "sweep_magnitude", "sweep": "drift", "component": "Y", "groups": ["body", "sail"]}
        self.assertAlmostEqual(extract(self.context(), spec), abs(side_force(8)), places=15)
        self.assertEqual(extract(self.context(), {**spec, "component": "Z"}), 0.0)

    def test_the_least_steady_point_is_found(self):
        ctx = self.context()
        self.assertAlmostEqual(extract(ctx, {"kind": "sweep_largest", "sweep": "drift", "field": "force_span"}), 9e-7,
                               places=20)
        with self.assertRaises(HarnessError) as cm:
            extract(ctx, {"kind": "sweep_largest", "sweep": "drift", "field": "span"})
        self.assertIn("has no field 'span'", str(cm.exception))

    def test_refusals_name_what_is_wrong(self):
        ctx = self.context()
        base = {"kind": "sweep_coefficient", "sweep": "drift", "component": "Y", "groups": ["body"]}
        for bad, said in (({"sweep": "beta"}, "no sweep 'beta'"), ({"component": "Q"}, "'component' must be"),
                          ({"groups": []}, "'groups' must be"), ({"groups": ["rudder"]}, "no force group 'rudder'")):
            with self.assertRaises(HarnessError) as cm:
                extract(ctx, {**base, **bad})
            self.assertIn(said, str(cm.exception))
        wrong_area = self.context(inputs={"grid": {"length": 2.0}, "output": {"reference_area": 1.0}})
        with self.assertRaises(HarnessError) as cm:
            extract(wrong_area, base)
        self.assertIn("reference_area = L^2", str(cm.exception))
        # Another length than the grid's (the captive data's L_BP) when the run is set for it.
        other = self.context(inputs={"grid": {"length": 2.0}, "output": {"reference_area": 0.25, "reference_length": 0.5}})
        self.assertEqual(extract(other, {**base, "length": 0.5}).y.size, 5)

    def test_a_reported_sweep_curve_is_drawn_in_the_report(self):
        from harness import report
        from harness.casefile import Reported
        from harness.runner import _reported
        q = Reported(name="Y' against drift", tiers=("quick",), unit="Y'",
                     extract={"kind": "sweep_coefficient", "sweep": "drift", "component": "Y", "groups": ["body"]})
        entry = _reported(self.context(), q)
        self.assertEqual(entry["curve"]["x"], [-8.0, -4.0, 0.0, 4.0, 8.0])
        self.assertEqual(len(entry["curve"]["yerr"]), 5)
        html = report._reported_section([entry], self.dir)
        self.assertIn("plotted below", html)
        self.assertIn("<img src='reported_0.png'", html)
        self.assertGreater((self.dir / "reported_0.png").stat().st_size, 1000)

    def test_linear_fit_recovers_a_line_and_refuses_a_single_abscissa(self):
        slope, error = linear_fit([0.0, 1.0, 2.0, 3.0], [1.0, 3.0, 5.0, 7.0])
        self.assertAlmostEqual(slope, 2.0, places=14)
        self.assertAlmostEqual(error, 0.0, places=14)
        self.assertTrue(math.isnan(linear_fit([0.0, 1.0], [0.0, 1.0])[1]))
        with self.assertRaises(HarnessError):
            linear_fit([1.0, 1.0], [0.0, 2.0])


UNSTEADY_RUNG = RUNG.replace('values = [-8, -4, 0, 4, 8]', """values = [-8, -4, 0, 4, 8]

[sweep.unsteady]
force_span = 1.0e-3
discard = 1.0
set = { "time.scheme" = "bdf2", "time.step" = 0.02, "time.steps" = 400 }""")

PERIOD = 1.3  # of the made-up continuations' swing


class UnsteadyPoints(unittest.TestCase):
    """Points whose steady runs ended with their forces swinging (the +-8 degree ones here)
    take their values from their continuations in physical time."""

    def setUp(self):
        self.dir, self.rung = rung_in_temp_dir(UNSTEADY_RUNG, INPUT)

    def context(self, drift=1e-4):
        """Steady runs as CaptiveSweeps'; at +-8 degrees a force span of 2e-2 and a
        continuation whose body side force swings by +-0.2 |Y'| about side_force(b), with a
        transient of 0.5 |Y'| in its first time unit and a drift of the mean by `drift`
        |Y'| per period, the sail's steady at 0."""
        dirs, effective = {}, {}
        sweep = self.rung.sweeps[0]
        for rid, b in zip(sweep.run_ids, sweep.values):
            d = self.dir / "runs" / rid
            d.mkdir(parents=True, exist_ok=True)
            y = side_force(b)
            forces = {g: {"body_axes": {"X": -0.001, "Y": y * f, "Z": 0.0, "K": 0.0, "M": 0.0, "N": 0.0}}
                      for g, f in (("body", 1.0), ("sail", 0.0))}
            unsteady = abs(b) == 8
            (d / "run.json").write_text(json.dumps({"forces": forces, "force_span": 2e-2 if unsteady else 1e-7,
                                                    "settings": {"force_window": WINDOW}}))
            write_history(d, forces, 0.0)
            dirs[rid] = d
            effective[rid] = effective_input(next(r for r in self.rung.runs if r.id == rid))
            if unsteady:
                later = sweep.unsteady.run_ids[sweep.run_ids.index(rid)]
                c = self.dir / "runs" / later
                c.mkdir(parents=True, exist_ok=True)
                t = np.arange(1, 501) * 0.02
                body_y = y * (1.0 + 0.2 * np.sin(2 * math.pi * t / PERIOD) + 0.5 * (t < 1.0)
                              + drift * t / PERIOD)
                rows = ["step,time,subiterations,drop,body_cfx,body_cfy,body_cfz,sail_cfx,sail_cfy,sail_cfz"]
                for n, (tn, yn) in enumerate(zip(t, body_y), 1):
                    # grid axes: cfx = -X, cfy = -Y
                    rows.append(f"{n},{tn!r},5,1.0,0.001,{-yn!r},0.0,0.001,0.0,0.0")
                (c / "steps.csv").write_text("\n".join(rows) + "\n")
                dirs[later] = c
                effective[later] = effective_input(next(r for r in self.rung.runs if r.id == later))
        return Context(self.rung, dirs, effective)

    def test_the_rung_declares_one_continuation_per_point_from_its_steady_run(self):
        sweep = self.rung.sweeps[0]
        self.assertEqual(sweep.unsteady.run_ids[0], "drift_m8_time")
        later = next(r for r in self.rung.runs if r.id == "drift_m8_time")
        self.assertEqual((later.restart_from, later.when_unsteady), ("drift_m8", 1e-3))
        self.assertEqual(later.set["time.step"], "0.02")
        self.assertEqual(later.set["flow.drift_angle"], "-8.0")

    def test_an_unsteady_point_s_value_is_its_continuation_s_mean_over_whole_periods(self):
        curve = extract(self.context(drift=0.0), {"kind": "sweep_coefficient", "sweep": "drift", "component": "Y",
                                                  "groups": ["body", "sail"]})
        for b, y, band in zip(curve.x, curve.y, curve.yerr):
            # The transient (first time unit) is left out; the swing averages out over whole periods.
            self.assertAlmostEqual(y, side_force(b), delta=1e-5 * abs(side_force(b)))
            self.assertLessEqual(band, 1e-5 * abs(side_force(b)))
        self.assertLess(extract(self.context(drift=0.0), {"kind": "sweep_oddness", "sweep": "drift", "component": "Y",
                                                          "groups": ["body", "sail"]}), 1e-8)

    def test_a_point_whose_periods_means_differ_carries_the_standard_error_of_its_mean(self):
        drift = 1e-3
        ctx = self.context(drift=drift)
        curve = extract(ctx, {"kind": "sweep_coefficient", "sweep": "drift", "component": "Y", "groups": ["body"]})
        y8 = abs(side_force(8.0))
        # Periods from t = 1 to 10: six whole ones, whose means step by drift |Y'|: their
        # standard deviation is drift |Y'| sqrt(P (P + 1) / 12), over sqrt(P).
        error = drift * y8 * math.sqrt(7 / 12)
        self.assertAlmostEqual(curve.yerr[-1], error, delta=0.03 * error)
        span = extract(ctx, {"kind": "sweep_largest", "sweep": "drift", "field": "force_span"})
        # Twice that over the largest group's force (the body's, X' = -0.001 and Y').
        force = math.hypot(0.001, y8 * (1.0 + drift * 5.5))
        self.assertAlmostEqual(span, 2 * error / force, delta=0.03 * 2 * error / force)

    def test_the_report_states_the_rule_and_the_points_continued(self):
        from harness import report
        from harness.captive import continuation_summary, point_force_span
        still = self.context(drift=0.0)
        summary = continuation_summary(still)
        self.assertEqual([p["point"] for p in summary[0]["points"]], ["drift_m8", "drift_8"])
        self.assertEqual(summary[0]["points"][1]["force_span"], point_force_span(still, still.rung.sweeps[0], "drift_8"))
        self.assertGreaterEqual(summary[0]["points"][0]["periods"], 6)
        html = report._unsteady_points_section(summary, self.dir)
        self.assertIn("time.step = 0.02", html)
        self.assertIn("drift_8_time", html)
        self.assertEqual(summary[0]["points"][1]["history"]["column"], "body_cfy")
        self.assertIn("<img src='unsteady_drift.png'", html)
        self.assertGreater((self.dir / "unsteady_drift.png").stat().st_size, 1000)
        ctx = self.context()
        (ctx.run_dir("drift_8_time") / "steps.csv").unlink()
        self.assertIn("no steps.csv", continuation_summary(ctx)[0]["points"][1]["error"])

    def test_a_missing_continuation_is_an_error_not_the_steady_value(self):
        ctx = self.context()
        (ctx.run_dir("drift_8_time") / "steps.csv").unlink()
        with self.assertRaises(HarnessError) as cm:
            extract(ctx, {"kind": "sweep_coefficient", "sweep": "drift", "component": "Y", "groups": ["body"]})
        self.assertIn("'drift_8_time' has no steps.csv", str(cm.exception))
        ctx = self.context()
        data = json.loads((ctx.run_dir("drift_4") / "run.json").read_text())
        del data["force_span"]
        (ctx.run_dir("drift_4") / "run.json").write_text(json.dumps(data))
        with self.assertRaises(HarnessError) as cm:
            extract(ctx, {"kind": "sweep_coefficient", "sweep": "drift", "component": "Y", "groups": ["body"]})
        self.assertIn("has no force_span", str(cm.exception))


if __name__ == "__main__":
    unittest.main()
