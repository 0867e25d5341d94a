"""A communicator that counts what passes through another one (mpi/comm_volume.py, docs/performance.md
"Scaling"). Off by default: nothing in pice builds one; a script wraps ``world()`` in it and hands it
to ``Simulation(job, comm=...)``, so that the step calls exactly the functions it always calls.

Each call is recorded under (kind, caller): the kind of collective (allreduce, reduce, bcast,
exchange, wait, alltoall, gather, scatter, barrier) and the qualified name of the pice function that
issued it (``Halo.update``, ``Halo.needs_rebuild``, ``Simulation.check_health``, ...). Per record:
the calls, the point-to-point messages this rank sends (the exchange and the alltoalls: one per
non-empty destination; a collective's own tree messages are not counted, see ``rounds``), the
payload bytes this rank contributes [B] (for pickled objects the size of their pickle, as mpi4py
sends them), and the wall seconds spent inside the call [s] (which include waiting for the slowest
rank). Counting reads a clock and pickles objects a second time: it slows the run, never its numbers.
"""

from __future__ import annotations

import math
import pickle
import sys
from time import perf_counter

import numpy as np

#: the fields of one record, in order
FIELDS = ("calls", "messages", "bytes", "seconds")


def payload_bytes(obj) -> int:
    """Bytes [B] an object occupies on the wire: a numpy array's buffer, else its pickle (mpi4py's
    lowercase collectives pickle with the highest protocol)."""
    if obj is None:
        return 0
    if isinstance(obj, np.ndarray):
        return int(obj.nbytes)
    return len(pickle.dumps(obj, protocol=pickle.HIGHEST_PROTOCOL))


def rounds(size: int) -> int:
    """Rounds [-] of a tree or recursive-doubling collective on ``size`` ranks: ceil(log2 size)."""
    return int(math.ceil(math.log2(size))) if size > 1 else 0


class CountingComm:
    """Wraps a communicator (parallel.comm.MPIComm or SerialComm) and counts every call through it."""

    def __init__(self, inner):
        self.inner = inner
        self.rank = inner.rank
        self.size = inner.size
        self.records: dict[tuple[str, str], list[float]] = {}

    @property
    def blocked(self) -> float:
        """[s] waited inside the wrapped communicator (parallel/comm.py)."""
        return self.inner.blocked

    def reset(self) -> None:
        """Forget every record (after set-up and warm-up, before the counted window)."""
        self.records = {}

    def _call(self, kind: str, messages: int, nbytes: int, fn, *args):
        code = sys._getframe(2).f_code  # the pice function that called the collective
        caller = getattr(code, "co_qualname", code.co_name)
        t0 = perf_counter()
        out = fn(*args)
        rec = self.records.setdefault((kind, caller), [0, 0, 0, 0.0])
        rec[0] += 1
        rec[1] += messages
        rec[2] += nbytes
        rec[3] += perf_counter() - t0
        return out

    # -- reductions and broadcasts ---------------------------------------------------------------
    def sum(self, value):
        return self._call("allreduce", 0, payload_bytes(value), self.inner.sum, value)

    def max(self, value):
        return self._call("allreduce", 0, payload_bytes(value), self.inner.max, value)

    def min(self, value):
        return self._call("allreduce", 0, payload_bytes(value), self.inner.min, value)

    def reduce_sum(self, array):
        return self._call("reduce", 0, payload_bytes(np.asarray(array, dtype=np.float64)),
                          self.inner.reduce_sum, array)

    def bcast(self, obj):
        nbytes = payload_bytes(obj) if self.rank == 0 else 0
        return self._call("bcast", 0, nbytes, self.inner.bcast, obj)

    def bcast_array(self, array):
        """The array's bytes on every rank (each holds the shape; rank 0's values arrive)."""
        return self._call("bcast", 0, payload_bytes(np.asarray(array, dtype=np.float64)),
                          self.inner.bcast_array, array)

    def start_bcast_array(self, array):
        """The non-blocking broadcast, posted (kind "bcast"); its wait is ``finish_bcast_array``."""
        return self._call("bcast", 0, payload_bytes(np.asarray(array, dtype=np.float64)),
                          self.inner.start_bcast_array, array)

    def finish_bcast_array(self, pending):
        """The wait for a posted broadcast (kind "wait": its time is the waiting)."""
        return self._call("wait", 0, 0, self.inner.finish_bcast_array, pending)

    def gather(self, obj):
        return self._call("gather", 0, payload_bytes(obj), self.inner.gather, obj)

    def scatter(self, objs):
        nbytes = sum(payload_bytes(o) for o in objs) if self.rank == 0 and objs is not None else 0
        return self._call("scatter", 0, nbytes, self.inner.scatter, objs)

    def barrier(self):
        return self._call("barrier", 0, 0, self.inner.barrier)

    # -- point to point: the ghost exchange and the migration -----------------------------------
    def exchange_doubles(self, sendbuf, sendcounts):
        """The ghost update: one message per rank with a non-empty block (an Alltoallv skips empty
        ones), 8 B a double; the Alltoall of the counts before it is recorded as kind "counts"."""
        counts = np.asarray(sendcounts)
        others = [r for r in range(self.size) if r != self.rank]
        nonempty = int(sum(1 for r in others if counts[r] > 0))
        self._note("counts", 0, 8 * self.size)
        return self._call("exchange", nonempty, 8 * int(sum(counts[r] for r in others)),
                          self.inner.exchange_doubles, sendbuf, sendcounts)

    def start_neighbour_exchange(self, sends, recvs):
        """The ghost update: one message per named rank, 8 B a double (posted, not waited for)."""
        return self._call("exchange", len(sends), sum(8 * int(np.asarray(a).size) for _, a in sends),
                          self.inner.start_neighbour_exchange, sends, recvs)

    def finish_neighbour_exchange(self, pending):
        """The wait for the ghost update's messages (kind "wait": its time is the waiting)."""
        return self._call("wait", 0, 0, self.inner.finish_neighbour_exchange, pending)

    def alltoall(self, objs):
        """Migration and ghost rebuild: mpi4py pickles one object per destination (None included)."""
        objs = list(objs)
        others = [r for r in range(self.size) if r != self.rank]
        return self._call("alltoall", len(others), sum(payload_bytes(objs[r]) for r in others),
                          self.inner.alltoall, objs)

    def _note(self, kind: str, messages: int, nbytes: int) -> None:
        """Record a call made inside another (no clock: its time is in the enclosing record)."""
        code = sys._getframe(2).f_code  # _note <- the wrapping method <- the pice function
        caller = getattr(code, "co_qualname", code.co_name)
        rec = self.records.setdefault((kind, caller), [0, 0, 0, 0.0])
        rec[0] += 1
        rec[2] += nbytes

    def h5py_comm(self):
        return self.inner.h5py_comm()

    # -- the figures ------------------------------------------------------------------------------
    def table(self) -> list[dict]:
        """This rank's records as rows {"kind", "caller", "calls", "messages", "bytes", "seconds"},
        sorted by kind then caller."""
        return [{"kind": k, "caller": c, **dict(zip(FIELDS, v))} for (k, c), v in sorted(self.records.items())]
