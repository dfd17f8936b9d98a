"""The runner's handling of builds that cannot run a rung, and of a resumed report."""
import hashlib
import os
import shutil
import subprocess
import stat
import tempfile
import textwrap
import unittest
from pathlib import Path

import support  # noqa: F401

from harness import report
from harness.archive import pack, unpack
from harness.casefile import load_rung
from harness.errors import HarnessError
from test_captive_extractors import UNSTEADY_RUNG
from test_casefile import GOOD
from harness.runner import built_with_mpi, case_folder_digest, run_rung

# A rung whose one run asks for two MPI ranks.
RUNG = GOOD.replace('input = "in.toml"', 'input = "in.toml"\nranks = 2')


def fake_narwhal(directory, version_line):
    """An executable that answers --version like narwhal and fails any real run."""
    exe = Path(directory) / "narwhal"
    exe.write_text(f"#!/bin/sh\n[ \"$1\" = --version ] && echo '{version_line}' && exit 0\nexit 99\n")
    exe.chmod(exe.stat().st_mode | stat.S_IXUSR)
    return exe


class MpiRungWithoutMpi(unittest.TestCase):
    def setUp(self):
        self.dir = Path(tempfile.mkdtemp())
        rung_dir = self.dir / "parallel"
        rung_dir.mkdir()
        (rung_dir / "in.toml").write_text("")
        (rung_dir / "case.toml").write_text(textwrap.dedent(RUNG))
        self.rung = load_rung(rung_dir / "case.toml")

    def test_version_line_tells_the_build(self):
        self.assertTrue(built_with_mpi(str(fake_narwhal(self.dir, "narwhal 0.1.0 (abc, MPI)"))))
        other = self.dir / "other"
        other.mkdir()
        self.assertFalse(built_with_mpi(str(fake_narwhal(other, "narwhal 0.1.0 (abc, no MPI)"))))

    def test_rung_on_several_ranks_is_skipped_with_its_reason_not_crashed(self):
        exe = fake_narwhal(self.dir, "narwhal 0.1.0 (abc, no MPI)")
        res = run_rung(self.rung, "quick", exe, self.dir / "out", self.dir)
        self.assertEqual(res["status"], "skipped")
        self.assertIn("without MPI", res["message"])
        self.assertTrue((self.dir / "out" / "results.json").exists())


def counting_narwhal(directory, exit_code=0):
    """An executable that answers --version like a serial narwhal and, for `run ... --out D`,
    writes D/run.json, appends a line to runs.log beside itself and exits with exit_code."""
    exe = Path(directory) / "narwhal"
    exe.write_text(textwrap.dedent(f"""\
        #!/bin/sh
        [ "$1" = --version ] && echo 'narwhal 0.1.0 (abc, no MPI)' && exit 0
        while [ "$1" != --out ]; do shift; done
        mkdir -p "$2"
        echo '{{"status": "converged", "iterations": 7, "provenance": {{"compiler": "c", "flags": "f", "version": "v"}}}}' > "$2/run.json"
        echo run >> "{directory}/runs.log"
        exit {exit_code}
        """))
    exe.chmod(exe.stat().st_mode | stat.S_IXUSR)
    return exe


def interrupted_narwhal(directory):
    """An executable like counting_narwhal whose first run of a folder is killed after writing
    its restart.h5 (exit 137); run with --restart it finishes. Each run's arguments go to
    runs.log beside it, one line per run."""
    exe = Path(directory) / "narwhal"
    exe.write_text(textwrap.dedent(f"""\
        #!/bin/sh
        [ "$1" = --version ] && echo 'narwhal 0.1.0 (abc, no MPI)' && exit 0
        echo "$@" >> "{directory}/runs.log"
        out=""; restart=""
        while [ $# -gt 0 ]; do
          [ "$1" = --out ] && out="$2"
          [ "$1" = --restart ] && restart="$2"
          shift
        done
        mkdir -p "$out"
        if [ -z "$restart" ]; then echo state > "$out/restart.h5"; exit 137; fi
        echo '{{"status": "converged", "iterations": 9, "provenance": {{"compiler": "c", "flags": "f", "version": "v"}}}}' > "$out/run.json"
        exit 0
        """))
    exe.chmod(exe.stat().st_mode | stat.S_IXUSR)
    return exe


class ResumedReport(unittest.TestCase):
    """--resume reuses a finished run only when nothing it depends on has changed."""

    def setUp(self):
        self.root = Path(tempfile.mkdtemp())
        git = lambda *a: subprocess.run(["git", *a], cwd=self.root, check=True, capture_output=True)  # noqa: E731
        (self.root / "solver").mkdir()
        (self.root / "solver" / "kernel.cpp").write_text("int x;\n")
        (self.root / "CMakeLists.txt").write_text("project(p)\n")
        git("init", "-q")
        git("add", ".")
        git("-c", "user.name=t", "-c", "user.email=t@t", "commit", "-q", "-m", "sources")
        self.case = self.root / "cases" / "r"
        self.case.mkdir(parents=True)
        (self.case / "in.toml").write_text("a = 1\n")
        (self.case / "case.toml").write_text(textwrap.dedent(GOOD))
        self.rung = load_rung(self.case / "case.toml")

    def runs_made(self, exe, resume=True):
        before = self.count(exe)
        res = run_rung(self.rung, "quick", exe, self.root / "out", self.root, resume=resume)
        return self.count(exe) - before, res

    @staticmethod
    def count(exe):
        log = exe.parent / "runs.log"
        return len(log.read_text().splitlines()) if log.exists() else 0

    def test_a_finished_run_is_reused_and_said_so(self):
        exe = counting_narwhal(self.root)
        self.assertEqual(self.runs_made(exe)[0], 1)
        made, res = self.runs_made(exe)
        self.assertEqual(made, 0)
        self.assertTrue(res["runs"][0]["reused"])
        self.assertEqual(res["runs"][0]["iterations"], 7)
        self.assertEqual(self.runs_made(exe, resume=False)[0], 1, "without --resume every run is made")

    def test_a_run_that_went_back_from_a_divergence_says_how_often(self):
        exe = counting_narwhal(self.root)
        exe.write_text(exe.read_text().replace('"iterations": 7,', '"iterations": 7, "retreats": [{}, {}],'))
        res = self.runs_made(exe)[1]
        self.assertEqual(res["runs"][0]["retreats"], 2)
        self.assertIn("went back 2 times from a divergence", report._retreat_note(res["runs"][0]["retreats"]))
        self.assertEqual(report._retreat_note(0), "")

    def test_a_changed_case_folder_or_uncommitted_solver_sources_run_again(self):
        exe = counting_narwhal(self.root)
        self.runs_made(exe)
        (self.case / "grid.xyz").write_text("1 2 3\n")
        self.assertEqual(self.runs_made(exe)[0], 1, "a new file beside the input")
        (self.root / "solver" / "kernel.cpp").write_text("int y;\n")
        self.assertEqual(self.runs_made(exe)[0], 1, "uncommitted solver sources")
        self.assertEqual(self.runs_made(exe)[0], 1, "and never recorded while they stay so")

    def test_a_changed_base_in_another_folder_runs_again(self):
        common = self.root / "cases" / "common"
        common.mkdir()
        (common / "base.toml").write_text("b = 1\n")
        (self.case / "in.toml").write_text('base = "../common/base.toml"\na = 1\n')
        exe = counting_narwhal(self.root)
        self.runs_made(exe)
        self.assertEqual(self.runs_made(exe)[0], 0)
        (common / "base.toml").write_text("b = 2\n")
        self.assertEqual(self.runs_made(exe)[0], 1, "the base changed")
        (common / "table.csv").write_text("1\n")
        self.assertEqual(self.runs_made(exe)[0], 1, "a file beside the base")
        self.assertEqual(self.runs_made(exe)[0], 0)

    def test_an_input_without_bases_elsewhere_keeps_its_digest(self):
        (self.case / "grid.xyz").write_text("1 2 3\n")
        h = hashlib.sha256()
        for f in sorted(self.case.iterdir()):
            if f.name != "case.toml":
                h.update(f.name.encode())
                h.update(f.read_bytes())
        self.assertEqual(case_folder_digest(self.case / "in.toml"), h.hexdigest())

    def test_the_solver_tests_and_notes_are_not_what_it_is_built_from(self):
        exe = counting_narwhal(self.root)
        self.runs_made(exe)
        (self.root / "solver" / "tests").mkdir()
        (self.root / "solver" / "tests" / "new_test.cpp").write_text("TEST\n")
        (self.root / "solver" / "DESIGN.md").write_text("why\n")
        self.assertEqual(self.runs_made(exe)[0], 0)

    def test_an_interrupted_run_goes_on_from_its_restart(self):
        exe = interrupted_narwhal(self.root)
        made, res = self.runs_made(exe)
        self.assertEqual(res["runs"][0]["status"], "crashed (exit 137)")
        made, res = self.runs_made(exe)
        self.assertEqual(made, 1)
        last = (self.root / "runs.log").read_text().splitlines()[-1]
        self.assertIn("--restart " + str(self.root / "out" / "runs"), last)
        self.assertTrue(res["runs"][0]["continued"])
        self.assertEqual(res["runs"][0]["status"], "converged")
        self.assertEqual(self.runs_made(exe)[0], 0, "then reused as any finished run")
        # Without --resume an interrupted run starts afresh.
        (self.root / "out" / "runs" / "a" / "harness_run.json").unlink()
        (self.root / "out" / "runs" / "a" / "harness_run_started.json").write_text("{}")
        self.assertEqual(self.runs_made(exe, resume=False)[0], 1)
        self.assertNotIn("--restart", (self.root / "runs.log").read_text().splitlines()[-1])

    def test_an_archived_run_is_reused_in_another_checkout(self):
        exe = counting_narwhal(self.root)
        self.runs_made(exe)
        (self.root / "out" / "runs" / "a" / "solution.cgns").write_text("field")
        archive = Path(tempfile.mkdtemp())
        packed = pack(self.root, archive)
        self.assertEqual([p.relative_to(archive).as_posix() for p in packed], ["out/a.tar.xz"])
        self.assertEqual(pack(self.root, archive), [], "already archived under the same key")
        other = Path(tempfile.mkdtemp()) / "clone"
        shutil.copytree(self.root, other, ignore=shutil.ignore_patterns("out", "runs.log"))
        self.assertEqual(len(unpack(archive, other)), 1)
        restored = other / "out" / "runs" / "a"
        self.assertFalse((restored / "solution.cgns").exists(), "fields stay out of the archive")
        self.assertFalse((restored / "restart.h5").exists(), "no run starts from it")
        before = self.count(exe)  # the copied executable logs beside the original
        res = run_rung(load_rung(other / "cases" / "r" / "case.toml"), "quick", other / "narwhal", other / "out",
                       other, resume=True)
        self.assertEqual(self.count(exe) - before, 0, "the archived run was not made again")
        self.assertTrue(res["runs"][0]["reused"])
        (other / "cases" / "r" / "in.toml").write_text("a = 2\n")
        run_rung(load_rung(other / "cases" / "r" / "case.toml"), "quick", other / "narwhal", other / "out",
                 other, resume=True)
        self.assertEqual(self.count(exe) - before, 1, "but made again once its input changed")

    def test_the_archive_keeps_a_restart_another_run_starts_from(self):
        exe = counting_narwhal(self.root)
        self.runs_made(exe)
        (self.root / "out" / "runs" / "a" / "restart.h5").write_text("state")
        archive = Path(tempfile.mkdtemp())
        pack(self.root, archive, keeps_restart=lambda rung, run_dir: run_dir.name == "a")
        unpacked = unpack(archive, Path(tempfile.mkdtemp()))
        self.assertEqual((unpacked[0] / "restart.h5").read_text(), "state")
        (self.root / "out" / "runs" / "a" / "restart.h5").unlink()
        with self.assertRaisesRegex(HarnessError, "restart.h5 is missing"):
            pack(self.root, Path(tempfile.mkdtemp()), keeps_restart=lambda rung, run_dir: run_dir.name == "a")

    def test_a_diverged_run_is_not_reused(self):
        exe = counting_narwhal(self.root, exit_code=3)
        self.runs_made(exe)
        self.assertEqual(self.runs_made(exe)[0], 1)


if __name__ == "__main__":
    unittest.main()


def swinging_narwhal(directory):
    """An executable whose steady runs at 8 degrees drift end with their forces swinging
    (run.json force_span 0.05) and settle at other angles (1e-7); each run's arguments go to
    runs.log beside it, one line per run."""
    exe = Path(directory) / "narwhal"
    exe.write_text(textwrap.dedent(f"""\
        #!/bin/sh
        [ "$1" = --version ] && echo 'narwhal 0.1.0 (abc, no MPI)' && exit 0
        echo "$@" >> "{directory}/runs.log"
        span=1e-7
        case "$*" in *flow.drift_angle=8.0*) span=0.05;; esac
        while [ "$1" != --out ]; do shift; done
        mkdir -p "$2"
        echo state > "$2/restart.h5"
        echo '{{"status": "converged", "iterations": 7, "force_span": '$span', "provenance": {{"compiler": "c", "flags": "f", "version": "v"}}}}' > "$2/run.json"
        exit 0
        """))
    exe.chmod(exe.stat().st_mode | stat.S_IXUSR)
    return exe


# The captive tests' sweep with an unsteady rule, at two angles.
SWEPT = UNSTEADY_RUNG.replace("values = [-8, -4, 0, 4, 8]", "values = [0, 8]")


class UnsteadySweepPoints(unittest.TestCase):
    def setUp(self):
        self.dir = Path(tempfile.mkdtemp())
        (self.dir / "r").mkdir()
        (self.dir / "r" / "in.toml").write_text("")
        (self.dir / "r" / "case.toml").write_text(textwrap.dedent(SWEPT))

    def test_only_a_point_that_ended_unsteady_goes_on_in_physical_time_from_its_state(self):
        exe = swinging_narwhal(self.dir)
        res = run_rung(load_rung(self.dir / "r" / "case.toml"), "quick", exe, self.dir / "out", self.dir)
        commands = (self.dir / "runs.log").read_text().splitlines()
        self.assertEqual(len(commands), 3, commands)
        later = commands[2]
        self.assertIn("--out " + str(self.dir / "out" / "runs" / "drift_8_time"), later)
        self.assertIn("--restart " + str(self.dir / "out" / "runs" / "drift_8" / "restart.h5"), later)
        self.assertIn("--set time.steps=400", later)
        self.assertIn("--set flow.drift_angle=8.0", later)
        status = {r["id"]: r["status"] for r in res["runs"]}
        self.assertEqual(status["drift_0_time"], "not needed")
        self.assertEqual(status["drift_8_time"], "converged")
        self.assertIn("force span 1.0e-07", next(r for r in res["runs"] if r["id"] == "drift_0_time")["message"])
        self.assertFalse((self.dir / "out" / "runs" / "drift_0_time").exists())
        self.assertNotEqual(res["status"], "crashed")

    def test_the_archive_keeps_a_point_s_restart_only_when_its_continuation_is_needed(self):
        import sys
        sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tools"))
        from run_archive import restart_keeper
        exe = swinging_narwhal(self.dir)
        run_rung(load_rung(self.dir / "r" / "case.toml"), "quick", exe, self.dir / "out" / "r", self.dir)
        keeps = restart_keeper(self.dir)
        runs = self.dir / "out" / "r" / "runs"
        self.assertTrue(keeps("r", runs / "drift_8"))
        self.assertFalse(keeps("r", runs / "drift_0"))
        self.assertFalse(keeps("r", runs / "drift_8_time"))

    def test_a_steady_run_that_cannot_tell_its_steadiness_stops_the_rung(self):
        exe = counting_narwhal(self.dir)  # its run.json has no force_span
        res = run_rung(load_rung(self.dir / "r" / "case.toml"), "quick", exe, self.dir / "out", self.dir)
        self.assertEqual(res["status"], "crashed")
        self.assertIn("has no force_span", res["runs"][-1]["message"])


class CaseInputsWithABase(unittest.TestCase):
    def test_a_case_is_laid_over_its_base_as_narwhal_does(self):
        from harness.errors import HarnessError
        from harness.runner import case_input
        d = Path(tempfile.mkdtemp())
        (d / "base.toml").write_text('[flow]\nreynolds = 1e6\nbeta = 5.0\n[motion]\ngravity = [0.0, 0.0, 1.0]\n')
        (d / "run.toml").write_text('base = "base.toml"\n[flow]\nreynolds = 2e6\n[time]\nstep = 0.02\n')
        self.assertEqual(case_input(d / "run.toml"), {"flow": {"reynolds": 2e6, "beta": 5.0},
                                                      "motion": {"gravity": [0.0, 0.0, 1.0]},
                                                      "time": {"step": 0.02}})
        (d / "sub").mkdir()
        (d / "sub" / "third.toml").write_text('base = "../run.toml"\n[time]\nsteps = 3\n')
        self.assertEqual(case_input(d / "sub" / "third.toml")["time"], {"step": 0.02, "steps": 3})
        self.assertEqual(case_input(d / "sub" / "third.toml")["flow"]["beta"], 5.0)
        (d / "loop.toml").write_text('base = "loop.toml"\n')
        with self.assertRaisesRegex(HarnessError, "loops"):
            case_input(d / "loop.toml")
        (d / "lost.toml").write_text('base = "nowhere.toml"\n')
        with self.assertRaisesRegex(HarnessError, "cannot open"):
            case_input(d / "lost.toml")
        (d / "device.toml").write_text('base = "/dev/zero"\n')
        with self.assertRaisesRegex(HarnessError, "regular file"):
            case_input(d / "device.toml")


def simulating_narwhal(directory):
    """counting_narwhal's runs, and `simulate CASE --model M --out D`, which copies the model
    file M it was given to D/model_seen.toml; every command goes to runs.log."""
    exe = Path(directory) / "narwhal"
    exe.write_text(textwrap.dedent(f"""\
        #!/bin/sh
        [ "$1" = --version ] && echo 'narwhal 0.1.0 (abc, no MPI)' && exit 0
        echo "$@" >> "{directory}/runs.log"
        what="$1"; out=""; model=""
        while [ $# -gt 0 ]; do
          [ "$1" = --out ] && out="$2"
          [ "$1" = --model ] && model="$2"
          shift
        done
        mkdir -p "$out"
        if [ "$what" = simulate ]; then cp "$model" "$out/model_seen.toml"; exit 0; fi
        echo '{{"status": "converged", "iterations": 7, "provenance": {{"compiler": "c", "flags": "f", "version": "v"}}}}' > "$out/run.json"
        exit 0
        """))
    exe.chmod(exe.stat().st_mode | stat.S_IXUSR)
    return exe


# The model run is listed first: it must still run after the run its model is made of.
MODELLED = GOOD.replace('''[[run]]
id = "a"''', '''[[run]]
id = "flown"
input = "in.toml"
model = "m"
set = { "time.steps" = 5 }

[[model]]
id = "m"
coefficients = { Yv = { kind = "run_json", run = "a", field = "iterations" } }

[[run]]
id = "a"''')


class ModelledRuns(unittest.TestCase):
    def setUp(self):
        self.dir = Path(tempfile.mkdtemp())
        self.case = self.dir / "r"
        self.case.mkdir()
        (self.case / "in.toml").write_text("")

    def rung(self, text):
        (self.case / "case.toml").write_text(textwrap.dedent(text))
        return load_rung(self.case / "case.toml")

    def test_a_model_made_of_the_runs_results_is_flown_after_them(self):
        exe = simulating_narwhal(self.dir)
        res = run_rung(self.rung(MODELLED), "quick", exe, self.dir / "out", self.dir)
        commands = (self.dir / "runs.log").read_text().splitlines()
        self.assertTrue(commands[0].startswith("run "), commands)
        self.assertTrue(commands[1].startswith("simulate "), commands)
        self.assertIn("--set time.steps=5", commands[1])
        seen = (self.dir / "out" / "runs" / "flown" / "model_seen.toml").read_text()
        self.assertIn("[coefficients]\nYv = 7.0", seen)
        self.assertEqual([r["status"] for r in res["runs"]], ["converged", "completed"])

    def test_a_simulator_given_apart_flies_the_model(self):
        exe = simulating_narwhal(self.dir)
        (self.dir / "later").mkdir()
        later = simulating_narwhal(self.dir / "later")
        run_rung(self.rung(MODELLED), "quick", exe, self.dir / "out", self.dir, simulator=later)
        self.assertEqual([c.split()[0] for c in (self.dir / "runs.log").read_text().splitlines()], ["run"])
        self.assertEqual([c.split()[0] for c in (self.dir / "later" / "runs.log").read_text().splitlines()],
                         ["simulate"])

    def test_a_model_whose_value_cannot_be_extracted_stops_the_rung(self):
        exe = simulating_narwhal(self.dir)
        text = MODELLED.replace('field = "iterations" } }', 'field = "no_such_field" } }')
        res = run_rung(self.rung(text), "quick", exe, self.dir / "out", self.dir)
        self.assertEqual(res["status"], "crashed")
        self.assertIn("coefficients.Yv", res["runs"][1]["message"])

    def test_unknown_models_and_literal_values_are_refused(self):
        with self.assertRaisesRegex(HarnessError, "unknown \\[\\[model\\]\\] 'n'"):
            self.rung(MODELLED.replace('model = "m"', 'model = "n"'))
        with self.assertRaisesRegex(HarnessError, "model\\[0\\].coefficients.Yv.*extractor table"):
            self.rung(MODELLED.replace('Yv = { kind = "run_json", run = "a", field = "iterations" }', "Yv = -0.03"))
        with self.assertRaisesRegex(HarnessError, "takes no"):
            self.rung(MODELLED.replace('model = "m"', 'model = "m"\nranks = 2'))
