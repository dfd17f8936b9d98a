"""The OpenFOAM peer run's pieces that need no OpenFOAM: the case it derives from a
Narwhal case, and the conversion of simpleFoam's forces to Narwhal's run.json layout."""
import json
import math
import re
import tempfile
import textwrap
import unittest
from pathlib import Path

import numpy as np

import support  # noqa: F401

from harness import openfoam
from harness.casefile import load_rung
from harness.errors import HarnessError
from harness.extract import Context, extract
from harness.references import resolve_reference
from test_casefile import GOOD

CASE = {"flow": {"reynolds": 4.0e6, "angle_of_attack": 10.0},
        "turbulence": {"model": "sst", "intensity": 0.01, "freestream_nut_ratio": 0.1},
        "output": {"reference_area": 2.0, "reference_length": 0.5, "moment_centre": [0.5, 0.0, 0.0]}}


def fake_foam_run(d, forces, moments, iterations=3):
    """What simpleFoam leaves behind: its log and the forces function object's files
    (total, pressure, viscous vectors per line), the same loads every iteration."""
    log = "".join(f"Time = {i}\n\nExecutionTime = {0.5 * i} s  ClockTime = {i} s\n\n" for i in range(1, iterations + 1))
    (d).mkdir(parents=True, exist_ok=True)
    (d / "log.simpleFoam").write_text("Version: 1912\n" + log)
    base = d / "postProcessing" / "forces" / "0"
    base.mkdir(parents=True)
    vec = lambda v: "({} {} {})".format(*v)
    for name, parts in (("force.dat", forces), ("moment.dat", moments)):
        lines = ["# Forces", "# Time total pressure viscous"]
        lines += [f"{i}\t" + "\t".join(vec(p) for p in parts) for i in range(1, iterations + 1)]
        (base / name).write_text("\n".join(lines) + "\n")
    poly = d / "constant" / "polyMesh"
    poly.mkdir(parents=True)
    (poly / "owner").write_text('note "nPoints:8  nCells:1  nFaces:6  nInternalFaces:0";\n')


def write_later_run(d, log):
    """A simpleFoam run started from the solution written at iteration 2 (a stage or a
    leg): iterations 3 and 4 in `log`, its execution time from zero again, a drag of 2,
    and the forces object's files in a new folder named by its start time."""
    (d / log).write_text("".join(f"Time = {i}\n\nExecutionTime = {0.25 * (i - 2)} s\n\n" for i in (3, 4)))
    folder = d / "postProcessing" / "forces" / "2"
    folder.mkdir(parents=True)
    for name, v in (("force.dat", "(2 0 0)\t(1 0 0)\t(1 0 0)"), ("moment.dat", "(0 0 0)\t(0 0 0)\t(0 0 0)")):
        (folder / name).write_text("# forces\n" + "".join(f"{i}\t{v}\n" for i in (3, 4)))


def write_cgns(path, zones, fields=True):
    """A solution or grid file in the layout narwhal writes (harness/solution.py reads it):
    zones as (name, ordinal, nodes (nk+1, nj+1, ni+1, 3), {CGNS name: (nk, nj, ni)})."""
    import h5py
    with h5py.File(path, "w") as f:
        base = f.create_group("Base")
        for name, ordinal, x, values in zones:
            z = base.create_group(name)
            z.attrs["label"] = np.bytes_(b"Zone_t")  # a fixed-length string, as the CGNS library writes
            z.create_group("Ordinal").create_dataset(" data", data=np.array([ordinal], dtype=np.int32))
            gc = z.create_group("GridCoordinates")
            for n, c in enumerate(("CoordinateX", "CoordinateY", "CoordinateZ")):
                gc.create_group(c).create_dataset(" data", data=x[..., n])
            if fields:
                fs = z.create_group("FlowSolution")
                for c, v in values.items():
                    fs.create_group(c).create_dataset(" data", data=v)


def two_blocks():
    """Two 2 x 1 x 1 blocks side by side in x, listed in the file against their order."""
    zones = []
    for name, ordinal, x0 in (("second", 2, 2.0), ("first", 1, 0.0)):
        x = np.stack(np.meshgrid(x0 + np.arange(3.0), np.arange(2.0), np.arange(2.0), indexing="ij"), axis=-1)
        x = np.ascontiguousarray(x.transpose(2, 1, 0, 3))  # (k, j, i, 3)
        cells = (1, 1, 2)
        values = {"Pressure": np.full(cells, 10.0 * ordinal) + [[[0.0, 1.0]]],
                  "VelocityX": np.full(cells, 1.0 * ordinal), "VelocityY": np.zeros(cells),
                  "VelocityZ": np.zeros(cells), "TurbulentEnergyKinetic": np.full(cells, 0.1 * ordinal),
                  "TurbulentDissipation": np.full(cells, 0.01 * ordinal)}
        zones.append((name, ordinal, x, values))
    return zones


class PeerCase(unittest.TestCase):
    def test_free_stream_follows_narwhal_grid_axes(self):
        s = openfoam.case_settings(CASE, "case.toml")
        a = math.radians(10.0)
        for got, want in zip(s["direction"], (math.cos(a), 0.0, -math.sin(a))):
            self.assertAlmostEqual(got, want, places=15)
        self.assertAlmostEqual(s["nu"], 2.5e-7)
        k = 1.5e-4
        self.assertAlmostEqual(s["k"], k)
        self.assertAlmostEqual(s["omega"], k / (0.1 * 2.5e-7))

    def test_other_models_are_refused_with_the_key(self):
        case = dict(CASE, turbulence={"model": "spalart_allmaras"})
        with self.assertRaises(HarnessError) as cm:
            openfoam.case_settings(case, "my.toml")
        self.assertIn("my.toml", str(cm.exception))
        self.assertIn("turbulence.model", str(cm.exception))

    def test_launder_sharma_solves_epsilon_from_the_same_eddy_viscosity_ratio(self):
        case = dict(CASE, turbulence=dict(CASE["turbulence"], model="launder-sharma"))
        s = openfoam.case_settings(case, "case.toml")
        self.assertAlmostEqual(0.09 * s["k"] ** 2 / s["epsilon"], 0.1 * 2.5e-7)
        d = Path(tempfile.mkdtemp())
        openfoam.write_case(d, s, 10)
        self.assertTrue((d / "0" / "epsilon").exists())
        # positive on the wall: OpenFOAM's f_mu divides by it there (a zero stopped simpleFoam)
        wall = re.search(r"body \{ type fixedValue; value uniform ([-+0-9.e]+); \}", (d / "0" / "epsilon").read_text())
        self.assertGreater(float(wall[1]), 0.0)
        self.assertFalse((d / "0" / "omega").exists())
        self.assertIn("LaunderSharmaKE", (d / "constant" / "turbulenceProperties").read_text())

    def test_a_sustained_free_stream_gains_its_ambient_destruction(self):
        for model, second in (("launder-sharma", "epsilon"), ("sst", "omega")):
            case = dict(CASE, turbulence=dict(CASE["turbulence"], model=model))
            d = Path(tempfile.mkdtemp())
            openfoam.write_case(d, openfoam.case_settings(case, "case.toml"), 10)
            self.assertFalse((d / "constant" / "fvOptions").exists())
            case["turbulence"]["sustain_freestream"] = True
            s = openfoam.case_settings(case, "case.toml")
            openfoam.write_case(d, s, 10)
            text = (d / "constant" / "fvOptions").read_text()
            self.assertIn("scalarSemiImplicitSource", text)
            rates = {m[0]: float(m[1]) for m in re.findall(r"^\s+(k|epsilon|omega) \(([-+0-9.e]+) 0\);$", text, re.M)}
            k = s["k"]
            if model == "sst":  # beta* k omega and beta_2 omega^2 (Menter 2003)
                want = {"k": 0.09 * k * s["omega"], "omega": 0.0828 * s["omega"] ** 2}
            else:  # epsilon-tilde, and C2 f2 eps^2 / k with Rt = k^2 / (nu eps) of the free stream
                e = s["epsilon"]
                f2 = 1.0 - 0.3 * math.exp(-min((k * k / (2.5e-7 * e)) ** 2, 50.0))
                want = {"k": e, "epsilon": 1.92 * f2 * e * e / k}
            self.assertEqual(set(rates), {"k", second})
            for name, value in want.items():
                self.assertAlmostEqual(rates[name] / value, 1.0, places=12)
            case["turbulence"]["sustain_freestream"] = False
            openfoam.write_case(d, openfoam.case_settings(case, "case.toml"), 10)
            self.assertFalse((d / "constant" / "fvOptions").exists())

    def test_forces_become_coefficients_in_body_axes(self):
        d = Path(tempfile.mkdtemp())
        s = openfoam.case_settings(CASE, "case.toml")
        # total = pressure + viscous; q A = 1/2 * 2 = 1, so coefficients equal forces
        fake_foam_run(d / "foam", [(3.0, 0.5, -2.0), (1.0, 0.5, -1.5), (2.0, 0.0, -0.5)],
                      [(0.1, 0.2, 0.3), (0.1, 0.2, 0.3), (0.0, 0.0, 0.0)])
        data = openfoam.write_results(d / "foam", d / "out", s, 12.5)
        body = json.loads((d / "out" / "run.json").read_text())["forces"]["body"]
        self.assertEqual(data["iterations"], 3)
        self.assertEqual(data["cells"], 1)
        self.assertAlmostEqual(body["cfx"], 3.0)
        self.assertAlmostEqual(body["pressure"]["cfz"], -1.5)
        self.assertAlmostEqual(body["friction"]["cfx"], 2.0)
        # moments on q A L_ref = 0.5; body axes x_B = -x, y_B = -y, z_B = z
        axes = body["body_axes"]
        self.assertAlmostEqual(axes["X"], -3.0)
        self.assertAlmostEqual(axes["Y"], -0.5)
        self.assertAlmostEqual(axes["Z"], -2.0)
        self.assertAlmostEqual(axes["K"], -0.2)
        self.assertAlmostEqual(axes["M"], -0.4)
        self.assertAlmostEqual(axes["N"], 0.6)
        history = (d / "out" / "history.csv").read_text().splitlines()
        self.assertEqual(history[1].split(",")[:3], ["iteration", "wall_s", "body_cfx"])
        self.assertEqual(len(history), 2 + 3)

    def test_wall_samples_become_pressure_and_friction_coefficients_on_the_body(self):
        d = Path(tempfile.mkdtemp())
        s = openfoam.case_settings(CASE, "case.toml")
        fake_foam_run(d / "foam", [(1.0, 0.0, 0.0)] * 3, [(0.0, 0.0, 0.0)] * 3)
        wall = d / "foam" / "postProcessing" / "wall" / "3"
        wall.mkdir(parents=True)
        (wall / "p_body.raw").write_text("#  x  y  z  p\n0.5 0 0.1 -0.25\n0.6 0.1 0 0.125\n")
        # the stress on the fluid: along -x where the flow drags the body along +x
        (wall / "wallShearStress_body.raw").write_text("#  x  y  z  tau\n0.5 0 0.1 -0.001 0 0\n0.6 0.1 0 -0.002 0 0.0005\n")
        openfoam.write_results(d / "foam", d / "out", s, 1.0)
        lines = (d / "out" / "surface_body.csv").read_text().splitlines()
        self.assertEqual(lines[1], "x,y,z,cp,cf_x,cf_y,cf_z")
        self.assertEqual([float(v) for v in lines[3].split(",")], [0.6, 0.1, 0.0, 0.25, 0.004, -0.0, -0.001])
        (wall / "wallShearStress_body.raw").write_text("#  x  y  z  tau\n0.5 0 0.1 -0.001 0 0\n")
        with self.assertRaises(HarnessError):
            openfoam.write_results(d / "foam", d / "out", s, 1.0)

    def test_a_peer_run_starts_from_narwhals_fields_in_the_exports_cell_order(self):
        d = Path(tempfile.mkdtemp())
        case = dict(CASE, turbulence=dict(CASE["turbulence"], model="launder-sharma"))
        s = openfoam.case_settings(case, "case.toml")
        fake_foam_run(d / "foam", [(1.0, 0.0, 0.0)] * 3, [(0.0, 0.0, 0.0)] * 3)
        (d / "foam" / "constant" / "polyMesh" / "owner").write_text('note "nCells:4";\n')
        openfoam.write_case(d / "foam", s, 10)
        zones = two_blocks()
        write_cgns(d / "solution.cgns", zones)
        write_cgns(d / "grid.cgns", zones, fields=False)
        openfoam.seed_from_narwhal(d / "foam", s, d / "solution.cgns", d / "grid.cgns")
        p = (d / "foam" / "0" / "p").read_text()
        self.assertIn("internalField nonuniform List<scalar> 4\n(\n10.0\n11.0\n20.0\n21.0\n);", p)
        self.assertIn("body { type zeroGradient; }", p)  # the boundary conditions stay
        self.assertIn("List<vector> 4\n(\n(1.0 0.0 0.0)\n(1.0 0.0 0.0)\n(2.0 0.0 0.0)",
                      (d / "foam" / "0" / "U").read_text())
        self.assertIn("List<scalar> 4\n(\n0.01\n0.01\n0.02\n0.02\n)", (d / "foam" / "0" / "epsilon").read_text())

    def test_a_solution_on_another_grid_is_refused_naming_the_block(self):
        d = Path(tempfile.mkdtemp())
        s = openfoam.case_settings(dict(CASE, turbulence=dict(CASE["turbulence"], model="launder-sharma")), "c")
        fake_foam_run(d / "foam", [(1.0, 0.0, 0.0)] * 3, [(0.0, 0.0, 0.0)] * 3)
        openfoam.write_case(d / "foam", s, 10)
        zones = two_blocks()
        write_cgns(d / "solution.cgns", zones)
        moved = [(n, o, x + (1e-6 if n == "first" else 0.0), v) for n, o, x, v in zones]
        write_cgns(d / "grid.cgns", moved, fields=False)
        with self.assertRaises(HarnessError) as cm:
            openfoam.seed_from_narwhal(d / "foam", s, d / "solution.cgns", d / "grid.cgns")
        self.assertIn("'first'", str(cm.exception))

    def test_no_force_output_is_an_error_naming_the_directory(self):
        d = Path(tempfile.mkdtemp())
        (d / "log.simpleFoam").write_text("Time = 1\nExecutionTime = 1 s\n")
        with self.assertRaises(HarnessError) as cm:
            openfoam.history(d, openfoam.case_settings(CASE, "c"))
        self.assertIn(str(d), str(cm.exception))


PEER_RUNG = GOOD.replace('input = "in.toml"\n', 'input = "in.toml"\n\n[[run]]\nid = "peer"\ncode = "openfoam"\n'
                         'input = "in.toml"\nmax_iterations = 10\n')


class StartStage(unittest.TestCase):
    """The Reynolds-number continuation (openfoam.StartStage): simpleFoam's first
    iterations at a lower Re, then the case's own, timed as one run."""

    def write(self, d, iterations=300):
        s = openfoam.case_settings(CASE, "case.toml")
        openfoam.write_case(d, s, iterations)
        return s

    def test_the_start_stage_runs_at_its_reynolds_number_then_the_case_continues(self):
        d = Path(tempfile.mkdtemp())
        s = self.write(d)
        seen = []

        def fake_foam(cmd, cwd, log, timeout=None):
            control = (cwd / "system" / "controlDict").read_text()
            nu = re.search(r"^nu (\S+);", (cwd / "constant" / "transportProperties").read_text(), re.M).group(1)
            seen.append((log.name, float(nu), re.search(r"endTime (\d+);", control).group(1),
                         re.search(r"startFrom (\w+);", control).group(1),
                         re.search(r"writeInterval (\d+);", control).group(1)))
        real = openfoam.foam
        openfoam.foam = fake_foam
        try:
            openfoam.run(d, 1, start=openfoam.StartStage(reynolds=1.0e4, iterations=100))
        finally:
            openfoam.foam = real
        self.assertEqual(seen, [("log.start", 1.0e-4, "100", "startTime", "100"),
                                ("log.simpleFoam", s["nu"], "300", "latestTime", "300")])

    def test_without_a_start_stage_the_case_runs_from_its_start(self):
        d = Path(tempfile.mkdtemp())
        self.write(d)
        seen = []
        real = openfoam.foam
        openfoam.foam = lambda cmd, cwd, log, timeout=None: seen.append(log.name)
        try:
            openfoam.run(d, 1)
        finally:
            openfoam.foam = real
        self.assertEqual(seen, ["log.simpleFoam"])
        self.assertIn("startFrom startTime;", (d / "system" / "controlDict").read_text())

    def test_the_history_runs_on_through_both_stages_with_the_start_stages_time(self):
        d = Path(tempfile.mkdtemp()) / "foam"
        s = openfoam.case_settings(CASE, "case.toml")
        fake_foam_run(d, [(1.0, 0.0, 0.0), (0.5, 0.0, 0.0), (0.5, 0.0, 0.0)],
                      [(0.0, 0.0, 0.0)] * 3, iterations=2)
        (d / "log.simpleFoam").rename(d / "log.start")
        write_later_run(d, "log.simpleFoam")  # the case's stage
        rows = openfoam.history(d, s)
        self.assertEqual([r[0] for r in rows], [1, 2, 3, 4])
        self.assertEqual([r[1] for r in rows], [0.5, 1.0, 1.25, 1.5])
        self.assertAlmostEqual(rows[-1][2]["total"]["cfx"], 2.0)


class Resume(unittest.TestCase):
    """A converging run longer than a sitting (openfoam.resume): written every few
    iterations, continued from its last write in a further log, read back as one history."""

    def test_the_write_interval_is_the_one_asked_for(self):
        d = Path(tempfile.mkdtemp())
        openfoam.write_case(d, openfoam.case_settings(CASE, "case.toml"), 300, write_interval=50)
        self.assertIn("writeInterval 50;", (d / "system" / "controlDict").read_text())

    def test_each_leg_continues_from_the_latest_write_in_its_own_log(self):
        d = Path(tempfile.mkdtemp())
        openfoam.write_case(d, openfoam.case_settings(CASE, "case.toml"), 300, write_interval=50)
        (d / "log.simpleFoam").write_text("Time = 1\n")
        seen = []

        def fake_foam(cmd, cwd, log, timeout=None):
            seen.append((log.name, re.search(r"startFrom (\w+);", (cwd / "system" / "controlDict").read_text()).group(1)))
            log.write_text("")
        real = openfoam.foam
        openfoam.foam = fake_foam
        try:
            openfoam.resume(d, 1)
            openfoam.resume(d, 1)
        finally:
            openfoam.foam = real
        self.assertEqual(seen, [("log.simpleFoam.2", "latestTime"), ("log.simpleFoam.3", "latestTime")])

    def test_a_run_whose_case_stage_never_started_is_not_continued(self):
        d = Path(tempfile.mkdtemp())
        openfoam.write_case(d, openfoam.case_settings(CASE, "case.toml"), 300)
        with self.assertRaises(HarnessError) as cm:
            openfoam.resume(d, 1)
        self.assertIn("log.simpleFoam", str(cm.exception))

    def test_the_history_takes_the_repeated_iterations_from_the_later_leg(self):
        d = Path(tempfile.mkdtemp()) / "foam"
        s = openfoam.case_settings(CASE, "case.toml")
        # leg 1 ran iterations 1-3 (drag 1) and was stopped; its last write was at 2
        fake_foam_run(d, [(1.0, 0.0, 0.0)] * 3, [(0.0, 0.0, 0.0)] * 3, iterations=3)
        # leg 2: iterations 3 and 4 again from the write at 2, drag 2
        write_later_run(d, "log.simpleFoam.2")
        rows = openfoam.history(d, s)
        self.assertEqual([r[0] for r in rows], [1, 2, 3, 4])
        q = 0.5 * s["area"]
        self.assertEqual([r[2]["total"]["cfx"] * q for r in rows], [1.0, 1.0, 2.0, 2.0])
        self.assertEqual([r[1] for r in rows], [0.5, 1.0, 1.75, 2.0])  # leg 1 ended at 1.5 s


class PeerRuns(unittest.TestCase):
    def rung(self, text):
        d = Path(tempfile.mkdtemp()) / "r"
        d.mkdir()
        (d / "in.toml").write_text("")
        (d / "case.toml").write_text(textwrap.dedent(text))
        return load_rung(d / "case.toml")

    def test_peer_run_is_read(self):
        runs = self.rung(PEER_RUNG).runs
        self.assertEqual([r.code for r in runs], ["narwhal", "openfoam"])

    def test_unknown_code_and_missing_iteration_count_are_named(self):
        with self.assertRaises(HarnessError) as cm:
            self.rung(PEER_RUNG.replace('"openfoam"', '"fluent"'))
        self.assertIn("run[1].code", str(cm.exception))
        with self.assertRaises(HarnessError) as cm:
            self.rung(PEER_RUNG.replace("max_iterations = 10\n", ""))
        self.assertIn("max_iterations", str(cm.exception))

    def test_a_peer_run_may_start_from_a_narwhal_run_only(self):
        rung = self.rung(PEER_RUNG.replace("max_iterations = 10\n", 'max_iterations = 10\nrestart_from = "a"\n'))
        self.assertEqual(rung.runs[1].restart_from, "a")
        swapped = PEER_RUNG.replace('input = "in.toml"\n\n[[run]]', 'input = "in.toml"\nrestart_from = "peer"\n\n[[run]]', 1)
        with self.assertRaises(HarnessError) as cm:
            self.rung(swapped)
        self.assertIn("a peer run", str(cm.exception))

    def test_reference_taken_from_the_peer_run(self):
        rung = self.rung(PEER_RUNG)
        dirs = {}
        for rid, iterations in (("a", 7), ("peer", 11)):
            dirs[rid] = Path(tempfile.mkdtemp())
            (dirs[rid] / "run.json").write_text(json.dumps({"iterations": iterations}))
        ctx = Context(rung, dirs, {"a": {}, "peer": {}})
        spec = {"extract": {"kind": "run_json", "run": "peer", "field": "iterations"}}
        value, desc = resolve_reference(ctx, spec, Path("."))
        self.assertEqual(value, 11.0)
        self.assertIn("openfoam", desc)
        self.assertEqual(extract(ctx, {"kind": "run_json", "run": "a", "field": "iterations"}), 7.0)

    def test_reference_from_a_run_takes_no_file_keys(self):
        with self.assertRaises(HarnessError) as cm:
            self.rung(GOOD.replace('reference = { file = "x.csv", column = "v" }',
                                   'reference = { column = "v", extract = { kind = "run_json", run = "a", field = "x" } }'))
        self.assertIn("check[0].reference", str(cm.exception))


if __name__ == "__main__":
    unittest.main()


class AzimuthalPicture(unittest.TestCase):
    def test_two_runs_at_two_stations_are_drawn(self):
        from harness import report
        rung_dir = Path(tempfile.mkdtemp())
        phi = np.linspace(-3.0, 3.0, 24)
        for run, shift in (("a", 0.0), ("peer", 0.01)):
            d = rung_dir / "runs" / run
            d.mkdir(parents=True)
            rows = [f"{x},{-0.1 * math.sin(p)},{0.1 * math.cos(p)},{math.cos(p) + shift}"
                    for x in (0.25, 0.5, 0.75) for p in phi]
            (d / "surface_body.csv").write_text("# test\nx,y,z,cp\n" + "\n".join(rows) + "\n")
        pic = {"kind": "azimuthal", "run": "a", "beside": "peer", "stations": [0.3, 0.8], "column": "cp",
               "group": "body", "title": "Cp around"}
        self.assertTrue(report._plot_picture(rung_dir, pic, rung_dir / "p.png"))
        self.assertGreater((rung_dir / "p.png").stat().st_size, 1000)

    def test_values_around_come_from_each_meridian_at_the_station(self):
        from harness import body
        phi = np.radians(np.arange(-172.5, 180.0, 15.0))
        rows = [(x + 0.01 * np.cos(p), -np.sin(p), np.cos(p), x * np.cos(p))  # stations slanted in x
                for x in (0.2, 0.4, 0.6, 0.8) for p in phi]
        rows.append((0.5, 0.0, 1.0, 99.0))  # a lone face (a pole square's): left out
        t = {k: np.array([r[n] for r in rows]) for n, k in enumerate(("x", "y", "z", "cp"))}
        a, v = body.around(t, "cp", 0.5)
        self.assertEqual(a.size, phi.size)
        np.testing.assert_allclose(v, (0.5 - 0.01 * np.cos(np.radians(a))) * np.cos(np.radians(a)), atol=1e-12)
