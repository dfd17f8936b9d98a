"""The runner's handling of builds that cannot run a rung."""
import os
import stat
import tempfile
import textwrap
import unittest
from pathlib import Path

import support  # noqa: F401

from harness.casefile import load_rung
from test_casefile import GOOD
from harness.runner import built_with_mpi, run_rung

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


if __name__ == "__main__":
    unittest.main()
