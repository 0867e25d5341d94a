"""pice.parallel.counting.CountingComm on one rank: what it records, and that it leaves the numbers
alone (mpi/comm_volume.py counts the step's messages with it; docs/performance.md, "Scaling")."""

from __future__ import annotations

import numpy as np

from pice.bench.sheet import reference_sheet
from pice.parallel.comm import SerialComm
from pice.parallel.counting import CountingComm, payload_bytes, rounds


def _issue(comm):
    comm.max(1.0)
    comm.sum(np.zeros(3))
    comm.reduce_sum(np.zeros((2, 6)))
    comm.bcast_array(np.zeros(13))
    comm.alltoall([{"x": np.zeros(4)}])
    comm.exchange_doubles(np.zeros(0), np.zeros(1, np.int64))


def test_records_kind_caller_and_payload():
    comm = CountingComm(SerialComm())
    _issue(comm)
    rows = {(r["kind"], r["caller"]): r for r in comm.table()}
    assert set(rows) == {(k, "_issue") for k in ("allreduce", "reduce", "bcast", "alltoall", "counts", "exchange")}
    assert rows[("allreduce", "_issue")]["calls"] == 2
    assert rows[("allreduce", "_issue")]["bytes"] == payload_bytes(1.0) + 24
    assert rows[("reduce", "_issue")]["bytes"] == 96 and rows[("bcast", "_issue")]["bytes"] == 104
    # one rank sends nothing to another: no message, no byte, in the exchange and the alltoall
    assert rows[("exchange", "_issue")]["messages"] == 0 and rows[("exchange", "_issue")]["bytes"] == 0
    assert rows[("alltoall", "_issue")]["messages"] == 0 and rows[("alltoall", "_issue")]["bytes"] == 0
    comm.reset()
    assert comm.table() == []


def test_rounds_of_a_tree():
    assert [rounds(p) for p in (1, 2, 3, 4, 5, 1024)] == [0, 1, 2, 2, 3, 10]


def test_a_counted_sheet_steps_as_the_plain_one():
    plain, _ = reference_sheet(length=8.0, width=6.0, broken=3, comm=SerialComm())
    counted, _ = reference_sheet(length=8.0, width=6.0, broken=3, comm=CountingComm(SerialComm()))
    plain.advance(12)
    counted.advance(12)
    n = plain.p.n
    assert counted.p.n == n
    assert np.array_equal(plain.p.x[:n], counted.p.x[:n]) and np.array_equal(plain.p.v[:n], counted.p.v[:n])


def test_fused_multiply_add_follows_numbas_cpu_settings(monkeypatch):
    """compiles_fused_multiply_add: NUMBA_CPU_FEATURES decides when given, a named CPU has FMA unless
    it is "generic", and the host's features decide otherwise (this machine's CPU: llvmlite's answer)."""
    import llvmlite.binding as llvm
    import numba

    from pice.parallel.comm import compiles_fused_multiply_add

    monkeypatch.setattr(numba.config, "CPU_NAME", None)
    monkeypatch.setattr(numba.config, "CPU_FEATURES", None)
    assert compiles_fused_multiply_add() == bool(llvm.get_host_cpu_features().get("fma", False))
    monkeypatch.setattr(numba.config, "CPU_NAME", "generic")
    assert not compiles_fused_multiply_add()
    monkeypatch.setattr(numba.config, "CPU_NAME", "skylake")
    assert compiles_fused_multiply_add()
    monkeypatch.setattr(numba.config, "CPU_FEATURES", "+avx2,-fma")
    assert not compiles_fused_multiply_add()
    monkeypatch.setattr(numba.config, "CPU_FEATURES", "+avx2,+fma")
    assert compiles_fused_multiply_add()
