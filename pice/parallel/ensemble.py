"""Ensembles: the ranks of one MPI job split into groups that run different variants side by side
(``pice study --group-size G``), taking them from a queue held by rank 0.

``split`` cuts the communicator into size / G groups of G consecutive ranks (MPI Comm_split); a
group of one rank gets SerialComm, so that a variant runs there exactly as it runs alone on one rank.
``WorkQueue`` is a counter in rank 0's memory that each group's leader increments atomically
(MPI one-sided Fetch_and_op under a passive-target lock): a group that finishes takes the next
number at once, without rank 0 having to answer (rank 0 runs variants too). MPICH has no progress
thread by default: a lock request to rank 0 is served only when rank 0 enters MPI, so rank 0 calls
``serve`` between the steps of its own variant (run_job's ``poll``); a one-rank variant makes no MPI
call, and without it the other groups would wait for rank 0's whole variant (seen on 2 ranks).
"""

from __future__ import annotations

import time

import numpy as np

from .comm import MPIComm, SerialComm


def split(comm, group_size: int):
    """(the group's communicator, the group's index, the number of groups) for groups of ``group_size``
    consecutive ranks; ValueError when the ranks do not divide into such groups."""
    if group_size < 1 or comm.size % group_size:
        raise ValueError(f"--group-size {group_size}: the {comm.size} rank(s) do not split into groups of "
                         f"{group_size}; use a divisor of {comm.size}")
    if group_size == comm.size:
        return comm, 0, 1
    colour = comm.rank // group_size
    raw = comm.comm.Split(colour, comm.rank)
    group = SerialComm() if group_size == 1 else MPIComm(raw)
    return group, colour, comm.size // group_size


def wait_for_all(comm, serve=None, pause: float = 0.05) -> None:
    """Return when every rank of ``comm`` has called this, sleeping ``pause`` [s] between tests: MPICH
    spins in a blocking collective, and a group that ran out of variants would keep its core busy
    while the others finish (seen on 2 ranks: the idle rank at 65 % of a core). ``serve``: called
    between tests (rank 0's queue)."""
    if comm.size == 1:
        return
    request = comm.comm.Ibarrier()
    while not request.Test():
        if serve is not None:
            serve()
        time.sleep(pause)


class WorkQueue:
    """Numbers 0, 1, 2, ... handed out once each across the groups (module docstring)."""

    def __init__(self, comm):
        self.comm = comm
        self.next_local = 0
        self.win = None
        if comm.size > 1:  # collective: every rank of comm
            MPI = comm._MPI
            self.counter = np.zeros(1 if comm.rank == 0 else 0, np.int64)
            self.win = MPI.Win.Create(self.counter, disp_unit=8, comm=comm.comm)
            comm.barrier()

    def take(self) -> int:
        """The next number (called by one rank of a group, its leader)."""
        if self.win is None:
            self.next_local += 1
            return self.next_local - 1
        MPI = self.comm._MPI
        one, got = np.ones(1, np.int64), np.zeros(1, np.int64)
        self.win.Lock(0, MPI.LOCK_EXCLUSIVE)
        self.win.Fetch_and_op([one, MPI.INT64_T], [got, MPI.INT64_T], 0, 0, MPI.SUM)
        self.win.Unlock(0)
        return int(got[0])

    def serve(self) -> None:
        """Let MPI progress the other groups' pending ``take`` (cheap; call it often on rank 0)."""
        if self.win is not None and self.comm.rank == 0:
            MPI = self.comm._MPI
            self.comm.comm.Iprobe(source=MPI.ANY_SOURCE, tag=MPI.ANY_TAG)

    def free(self) -> None:
        """Release the window (collective)."""
        if self.win is not None:
            self.win.Free()
            self.win = None
