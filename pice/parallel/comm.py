"""A small communicator interface: mpi4py's COMM_WORLD under a launcher, a serial stand-in otherwise."""

from __future__ import annotations

import functools
import os
from time import perf_counter

import numpy as np

GHOST_TAG = 17  # the tag of the ghost update's point-to-point messages

_LAUNCHER_VARS = ("PMI_SIZE", "PMI_RANK", "OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "MPI_LOCALNRANKS")
# the prefixes of the variables MPICH's Hydra and Open MPI's launchers give their processes
LAUNCHER_PREFIXES = ("PMI_", "OMPI_", "PMIX_", "HYDRA_", "MPI_", "MPIR_")


def launched_by_mpi() -> bool:
    """True when an MPI launcher (mpiexec/srun) started this process."""
    return any(v in os.environ for v in _LAUNCHER_VARS)


def without_launcher(env=None) -> dict:
    """A copy of ``env`` (default: this process's environment) without the MPI launcher's variables
    (LAUNCHER_PREFIXES): a child `mpiexec` given it starts its own job, even from a process that an
    mpiexec started (the tests under `mpiexec -n 2`, the benchmarks' launches)."""
    env = os.environ if env is None else env
    return {k: v for k, v in env.items() if not k.startswith(LAUNCHER_PREFIXES)}


class SerialComm:
    """The size-1 communicator: every collective is the identity."""

    rank = 0
    size = 1
    blocked = 0.0  # [s] never waits

    def sum(self, value):
        return value

    def max(self, value):
        return value

    def min(self, value):
        return value

    def bcast(self, obj):
        return obj

    def reduce_sum(self, array):
        return array.copy()

    def bcast_array(self, array):
        return array

    def start_bcast_array(self, array):
        return array

    def finish_bcast_array(self, pending):
        return pending

    def gather(self, obj):
        return [obj]

    def scatter(self, objs):
        return objs[0]

    def h5py_comm(self):
        """No communicator: h5py opens files with its default (serial) driver."""
        return None

    def alltoall(self, objs):
        return list(objs)

    def exchange_doubles(self, sendbuf, sendcounts):
        return sendbuf.copy(), np.asarray(sendcounts)

    def allgather_doubles(self, local):
        """Every rank's float64 vector, concatenated in rank order, on every rank; and the counts."""
        return np.array(local, dtype=np.float64), np.array([len(local)], np.int64)

    def start_neighbour_exchange(self, sends, recvs):
        """No other rank: nothing is sent; every receive is for this rank's own send."""
        return [a.copy() for _, a in sends]

    def finish_neighbour_exchange(self, pending):
        return pending

    def barrier(self):
        """Nothing to wait for on one rank."""
        return None


def _blocking(method):
    """An MPIComm method that may wait for other ranks: its wall time is added to ``blocked`` [s]."""
    @functools.wraps(method)
    def timed(self, *args):
        t0 = perf_counter()
        try:
            return method(self, *args)
        finally:
            self.blocked += perf_counter() - t0
    return timed


class MPIComm:
    """COMM_WORLD through mpi4py: numpy-buffer collectives for the step, pickled ones for set-up.

    ``comm``: another mpi4py communicator instead (a part of COMM_WORLD: mpi/scaling.py --weak runs
    each point of its series on the first ranks of the job)."""

    def __init__(self, comm=None):
        from mpi4py import MPI

        self._MPI = MPI
        self.comm = comm if comm is not None else MPI.COMM_WORLD
        self.rank = self.comm.Get_rank()
        self.size = self.comm.Get_size()
        self.blocked = 0.0  # [s] of wall time inside calls that wait for other ranks (parallel/domain.py)

    @_blocking
    def _reduce(self, value, op):
        if isinstance(value, np.ndarray):
            out = np.empty_like(value)
            self.comm.Allreduce(np.ascontiguousarray(value), out, op=op)
            return out
        return self.comm.allreduce(value, op=op)

    def sum(self, value):
        return self._reduce(value, self._MPI.SUM)

    def max(self, value):
        return self._reduce(value, self._MPI.MAX)

    def min(self, value):
        return self._reduce(value, self._MPI.MIN)

    @_blocking
    def bcast(self, obj):
        return self.comm.bcast(obj, root=0)

    @_blocking
    def reduce_sum(self, array):
        """Sum of a float64 array over ranks, on rank 0 (None elsewhere)."""
        array = np.ascontiguousarray(array, dtype=np.float64)
        out = np.empty_like(array) if self.rank == 0 else None
        self.comm.Reduce(array, out, op=self._MPI.SUM, root=0)
        return out

    @_blocking
    def bcast_array(self, array):
        """Rank 0's float64 array on every rank (in place on the others)."""
        array = np.ascontiguousarray(array, dtype=np.float64)
        self.comm.Bcast(array, root=0)
        return array

    def start_bcast_array(self, array):
        """Post ``bcast_array`` without waiting (every rank passes an array of the shape, which must
        stay untouched until ``finish_bcast_array``, which waits and returns rank 0's values)."""
        array = np.ascontiguousarray(array, dtype=np.float64)
        return self.comm.Ibcast(array, root=0), array

    @_blocking
    def finish_bcast_array(self, pending):
        request, array = pending
        request.Wait()
        return array

    @_blocking
    def gather(self, obj):
        return self.comm.gather(obj, root=0)

    @_blocking
    def scatter(self, objs):
        """objs[k] of rank 0's list arrives on rank k (objs is ignored on the other ranks)."""
        return self.comm.scatter(objs if self.rank == 0 else None, root=0)

    def h5py_comm(self):
        """The mpi4py communicator object, for ``h5py.File(..., driver="mpio", comm=...)``."""
        return self.comm

    @_blocking
    def alltoall(self, objs):
        return self.comm.alltoall(list(objs))

    @_blocking
    def exchange_doubles(self, sendbuf, sendcounts):
        """Alltoallv of float64 blocks: block k of sendbuf (sendcounts[k] doubles) goes to rank k.

        Returns (recvbuf, recvcounts); blocks arrive ordered by source rank.
        """
        sendcounts = np.ascontiguousarray(sendcounts, dtype=np.int64)
        recvcounts = np.empty_like(sendcounts)
        self.comm.Alltoall(sendcounts, recvcounts)
        sdispl = np.concatenate([[0], np.cumsum(sendcounts)[:-1]])
        rdispl = np.concatenate([[0], np.cumsum(recvcounts)[:-1]])
        recvbuf = np.empty(int(recvcounts.sum()))
        D = self._MPI.DOUBLE
        self.comm.Alltoallv([np.ascontiguousarray(sendbuf), (sendcounts, sdispl), D],
                            [recvbuf, (recvcounts, rdispl), D])
        return recvbuf, recvcounts

    @_blocking
    def allgather_doubles(self, local):
        """Every rank's float64 vector ``local``, concatenated in rank order, on every rank (Allgatherv);
        returns (the concatenation, each rank's count)."""
        local = np.ascontiguousarray(local, dtype=np.float64)
        counts = np.empty(self.size, np.int64)
        self.comm.Allgather(np.array([len(local)], np.int64), counts)
        displ = np.concatenate([[0], np.cumsum(counts)[:-1]])
        out = np.empty(int(counts.sum()))
        self.comm.Allgatherv(local, [out, (counts, displ), self._MPI.DOUBLE])
        return out, counts

    def start_neighbour_exchange(self, sends, recvs):
        """Post non-blocking messages of float64: ``sends`` [(rank, array)], ``recvs`` [(rank, doubles)].

        Returns the pending exchange for ``finish_neighbour_exchange`` (which keeps the send buffers
        alive until they have gone). Only the ranks named exchange messages: no collective."""
        D = self._MPI.DOUBLE
        bufs = [np.empty(int(n)) for _, n in recvs]
        reqs = [self.comm.Irecv([b, D], source=int(r), tag=GHOST_TAG) for (r, _), b in zip(recvs, bufs)]
        sent = [np.ascontiguousarray(a) for _, a in sends]
        reqs += [self.comm.Isend([a, D], dest=int(r), tag=GHOST_TAG) for (r, _), a in zip(sends, sent)]
        return reqs, bufs, sent

    @_blocking
    def finish_neighbour_exchange(self, pending):
        """Wait for a ``start_neighbour_exchange``; returns the received arrays, in ``recvs`` order."""
        reqs, bufs, _ = pending
        self._MPI.Request.Waitall(reqs)
        return bufs

    @_blocking
    def barrier(self):
        self.comm.Barrier()


def world():
    """The communicator of this process: MPI when launched by mpiexec with more than one rank."""
    if launched_by_mpi():
        comm = MPIComm()
        if comm.size > 1:
            return comm
    return SerialComm()


def mpi_library_version() -> str | None:
    """The first line of the MPI library's version string when an MPI launcher started this process
    (None otherwise: a serial process never initialises MPI)."""
    if not launched_by_mpi():
        return None
    from mpi4py import MPI

    return MPI.Get_library_version().strip().splitlines()[0].strip()


def settle_all(timeout: float = 10.0) -> None:
    """Wait (at most ``timeout`` s) until every rank of an MPI job gets here: before a rank ends its
    process with os._exit, so that rank 0 has printed its message before the launcher ends the job."""
    if launched_by_mpi():
        import time

        from mpi4py import MPI

        if MPI.Is_initialized() and not MPI.Is_finalized() and MPI.COMM_WORLD.Get_size() > 1:
            req = MPI.COMM_WORLD.Ibarrier()
            end = time.monotonic() + timeout
            while not req.Test() and time.monotonic() < end:
                time.sleep(0.01)


def abort_all(code: int = 1) -> None:
    """End every rank of an MPI job (one rank failing alone must not leave the others waiting)."""
    if launched_by_mpi():
        from mpi4py import MPI

        if MPI.Is_initialized() and MPI.COMM_WORLD.Get_size() > 1:
            MPI.COMM_WORLD.Abort(code)


def on_root(comm, work, *, translate=None, here=None):
    """Run ``work()`` on rank 0 only (or where ``here`` is true); rank 0's error is raised on every rank.

    The one pattern for set-up and output done by rank 0 in a collective context: the other ranks
    must not wait forever for a rank that failed. A ``PiceError`` travels as it is; another exception
    passes through ``translate(exc)`` when given, which returns the PiceError to raise everywhere (or
    None: rank 0 re-raises the original, the others a PiceError naming it). Returns ``work()``'s
    result on rank 0, None elsewhere.
    """
    from ..errors import PiceError

    result, error, original = None, None, None
    if (comm.rank == 0) if here is None else here:
        try:
            result = work()
        except PiceError as exc:
            error = exc
        except Exception as exc:
            error = translate(exc) if translate is not None else None
            if error is None:
                original = exc
                error = PiceError(f"rank 0 failed: {type(exc).__name__}: {exc}")
    error = comm.bcast(error) if comm.size > 1 else error
    if original is not None:
        raise original
    if error is not None:
        raise error
    return result


def compiles_fused_multiply_add() -> bool:
    """Whether the CPU numba compiles for here has fused multiply-add (the bond kernel fuses where it
    can: kernels/__init__.py JIT_FMA): the host's, or NUMBA_CPU_NAME / NUMBA_CPU_FEATURES when set
    (a named CPU without a feature list counts as having FMA, but "generic")."""
    import numba

    name, features = numba.config.CPU_NAME, numba.config.CPU_FEATURES
    if features:
        return "+fma" in features.split(",")
    if name:
        return name != "generic"
    import llvmlite.binding as llvm

    return bool(llvm.get_host_cpu_features().get("fma", False))


def refuse_mixed_arithmetic(comm) -> None:
    """Refuse to run on ranks whose CPUs differ in fused multiply-add (every rank, collectively).

    The two ranks holding the ends of a bond across a cut compute it each, and must break it at the
    same step: they must round alike, which a rank fusing multiply-adds and one that does not would not."""
    if comm.size == 1:
        return
    from ..errors import PiceError

    fma = comm.bcast(comm.gather(compiles_fused_multiply_add()))
    if len(set(fma)) > 1:
        with_fma = [r for r, f in enumerate(fma) if f]
        raise PiceError(f"ranks {with_fma} run on CPUs with fused multiply-add and the others on CPUs without: the "
                        "two ends of a bond across ranks would round differently; run on one kind of node, or set "
                        "NUMBA_CPU_NAME=generic for every rank (no fused multiply-add anywhere, a few per cent "
                        "slower)")
