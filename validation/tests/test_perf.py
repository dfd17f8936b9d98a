"""Benchmark history: an artificial 30 % slowdown is flagged, noise-level changes and
other machines' runs are not, and the performance page shows the flag."""
import json
import shutil
import tempfile
import unittest
from pathlib import Path

import support  # noqa: F401

from harness import perf
from harness.report import build_report


def gbench(times_ms):
    return {"benchmarks": [{"name": f"{n}_median", "run_name": n, "aggregate_name": "median", "real_time": t,
                            "time_unit": "ms"} for n, t in times_ms.items()]}


class History(unittest.TestCase):
    def setUp(self):
        self.dir = Path(tempfile.mkdtemp())

    def tearDown(self):
        shutil.rmtree(self.dir, ignore_errors=True)

    def fill(self, machine="m1"):
        base = [10.0, 10.4, 9.8, 10.1, 10.2]  # about 2 % noise
        for i, t in enumerate(base):
            perf.append(self.dir, gbench({"BM_Sweep": t, "BM_Flux": 2.0}), machine, "g++", f"sha{i}", when=f"2026010{i}")

    def test_thirty_percent_slowdown_is_flagged(self):
        self.fill()
        perf.append(self.dir, gbench({"BM_Sweep": 13.0, "BM_Flux": 2.02}), "m1", "g++", "slow", when="20260109")
        flags = perf.regressions(perf.load(self.dir))
        now, ref, ratio, verdict = flags["BM_Sweep"]
        self.assertEqual(verdict, "REGRESSION")
        self.assertAlmostEqual(ref * 1e-6, 10.1)
        self.assertAlmostEqual(ratio, 13.0 / 10.1)
        self.assertEqual(flags["BM_Flux"][3], "ok")

    def test_noise_is_not_flagged_and_other_machines_do_not_count(self):
        self.fill()
        perf.append(self.dir, gbench({"BM_Sweep": 30.0}), "other", "g++", "x", when="20260108")
        perf.append(self.dir, gbench({"BM_Sweep": 10.9}), "m1", "g++", "ok", when="20260109")
        self.assertEqual(perf.regressions(perf.load(self.dir))["BM_Sweep"][3], "ok")

    def test_a_slowdown_inside_the_benchmarks_own_noise_is_marked_noisy(self):
        self.fill()
        data = gbench({"BM_Sweep": 13.0})
        data["benchmarks"].append({"name": "BM_Sweep_cv", "run_name": "BM_Sweep", "aggregate_name": "cv",
                                   "real_time": 0.12, "time_unit": "ms"})
        perf.append(self.dir, data, "m1", "g++", "noisy", when="20260109")
        self.assertEqual(perf.regressions(perf.load(self.dir))["BM_Sweep"][3], "noisy")

    def test_performance_page_shows_the_regression(self):
        self.fill()
        perf.append(self.dir, gbench({"BM_Sweep": 13.0, "BM_Flux": 2.0}), "m1", "g++", "slow", when="20260109")
        reports = self.dir / "reports"
        (reports / "r").mkdir(parents=True)
        build_report(reports / "r", reports, self.dir)
        page = (reports / "r" / "perf.html").read_text()
        self.assertIn("BM_Sweep", page)
        self.assertIn("REGRESSION", page)
        self.assertTrue((reports / "r" / "bench_history.png").exists())

    def test_medians_from_google_benchmark_json(self):
        data = {"benchmarks": [{"name": "BM_A_mean", "run_name": "BM_A", "aggregate_name": "mean", "real_time": 5.0,
                                "time_unit": "us"},
                               {"name": "BM_A_median", "run_name": "BM_A", "aggregate_name": "median",
                                "real_time": 4.0, "time_unit": "us"}]}
        self.assertEqual(perf.medians(data), {"BM_A": 4000.0})


if __name__ == "__main__":
    unittest.main()
