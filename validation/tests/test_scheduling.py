"""validation/run's core slots: a multi-rank rung never shares its cores, one-core rungs
run side by side, and rungs start in ticket order."""
import threading
import time
import unittest

from support import ROOT

from harness.scheduling import CoreSlots, start_order


def run_jobs(cores, needs, seconds=0.05):
    """Runs one thread per job (ticket = index), each holding its cores for `seconds`;
    returns (start, end, cores) per job."""
    slots = CoreSlots(cores)
    spans = [None] * len(needs)

    def job(ticket, n):
        got = slots.acquire(ticket, n)
        start = time.monotonic()
        time.sleep(seconds)
        spans[ticket] = (start, time.monotonic(), got)
        slots.release(got)

    threads = [threading.Thread(target=job, args=(t, n)) for t, n in enumerate(needs)]
    for t in reversed(threads):  # started out of order: the tickets must still hold
        t.start()
    for t in threads:
        t.join(timeout=10)
    return spans


def overlap(a, b):
    return a[0] < b[1] and b[0] < a[1]


class CoreSlotsTest(unittest.TestCase):
    def test_a_two_core_rung_runs_alone_on_two_cores(self):
        spans = run_jobs(2, [2, 1, 1, 2, 1])
        for i, s in enumerate(spans):
            for j, t in enumerate(spans):
                if i != j and (s[2] == 2 or t[2] == 2):
                    self.assertFalse(overlap(s, t), f"job {i} ({s[2]} cores) overlaps job {j} ({t[2]} cores)")

    def test_one_core_rungs_run_side_by_side(self):
        spans = run_jobs(2, [1, 1])
        self.assertTrue(overlap(spans[0], spans[1]))

    def test_rungs_start_in_ticket_order(self):
        spans = run_jobs(2, [1, 2, 1, 1])
        starts = [s[0] for s in spans]
        self.assertEqual(starts, sorted(starts))

    def test_a_claim_beyond_the_machine_takes_all_its_cores(self):
        self.assertEqual(run_jobs(2, [3])[0][2], 2)

    def test_the_widest_rungs_start_first(self):
        self.assertEqual(start_order(["a", "bb", "c", "ddd"], len), ["ddd", "bb", "a", "c"])


class EveryTestModuleRuns(unittest.TestCase):
    def test_ctest_names_every_test_module(self):
        """A test module that validation/CMakeLists.txt does not name never runs in CI."""
        listed = (ROOT / "validation" / "CMakeLists.txt").read_text().split()
        modules = sorted(p.stem for p in (ROOT / "validation" / "tests").glob("test_*.py"))
        self.assertEqual([m for m in modules if m not in listed], [])


if __name__ == "__main__":
    unittest.main()
