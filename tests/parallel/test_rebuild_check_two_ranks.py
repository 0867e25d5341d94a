"""The halo's rebuild check every N steps, N from a bound on the motion (parallel/halo.py
steps_to_next_check), on two ranks (under `mpiexec -n 2 python -m pytest -m mpi`): a slow sheet
reduces far less than once a step, with a numpy Allreduce (and the health check once), and a fast, accelerating sheet rebuilds on
the same steps, with the same bits, as with the check forced on every step."""

from __future__ import annotations

import numpy as np
import pytest
from launch import need_two_ranks

from pice.bench.sheet import reference_sheet
from pice.parallel.counting import CountingComm

pytestmark = pytest.mark.mpi


def _rebuilds(sim):
    """Count the halo's rebuilds of ``sim`` (wraps its Halo.rebuild)."""
    halo = sim.domain.halo
    inner, count = halo.rebuild, [0]

    def rebuild(p):
        count[0] += 1
        inner(p)

    halo.rebuild = rebuild
    return count


def _pair(comm, steps, *, speed=0.0, accel=0.0):
    """The 12 m x 6 m sheet twice: with the bounded check and with the check on every step, given a
    uniform extra speed [m/s] and acceleration [m/s^2] along x; (bounded, its rebuilds, every step,
    its rebuilds, the bounded run's rebuild checks)."""
    out, counting = [], CountingComm(comm)
    for cap in (None, 1):
        sim, _ = reference_sheet(length=12.0, width=6.0, broken=3, comm=counting if cap is None else comm)
        if cap is not None:
            sim.domain.halo.check_cap = cap
        p = sim.p
        p.v[:, 0] += speed
        p.ext_force[:p.nlocal, 0] += accel * p.mass[:p.nlocal]
        count = _rebuilds(sim)
        counting.reset()
        sim.advance(steps)
        out += [sim, count[0]]
        if cap is None:
            checks = counting.records[("allreduce", "Halo.needs_rebuild")][0]
    return out + [checks]


def test_a_slow_sheet_checks_far_less_than_every_step():
    comm = need_two_ranks()
    counting = CountingComm(comm)
    sim, _ = reference_sheet(length=12.0, width=6.0, broken=3, comm=counting)
    counting.reset()
    steps = 60
    sim.advance(steps)
    rows = {(r["kind"], r["caller"]): r for r in counting.table()}
    check = rows[("allreduce", "Halo.needs_rebuild")]
    assert check["calls"] < steps / 10, check  # the sheet moves ~1 m/s: 0.15 m takes ~160 steps, capped at 50
    assert check["bytes"] == 24 * check["calls"]  # 3 doubles a check, as a numpy buffer (not pickled)
    health = rows[("allreduce", "Simulation.check_health")]  # one reduction: the runaway and crushed flags
    assert health["calls"] == steps // sim.job.run.check_every and health["bytes"] == 16 * health["calls"]
    assert not any(caller.startswith("Halo.check_bond") for _, caller in rows)


def test_a_fast_accelerating_sheet_rebuilds_on_the_same_steps_with_the_same_bits():
    comm = need_two_ranks()
    steps = 80
    bounded, nb, every, ne, checks = _pair(comm, steps, speed=6.0, accel=40.0)  # skin/2 in ~20 steps, then fewer
    assert ne >= 3 and nb == ne  # it migrates several times, on the same steps
    assert checks < steps / 2  # and still skips most checks
    n = bounded.p.n
    assert every.p.n == n and every.p.nlocal == bounded.p.nlocal
    for name in ("gid", "x", "v", "w"):
        assert np.array_equal(getattr(bounded.p, name)[:n], getattr(every.p, name)[:n]), name


def test_the_ghost_update_reuses_its_buffer_and_refuses_a_second_post():
    """Halo.start_update packs into one send buffer kept from the rebuild (Halo._plan_update): a
    second post before the first has been received would overwrite a message in flight, and is
    refused; after a rebuild the plan is made again, for the new ghost lists, and the ghosts received
    are the owners' current positions."""
    comm = need_two_ranks()
    sim, _ = reference_sheet(length=12.0, width=6.0, broken=3, comm=comm)
    halo, p = sim.domain.halo, sim.p
    halo.start_update(p)
    with pytest.raises(RuntimeError, match="before the previous one was received"):
        halo.start_update(p)
    halo.finish_update(p)
    buffer = halo._plan[2]
    halo.update(p)
    assert halo._plan[2] is buffer  # the same buffer, step after step
    p.x[:p.nlocal, 0] += 0.01  # every owner moves; its ghosts on the other rank follow at the update
    halo.rebuild(p)
    halo.update(p)
    assert halo._plan[0] is halo.send_idx and halo._plan[2] is not buffer  # planned again after the rebuild
    ghosts = comm.comm.allgather(dict(zip(p.gid[p.nlocal:p.n].tolist(), p.x[p.nlocal:p.n].tolist())))
    owned = dict(zip(p.gid[:p.nlocal].tolist(), p.x[:p.nlocal].tolist()))
    other = ghosts[1 - comm.rank]  # the other rank's ghosts of this rank's elements
    assert other and set(other) <= set(owned)
    assert all(owned[g] == x for g, x in other.items())
