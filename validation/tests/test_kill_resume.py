"""kill -9 at 20 random moments, resuming each time from the run's own restart.h5:
the history must stay monotonic with no torn row, and the final answer must equal an
uninterrupted run's bit for bit (issue 14, bar 3)."""
import json
import os
import random
import signal
import subprocess
import tempfile
import time
import unittest
from pathlib import Path

import support

CASE = support.ROOT / "validation" / "cases" / "flat_plate_laminar" / "flat_plate.toml"
# A checkpoint every 5 iterations (about 0.1 s here), so that kills land between
# checkpoints, inside restart writes, history rows and the final outputs alike.
# 1200 iterations to a drop of 1e-15 that it does not reach: a run of several seconds.
SETS = ["--set", "output.restart_interval=5", "--set", "solver.residual_drop=1e-15"]
KILLS = 20


def run(out, restart=None, iterations=1200):
    cmd = [str(support.NARWHAL), "run", str(CASE), "--out", str(out), "--max-iterations", str(iterations)] + SETS
    if restart:
        cmd += ["--restart", str(restart)]
    return cmd


def history(path):
    lines = Path(path).read_text().split("\n")
    header, rows = lines[0], lines[1:]
    if rows and rows[-1] == "":
        rows = rows[:-1]
    return header, rows


def without_wall_time(row):
    f = row.split(",")
    return f[:1] + f[2:]


class KillAndResume(unittest.TestCase):
    def test_twenty_kills_then_resume_equal_the_uninterrupted_run(self):
        work = Path(tempfile.mkdtemp(prefix="narwhal_kill_"))
        t0 = time.monotonic()
        subprocess.run(run(work / "startup", iterations=0), capture_output=True)
        startup = time.monotonic() - t0
        t0 = time.monotonic()
        subprocess.run(run(work / "whole"), capture_output=True)
        iterating = time.monotonic() - t0 - startup
        # Kills spread so that the twenty of them land over the whole run: each process
        # lives its start-up plus a random few per cent of the iterating time.
        rng = random.Random(14)
        out = work / "killed"
        after_checkpoint = kills = 0
        for k in range(KILLS):
            restart = out / "restart.h5"
            resume = restart.exists()
            after_checkpoint += resume
            p = subprocess.Popen(run(out, restart if resume else None), stdout=subprocess.DEVNULL,
                                 stderr=subprocess.PIPE)
            time.sleep(startup + rng.uniform(0.0, 0.03 * iterating))
            if p.poll() is not None:
                err = p.communicate()[1].decode()
                self.assertIn(p.returncode, (0, 1), err)
                break  # finished before this kill
            os.kill(p.pid, signal.SIGKILL)
            p.wait()
            kills += 1
            p.stderr.close()
            if (out / "history.csv").exists():  # monotonic after every kill too, up to a torn last row
                _, rows = history(out / "history.csv")
                its = [int(r.split(",")[0]) for r in rows if r.count(",") == rows[0].count(",")]
                self.assertEqual(its, sorted(set(its)), f"kill {k + 1}: iterations repeat or go back")
        print(f"\nkill_resume: {kills} kills, {after_checkpoint} of them resumed from a checkpoint "
              f"(start-up {startup:.2f} s, iterating {iterating:.2f} s)")
        self.assertEqual(kills, KILLS, "the run finished before every kill landed")
        self.assertGreaterEqual(after_checkpoint, KILLS // 4,
                                f"too few kills landed after a checkpoint (start-up {startup:.2f} s, "
                                f"iterations {iterating:.2f} s)")
        final = subprocess.run(run(out, out / "restart.h5"), capture_output=True, text=True)
        self.assertIn(final.returncode, (0, 1), final.stderr)

        a, b = (json.loads((d / "run.json").read_text()) for d in (work / "whole", out))
        self.assertEqual(a["status"], b["status"])
        self.assertEqual(a["iterations"], b["iterations"])
        self.assertEqual(a["forces"], b["forces"])  # the same doubles, bit for bit
        self.assertEqual(a["final_residual"], b["final_residual"])
        ha, ra = history(work / "whole" / "history.csv")
        hb, rb = history(out / "history.csv")
        self.assertEqual(ha, hb)
        fields = ha.count(",") + 1
        for r in rb:
            self.assertEqual(r.count(",") + 1, fields, f"torn row {r!r}")
        self.assertEqual([int(r.split(",")[0]) for r in rb], list(range(1, len(ra) + 1)))
        self.assertEqual([without_wall_time(r) for r in ra], [without_wall_time(r) for r in rb])
        self.assertEqual((work / "whole" / "surface_plate.csv").read_text(), (out / "surface_plate.csv").read_text())
        self.assertEqual(sorted(p.name for p in out.glob("*.tmp")), [])


if __name__ == "__main__":
    unittest.main()
