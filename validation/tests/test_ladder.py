"""The harness end to end on real solver runs (needs the built narwhal):
a flipped reference value makes the ladder fail with that check's delta shown, and a
crashing rung does not stop the others."""
import shutil
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

from support import NARWHAL, ROOT

RUN = [sys.executable, str(ROOT / "validation" / "run")]


@unittest.skipUnless(NARWHAL.exists(), f"solver not built at {NARWHAL}")
class Ladder(unittest.TestCase):
    def setUp(self):
        self.tmp = Path(tempfile.mkdtemp())

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def run_ladder(self, *args):
        return subprocess.run([*RUN, "--tier", "quick", "--narwhal", str(NARWHAL), "--reports",
                               str(self.tmp / "reports"), "--run-id", "t", *args],
                              capture_output=True, text=True, timeout=600)

    def test_unchanged_reference_passes(self):
        p = self.run_ladder("--rung", "couette")
        self.assertEqual(p.returncode, 0, p.stdout + p.stderr)
        self.assertIn("PASSED   couette", p.stdout)

    def test_flipped_reference_value_fails_with_its_delta(self):
        scratch = self.tmp / "root"
        shutil.copytree(ROOT / "reference_data", scratch / "reference_data")
        f = scratch / "reference_data" / "square_duct" / "laminar_square_duct_exact.csv"
        text = f.read_text()
        flipped = text.replace("0.000,2.0962560182,", "0.000,2.3962560182,", 1)
        self.assertNotEqual(text, flipped)
        f.write_text(flipped)
        p = self.run_ladder("--rung", "square_duct_laminar", "--reference-root", str(scratch))
        self.assertNotEqual(p.returncode, 0, p.stdout)
        self.assertIn("FAILED   square_duct_laminar", p.stdout)
        self.assertIn("FAIL u_max / u_bulk (24 x 24): computed", p.stdout)
        self.assertIn("reference 2.396256", p.stdout)
        self.assertIn("delta -1.32", p.stdout)
        # The untouched check of the same rung still passes.
        self.assertNotIn("FAIL f Re_Dh", p.stdout)
        html = (self.tmp / "reports" / "t" / "index.html").read_text()
        self.assertIn("FAIL", html)

    def test_missing_reference_column_is_a_failure_not_a_pass(self):
        scratch = self.tmp / "root"
        shutil.copytree(ROOT / "reference_data", scratch / "reference_data")
        f = scratch / "reference_data" / "verification" / "scheme_expectations.csv"
        f.write_text(f.read_text().replace("observed_order,couette_error", "observed_order,couette_err"))
        p = self.run_ladder("--rung", "couette", "--reference-root", str(scratch))
        self.assertNotEqual(p.returncode, 0)
        self.assertIn("no column 'couette_error'", p.stdout)

    def test_a_crashing_rung_does_not_stop_the_others(self):
        cases = self.tmp / "cases"
        shutil.copytree(ROOT / "validation" / "cases" / "couette", cases / "couette")
        shutil.copytree(ROOT / "validation" / "cases" / "couette", cases / "broken")
        (cases / "broken" / "case.toml").write_text(
            (cases / "broken" / "case.toml").read_text().replace('"flow.viscous" = "thin-layer"',
                                                                 '"flow.viscous" = "thin-layer", "flow.reynolds" = -1.0'))
        p = self.run_ladder("--cases", str(cases))
        self.assertNotEqual(p.returncode, 0)
        self.assertIn("CRASHED  broken", p.stdout, p.stderr)
        self.assertIn("PASSED   couette", p.stdout)


    def test_a_rung_over_its_time_limit_is_reported_as_timeout(self):
        cases = self.tmp / "cases"
        shutil.copytree(ROOT / "validation" / "cases" / "couette", cases / "couette")
        shutil.copytree(ROOT / "validation" / "cases" / "flat_plate_laminar", cases / "slow")
        rung = cases / "slow" / "case.toml"
        rung.write_text(rung.read_text().replace("timeout_s = 1800", "timeout_s = 1.0"))
        p = self.run_ladder("--cases", str(cases))
        self.assertNotEqual(p.returncode, 0)
        self.assertIn("TIMEOUT  slow", p.stdout)
        self.assertIn("PASSED   couette", p.stdout)
        import json
        res = json.loads((self.tmp / "reports" / "t" / "slow" / "results.json").read_text())
        self.assertEqual(res["status"], "timeout")


if __name__ == "__main__":
    unittest.main()
