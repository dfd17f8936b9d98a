"""Rungs run side by side on a machine's cores (validation/run --jobs).

A rung with runs on several MPI ranks claims as many cores: its ranks busy-wait in their
halo exchanges, so another process on one of their cores slows the whole rung several-fold
(the 2-rank parallel-consistency rung: 72 s alone, 500 s beside one busy process). Rungs
start in the order given, each once its cores are free, so a rung waiting for two cores is
not overtaken by one-core rungs for ever.
"""
import threading


class CoreSlots:
    """`cores` cores handed out first come, first served, in the order of the tickets."""

    def __init__(self, cores):
        self.cores = max(1, cores)
        self._free = self.cores
        self._next = 0
        self._lock = threading.Condition()

    def acquire(self, ticket, n):
        """Blocks until every earlier ticket has its cores and n of them (at most all) are free."""
        n = min(max(1, n), self.cores)
        with self._lock:
            self._lock.wait_for(lambda: self._next == ticket and self._free >= n)
            self._free -= n
            self._next += 1
            self._lock.notify_all()
        return n

    def release(self, n):
        with self._lock:
            self._free += n
            self._lock.notify_all()


def start_order(rungs, cores_of):
    """Rungs needing the most cores first (then as given): they wait only for the start."""
    return sorted(rungs, key=lambda r: -cores_of(r))
