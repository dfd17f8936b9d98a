"""The command line as a user meets it (issue 14): argument errors exit 2 with a message,
`check` refuses what a run would refuse, an unusable or busy --out is a clean error."""
import subprocess
import tempfile
import time
import unittest
from pathlib import Path

import support

PLATE = support.ROOT / "validation" / "cases" / "flat_plate_laminar" / "flat_plate.toml"


def narwhal(*args, **kw):
    return subprocess.run([str(support.NARWHAL), *map(str, args)], capture_output=True, text=True, timeout=120, **kw)


class Arguments(unittest.TestCase):
    def test_argument_errors_exit_2_with_a_message(self):
        for args in (["run"], ["run", PLATE, "--bogus"], ["run", PLATE, "--max-iterations", "-5"],
                     ["run", PLATE, "--max-iterations", "abc"], ["frobnicate"], []):
            r = narwhal(*args)
            self.assertEqual(r.returncode, 2, f"{args}: {r.stderr}")
            self.assertTrue(r.stderr.strip(), f"{args}: no message")

    def test_help_and_version_exit_0(self):
        self.assertEqual(narwhal("--help").returncode, 0)
        self.assertEqual(narwhal("--version").returncode, 0)


class Check(unittest.TestCase):
    def test_check_refuses_multigrid_levels_the_grid_cannot_coarsen_to(self):
        r = narwhal("check", PLATE, "--set", "solver.multigrid_levels=9")
        self.assertEqual(r.returncode, 2, r.stdout)
        self.assertIn("key 'solver.multigrid_levels'", r.stderr)
        self.assertEqual(narwhal("check", PLATE, "--set", "solver.multigrid_levels=3").returncode, 0)

    def test_out_of_range_set_is_refused_naming_file_and_key(self):
        r = narwhal("check", PLATE, "--set", "grid.cells_plate=4294967297")
        self.assertEqual(r.returncode, 2)
        self.assertIn("flat_plate.toml", r.stderr)
        self.assertIn("key 'grid.cells_plate'", r.stderr)


class OutputDirectory(unittest.TestCase):
    def test_out_that_is_a_file_or_empty_is_a_clean_error(self):
        d = Path(tempfile.mkdtemp())
        (d / "afile").write_text("x")
        for out in (d / "afile", "", d / "afile" / "sub"):
            r = narwhal("run", PLATE, "--out", out, "--max-iterations", "1")
            self.assertEqual(r.returncode, 2, f"--out {out!s}: {r.stderr}")
            self.assertIn("--out", r.stderr)
            self.assertNotIn("terminate called", r.stderr)

    def test_second_run_into_a_busy_directory_stops_at_once(self):
        d = Path(tempfile.mkdtemp()) / "out"
        first = subprocess.Popen([str(support.NARWHAL), "run", str(PLATE), "--out", str(d), "--max-iterations", "400"],
                                 stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            for _ in range(200):  # until the first run holds the lock
                if (d / ".narwhal.lock").exists() and (d / ".narwhal.lock").read_text():
                    break
                time.sleep(0.02)
            r = narwhal("run", PLATE, "--out", d, "--max-iterations", "1")
            self.assertEqual(r.returncode, 2, r.stderr)
            self.assertIn("another narwhal run", r.stderr)
        finally:
            first.kill()
            first.wait()


if __name__ == "__main__":
    unittest.main()
