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
# A checkpoint every 5 iterations, so that kills land between checkpoints and inside
# restart writes and history rows alike; converged to a drop of 1e-15 (a few hundred
# iterations), so that the run ends converged from its last restart too.
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


def rows_written(path):
    try:
        return max(Path(path).read_text().count("\n") - 1, 0)
    except OSError:
        return 0


class KillAndResume(unittest.TestCase):
    def test_twenty_kills_then_resume_equal_the_uninterrupted_run(self):
        work = Path(tempfile.mkdtemp(prefix="narwhal_kill_"))
        subprocess.run(run(work / "whole"), capture_output=True)
        _, whole_rows = history(work / "whole" / "history.csv")
        # Twenty moments at random points of the run, by progress rather than by the clock
        # (so that a loaded machine moves them with the run): each process is killed a
        # random few milliseconds after its history reaches a random iteration, which
        # puts kills inside iterations, history rows and restart writes alike.
        rng = random.Random(14)
        targets = sorted(rng.sample(range(2, int(0.8 * len(whole_rows))), KILLS))
        out = work / "killed"
        after_checkpoint = kills = 0
        for k, target in enumerate(targets):
            restart = out / "restart.h5"
            resume = restart.exists()
            after_checkpoint += resume
            p = subprocess.Popen(run(out, restart if resume else None), stdout=subprocess.DEVNULL,
                                 stderr=subprocess.PIPE)
            while p.poll() is None and rows_written(out / "history.csv") < target:
                time.sleep(0.002)
            time.sleep(rng.uniform(0.0, 0.02))
            if p.poll() is not None:
                err = p.communicate()[1].decode()
                self.fail(f"run ended (exit {p.returncode}) before kill {k + 1} at iteration {target}: {err}")
            os.kill(p.pid, signal.SIGKILL)
            p.wait()
            p.stderr.close()
            kills += 1
            _, rows = history(out / "history.csv")
            its = [int(r.split(",")[0]) for r in rows if r.count(",") == rows[0].count(",")]
            self.assertEqual(its, sorted(set(its)), f"kill {k + 1}: iterations repeat or go back")
        print(f"\nkill_resume: {kills} kills at iterations {targets}, {after_checkpoint} resumed from a checkpoint")
        self.assertGreaterEqual(after_checkpoint, KILLS // 2, "too few kills landed after a checkpoint")
        final = subprocess.run(run(out, out / "restart.h5"), capture_output=True, text=True)
        self.assertIn(final.returncode, (0, 1), final.stderr)

        a, b = (json.loads((d / "run.json").read_text()) for d in (work / "whole", out))
        self.assertEqual(a["status"], b["status"])
        self.assertEqual(a["iterations"], b["iterations"])
        self.assertEqual(a["forces"], b["forces"])  # the same doubles, bit for bit
        self.assertEqual(a["final_residual"], b["final_residual"])
        self.assertEqual(a["equation_drops"], b["equation_drops"])
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
