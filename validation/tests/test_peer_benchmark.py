"""benchmarks/peer/openfoam_body.py: a benchmark longer than one sitting continues where it
stopped, and never mixes its runs with another benchmark's (the runs themselves are faked)."""
import importlib.util
import json
import sys
import tempfile
import unittest
from pathlib import Path
from unittest import mock

from support import ROOT

spec = importlib.util.spec_from_file_location("openfoam_body", ROOT / "benchmarks" / "peer" / "openfoam_body.py")
bench = importlib.util.module_from_spec(spec)
spec.loader.exec_module(bench)

CASE = str(ROOT / "validation" / "cases" / "spheroid_turbulent" / "spheroid.toml")


class Resume(unittest.TestCase):
    def run_bench(self, out, runs, fail_openfoam_at=None):
        """main() with each run faked: the codes' histories steady from iteration 3 (narwhal)
        and 7 (simpleFoam); each timed run takes a second more than the last."""
        def narwhal(a, sets, d, max_iterations=None):
            runs.append(("narwhal", d.name))
            return float(len(runs))

        def openfoam(a, sets, s, d, iterations, write_interval=None):
            if d.name == "openfoam":  # the converging run: simpleFoam starts its log
                d.mkdir(parents=True, exist_ok=True)
                (d / "log.simpleFoam").write_text("")
            if fail_openfoam_at is not None and d.name == fail_openfoam_at:
                raise KeyboardInterrupt  # the sitting ends inside this run
            runs.append(("openfoam", d.name))
            return float(len(runs))

        def resume(d, ranks, timeout=None):
            runs.append(("resume", d.name))
            return 1.0
        history = lambda first: [(i, float(i), 2.0 if i < first else 1.0) for i in range(1, 11)]
        argv = ["openfoam_body.py", CASE, "--out", str(out), "--repeat", "2", "--narwhal", sys.executable]
        with mock.patch.object(bench, "run_narwhal", narwhal), mock.patch.object(bench, "run_openfoam", openfoam), \
                mock.patch.object(bench.openfoam, "resume", resume), \
                mock.patch.object(bench, "narwhal_history", lambda d: history(3)), \
                mock.patch.object(bench, "foam_history", lambda d, s: history(7)), \
                mock.patch.object(sys, "argv", argv), mock.patch("builtins.print"):
            bench.main()

    def test_an_interrupted_benchmark_continues_without_repeating_finished_runs(self):
        out = Path(tempfile.mkdtemp())
        first, second = [], []
        with self.assertRaises(KeyboardInterrupt):
            self.run_bench(out, first, fail_openfoam_at="openfoam_t1")
        self.run_bench(out, second)
        self.assertEqual(first, [("narwhal", "narwhal"), ("openfoam", "openfoam"), ("narwhal", "narwhal_t0"),
                                 ("openfoam", "openfoam_t0"), ("narwhal", "narwhal_t1")])
        self.assertEqual(second, [("openfoam", "openfoam_t1")])
        done = json.loads((out / "peer_body.json").read_text())
        self.assertEqual(done["narwhal"]["iterations_to_steady"], 3)
        self.assertEqual(done["openfoam"]["iterations_to_steady"], 7)
        self.assertEqual(done["narwhal"]["timed_s"], [3.0, 5.0])
        self.assertEqual(done["openfoam"]["timed_s"], [4.0, 1.0])
        self.assertAlmostEqual(done["speed_ratio"], 2.5 / 4.0)

    def test_a_converging_run_stopped_with_its_sitting_is_continued_not_restarted(self):
        out = Path(tempfile.mkdtemp())
        first, second = [], []
        with self.assertRaises(KeyboardInterrupt):
            self.run_bench(out, first, fail_openfoam_at="openfoam")
        self.run_bench(out, second)
        self.assertEqual(first, [("narwhal", "narwhal")])
        self.assertEqual(second[0], ("resume", "openfoam"))
        self.assertNotIn(("openfoam", "openfoam"), second)

    def test_results_of_another_benchmark_are_refused_naming_the_key(self):
        out = Path(tempfile.mkdtemp())
        (out / "peer_body.json").write_text(json.dumps({"case": "other.toml"}))
        with self.assertRaises(SystemExit) as e:
            self.run_bench(out, [])
        self.assertIn("case", str(e.exception))
        self.assertIn("other.toml", str(e.exception))


if __name__ == "__main__":
    unittest.main()
