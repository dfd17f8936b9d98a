"""Body extractors on hand-made surfaces and loads: taps of a linear Cp field are exact,
the wind axes follow the angle of attack, the Munk moment follows Lamb's table."""
import json
import math
import tempfile
import unittest
from pathlib import Path

import support  # noqa: F401
import numpy as np

from harness.compare import compare
from harness.extract import EXTRACT
from harness.reference import ReferenceFile
from harness.references import DERIVED, resolve_reference

REFERENCE_ROOT = support.ROOT / "reference_data"
TAPS = "spheroid/prolate_spheroid_6to1_potential_flow_cp.csv"


class Ctx:
    reference_root = REFERENCE_ROOT

    def __init__(self, directory, alpha=0.0):
        self.directory, self.alpha = Path(directory), alpha

    def run_dir(self, run_id):
        return self.directory / run_id

    def resolve(self, run_id, value):
        return self.alpha if isinstance(value, str) and value.startswith("input:") else value


def write_surface(path, cp_of, slant=0.0):
    """Faces of a 6:1 spheroid of length 1 on a fine (x, phi) lattice, Cp = cp_of(x, phi);
    `slant`: each station's faces shifted in x by slant cos(phi), as on narwhal's grids,
    whose meridians start at the pole squares' edges."""
    rows = ["# hand-made surface", "x,y,z,nx,ny,nz,area,cp,cf_x,cf_y,cf_z,cf_signed,y_plus"]
    for x in np.linspace(0.002, 0.998, 400):
        r = math.sqrt(max(0.0, 1.0 - (2 * x - 1) ** 2)) / 12.0
        for p in np.radians(np.arange(1.25, 360.0, 2.5)):
            y, z = -r * math.sin(p), r * math.cos(p)  # phi from +z (windward)
            xf = x + slant * math.cos(p)
            rows.append(f"{xf},{y},{z},0,0,0,1,{cp_of(xf, math.degrees(min(p, 2 * math.pi - p)))},0,0,0,0,0")
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("\n".join(rows) + "\n")


class SurfaceTaps(unittest.TestCase):
    def test_a_field_linear_in_x_and_arc_is_reproduced_at_every_tap(self):
        with tempfile.TemporaryDirectory() as d:
            write_surface(Path(d) / "run" / "surface_body.csv", lambda x, phi: 0.3 - 0.5 * x + 0.001 * phi)
            fn = EXTRACT["surface_taps"][0]
            curve = fn(Ctx(d), {"taps": {"file": TAPS, "where": {"alpha_deg": 10.0}}, "exclude_pole_stations": 2}, "run")
            ref = ReferenceFile(REFERENCE_ROOT, TAPS)
            rows = ref.rows_where({"alpha_deg": 10.0})
            x, phi = ref.column("x_over_L", rows), ref.column("phi_deg", rows)
            kept = curve.x.astype(int)
            self.assertEqual(len(set(x[kept])), len(set(x)) - 4)  # two stations off each end
            # linear in the arc r phi, not in phi: compare where r is nearly constant over the fit
            expected = 0.3 - 0.5 * x[kept] + 0.001 * phi[kept]
            self.assertLess(np.max(np.abs(curve.y - expected)), 2e-3)

    def test_row_numbered_reference_lines_up_with_the_taps(self):
        ref, _ = resolve_reference(None, {"file": TAPS, "where": {"alpha_deg": 0.0}, "x": "#row", "y": "Cp"},
                                   REFERENCE_ROOT)
        self.assertEqual(ref.x[0], 0.0)
        self.assertEqual(ref.x[-1], ref.x.size - 1)
        with tempfile.TemporaryDirectory() as d:
            cp = ReferenceFile(REFERENCE_ROOT, TAPS)
            write_surface(Path(d) / "run" / "surface_body.csv", lambda x, phi: 0.0)
            curve = EXTRACT["surface_taps"][0](Ctx(d), {"taps": {"file": TAPS, "where": {"alpha_deg": 0.0}}}, "run")
            result = compare("profile_max", curve, ref, 0.02, {"relative": False})
            rows = cp.rows_where({"alpha_deg": 0.0})
            worst = float(np.max(np.abs(cp.column("Cp", rows)[curve.x.astype(int)])))
            self.assertAlmostEqual(result["delta"], worst)  # zero Cp misses the exact one by all of it
            self.assertFalse(result["pass"])


class BodyLoads(unittest.TestCase):
    def write_run(self, d, body_axes):
        (Path(d) / "run").mkdir()
        (Path(d) / "run" / "run.json").write_text(json.dumps({"forces": {"body": {"body_axes": body_axes}}}))

    def test_drag_and_lift_rotate_with_the_angle_of_attack(self):
        a = math.radians(10.0)
        # a pure drag D and lift L (up) at alpha, in body axes (x forward, z down)
        d_, l_ = 0.3, 0.7
        body = {"X": -d_ * math.cos(a) + l_ * math.sin(a), "Y": 0.0, "Z": -d_ * math.sin(a) - l_ * math.cos(a),
                "K": 0.0, "M": 0.1, "N": 0.0}
        with tempfile.TemporaryDirectory() as d:
            self.write_run(d, body)
            fn = EXTRACT["body_loads"][0]
            self.assertAlmostEqual(fn(Ctx(d, 10.0), {"quantity": "drag"}, "run"), d_)
            self.assertAlmostEqual(fn(Ctx(d, 10.0), {"quantity": "lift"}, "run"), l_)
            self.assertAlmostEqual(fn(Ctx(d, 10.0), {"quantity": "M"}, "run"), 0.1)
            self.assertAlmostEqual(fn(Ctx(d, 10.0), {"quantity": "Z", "absolute": True}, "run"), abs(body["Z"]))


class MunkMoment(unittest.TestCase):
    def test_lamb_row_of_the_aspect_ratio(self):
        ref = ReferenceFile(REFERENCE_ROOT, "spheroid/spheroid_added_mass_lamb.csv")
        value = DERIVED["munk_moment"](ref, {"ratio": 6.0, "length": 1.0, "alpha_deg": 10.0, "area_ref": 2.0,
                                             "length_ref": 1.0})
        volume = math.pi / 216.0
        k = 0.917123420393 - 0.045182893471
        self.assertAlmostEqual(value, k * volume * math.sin(math.radians(10)) * math.cos(math.radians(10)), places=12)


if __name__ == "__main__":
    unittest.main()


AFF1 = "suboff/suboff_aff1_fragments_liu_huang1998.csv"


class AxialProfileAndNewtons(unittest.TestCase):
    def test_azimuthal_means_are_interpolated_to_the_stations_and_a_pole_tap_is_left_out(self):
        with tempfile.TemporaryDirectory() as d:
            # Cp = x + 0.01 cos(phi): its azimuthal mean is x exactly on the lattice.
            write_surface(Path(d) / "run" / "surface_body.csv", lambda x, phi: x + 0.01 * math.cos(math.radians(phi)))
            fn = EXTRACT["axial_profile"][0]
            stations = {"file": AFF1, "where": {"quantity": "Cp upper meridian"}, "x": "x_over_L"}
            curve = fn(Ctx(d), {"y": "cp", "stations": stations}, "run")
            ref = ReferenceFile(REFERENCE_ROOT, AFF1)
            x = ref.column("x_over_L", ref.rows_where({"quantity": "Cp upper meridian"}))
            self.assertEqual(curve.x.tolist(), x[1:].tolist())  # the tap at the nose (x = 0) is left out
            self.assertIn("1 station(s)", curve.label)
            self.assertLess(np.max(np.abs(curve.y - curve.x)), 1e-12)

    def test_the_mean_around_follows_the_meridians_where_a_station_is_not_a_ring(self):
        # Cp = x + 0.3 cos(phi) (a flow at incidence) on faces whose x varies around each
        # station: grouping faces by x would see no ring at all; along the meridians the
        # mean around is x, and the cos(phi) part averages out.
        with tempfile.TemporaryDirectory() as d:
            write_surface(Path(d) / "run" / "surface_body.csv",
                          lambda x, phi: x + 0.3 * math.cos(math.radians(phi)), slant=0.004)
            fn = EXTRACT["axial_profile"][0]
            stations = {"file": AFF1, "where": {"quantity": "Cp upper meridian"}, "x": "x_over_L"}
            curve = fn(Ctx(d), {"y": "cp", "stations": stations}, "run")
            self.assertGreater(curve.x.size, 3)
            self.assertLess(np.max(np.abs(curve.y - curve.x)), 1e-12)

    def test_a_coefficient_in_newtons_and_the_parts_of_a_force(self):
        with tempfile.TemporaryDirectory() as d:
            run = Path(d) / "run"
            run.mkdir()
            (run / "history.csv").write_text("iteration,body_cfx\n1,0.5\n2,0.002\n")
            part = {"cfx": 0.0015, "cfy": 0, "cfz": 0, "cmx": 0, "cmy": 0, "cmz": 0}
            (run / "run.json").write_text(json.dumps({"forces": {"body": {
                "cfx": 0.002, "pressure": part, "friction": dict(part, cfx=0.0005)}}}))
            newtons = EXTRACT["dimensional"][0]
            spec = {"of": {"kind": "history_last", "column": "body_cfx"}, "density": 1000.0, "speed": 3.0, "area": 2.0}
            self.assertAlmostEqual(newtons(Ctx(d), spec, "run"), 0.002 * 0.5 * 1000.0 * 9.0 * 2.0, places=12)
            (run / "history.csv").write_text("iteration,body_cfx,sail_cfx\n1,0.5,0.1\n2,0.002,0.0004\n")
            last = EXTRACT["history_last"][0]
            self.assertAlmostEqual(last(Ctx(d), {"columns": ["body_cfx", "sail_cfx"]}, "run"), 0.0024, places=15)
            self.assertEqual(last(Ctx(d), {"column": "sail_cfx"}, "run"), 0.0004)
            from harness.errors import HarnessError
            for bad in ({}, {"column": "body_cfx", "columns": ["sail_cfx"]}, {"columns": []}, {"columns": ["fin_cfx"]}):
                with self.assertRaises(HarnessError):
                    last(Ctx(d), bad, "run")
            parts = EXTRACT["force_part"][0]
            self.assertEqual(parts(Ctx(d), {"part": "friction"}, "run"), 0.0005)
            self.assertEqual(parts(Ctx(d), {"part": "pressure", "component": "cfx"}, "run"), 0.0015)
            from harness.errors import HarnessError
            with self.assertRaises(HarnessError):
                parts(Ctx(d), {"part": "viscous"}, "run")


    def test_the_largest_y_plus_over_several_walls(self):
        with tempfile.TemporaryDirectory() as d:
            write_surface(Path(d) / "run" / "surface_body.csv", lambda x, phi: x)
            (Path(d) / "run" / "surface_sail.csv").write_text(
                "x,y,z,nx,ny,nz,area,cp,cf_x,cf_y,cf_z,cf_signed,y_plus\n0.3,0,0.1,0,0,1,1,0,0,0,0,0,1.25\n"
                "0.4,0,0.1,0,0,1,1,0,0,0,0,0,0.5\n")
            largest = EXTRACT["surface_largest"][0]
            self.assertEqual(largest(Ctx(d), {"groups": ["body", "sail"], "column": "y_plus"}, "run"), 1.25)
            self.assertAlmostEqual(largest(Ctx(d), {"groups": ["body"], "column": "cp"}, "run"), 0.998, places=12)
            from harness.errors import HarnessError
            with self.assertRaisesRegex(HarnessError, "surface_rudder.csv"):
                largest(Ctx(d), {"groups": ["body", "rudder"], "column": "y_plus"}, "run")
            with self.assertRaisesRegex(HarnessError, "no column"):
                largest(Ctx(d), {"groups": ["sail"], "column": "yplus"}, "run")

    def test_an_increment_between_two_runs_each_at_its_own_speed(self):
        with tempfile.TemporaryDirectory() as d:
            for run, cfx in (("bare", 0.002), ("appended", 0.0025)):
                (Path(d) / run).mkdir()
                (Path(d) / run / "history.csv").write_text(f"iteration,body_cfx\n1,0.5\n2,{cfx}\n")
            def newtons(run, speed):
                return {"kind": "dimensional", "run": run, "of": {"kind": "history_last", "column": "body_cfx"},
                        "density": 1000.0, "speed": speed, "area": 2.0}
            diff = EXTRACT["difference"][0]
            got = diff(Ctx(d), {"a": newtons("appended", 3.1), "b": newtons("bare", 3.0)}, "")
            self.assertAlmostEqual(got, 0.0025 * 1000.0 * 3.1 ** 2 - 0.002 * 1000.0 * 9.0, places=12)
            from harness.errors import HarnessError
            with self.assertRaisesRegex(HarnessError, "minuend"):
                diff(Ctx(d), {"b": newtons("bare", 3.0)}, "")


def crossflow_table(separation_of_x, slant=0.003):
    """Faces on meridians every 5 degrees (from 2.5), stations slanted in x as on
    narwhal's grids; circumferential friction c (phi_s(x) - |phi|) toward leeward on
    each side, linear in phi and x, so that it vanishes at phi_s(x) exactly."""
    rows = []
    for x0 in np.linspace(0.05, 0.95, 19):
        for p in np.arange(-177.5, 180.0, 5.0):
            x = x0 + slant * math.cos(math.radians(p))
            r = 0.08
            a = math.radians(p)
            e_phi = np.array([0.0, -math.cos(a), -math.sin(a)])
            tau = 1e-3 * (separation_of_x(x) - abs(p)) * (1.0 if p > 0 else -1.0)
            cf = np.array([3e-3, 0.0, 0.0]) + tau * e_phi
            rows.append((x, -r * math.sin(a), r * math.cos(a), *cf))
    return {k: np.array([row[n] for row in rows]) for n, k in enumerate(("x", "y", "z", "cf_x", "cf_y", "cf_z"))}


class CrossflowSeparation(unittest.TestCase):
    def test_the_zero_of_the_circumferential_friction_is_found_on_both_sides(self):
        from harness import body
        t = body.with_crossflow_friction(crossflow_table(lambda x: 100.0 + 50.0 * x))
        for station in (0.3, 0.62, 0.8):
            self.assertAlmostEqual(body.separation_azimuth(t, station), 100.0 + 50.0 * station, places=9)

    def test_no_sign_change_is_nan_and_the_extractor_says_so(self):
        from harness import body
        from harness.errors import HarnessError
        t = crossflow_table(lambda x: 400.0)  # the cross flow never turns back
        self.assertTrue(math.isnan(body.separation_azimuth(body.with_crossflow_friction(t), 0.5)))
        with tempfile.TemporaryDirectory() as d:
            run = Path(d) / "run"
            run.mkdir()
            names = ("x", "y", "z", "cf_x", "cf_y", "cf_z")
            rows = "\n".join(",".join(repr(float(t[k][i])) for k in names) for i in range(t["x"].size))
            (run / "surface_body.csv").write_text("# hand-made\n" + ",".join(names) + "\n" + rows + "\n")
            fn = EXTRACT["separation_azimuth"][0]
            with self.assertRaises(HarnessError) as cm:
                fn(Ctx(d), {"station": 0.5}, "run")
            self.assertIn("changes sign nowhere", str(cm.exception))
            t2 = crossflow_table(lambda x: 120.0)
            rows = "\n".join(",".join(repr(float(t2[k][i])) for k in names) for i in range(t2["x"].size))
            (run / "surface_body.csv").write_text("# hand-made\n" + ",".join(names) + "\n" + rows + "\n")
            self.assertAlmostEqual(fn(Ctx(d), {"station": 0.5}, "run"), 120.0, places=9)

    def test_friction_lines_picture_draws_with_a_peer_without_wall_shear(self):
        from harness import report
        import matplotlib.pyplot as plt
        t = crossflow_table(lambda x: 100.0 + 50.0 * x)
        peer = {k: t[k] for k in ("x", "y", "z")}
        fig, ax = plt.subplots()
        report._picture_friction_lines([("a", t), ("peer", peer)], {}, ax)
        self.assertEqual(len(ax.get_legend().get_texts()), 1)
        plt.close(fig)
