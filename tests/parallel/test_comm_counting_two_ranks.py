"""CountingComm on two ranks (under `mpiexec -n 2 python -m pytest -m mpi`): it counts the ghost
update the step really sends (72 B a ghost, one message a step to the one neighbour) and leaves the
numbers bit for bit as they are without it (mpi/comm_volume.py; docs/performance.md, "Scaling")."""

from __future__ import annotations

import numpy as np
import pytest
from launch import need_two_ranks

from pice.bench.sheet import reference_sheet
from pice.kernels.halo import GHOST_DOUBLES
from pice.parallel.counting import CountingComm

pytestmark = pytest.mark.mpi
STEPS = 6


def test_counts_the_ghost_update_and_changes_nothing():
    comm = need_two_ranks()
    plain, _ = reference_sheet(length=12.0, width=6.0, broken=3, comm=comm)
    counting = CountingComm(comm)
    counted, _ = reference_sheet(length=12.0, width=6.0, broken=3, comm=counting)
    counting.reset()
    plain.advance(STEPS)
    counted.advance(STEPS)
    n = plain.p.n
    assert counted.p.n == n and counted.p.nlocal == plain.p.nlocal
    assert np.array_equal(plain.p.x[:n], counted.p.x[:n]) and np.array_equal(plain.p.w[:n], counted.p.w[:n])
    rows = {(r["kind"], r["caller"]): r for r in counting.table()}
    update = rows[("exchange", "Halo.start_update")]
    sent = sum(len(i) for i in counted.domain.halo.send_idx)
    assert sent > 0 and update["calls"] == STEPS  # the sheet moves 6 mm: no rebuild in 6 steps
    assert update["messages"] == STEPS and update["bytes"] == STEPS * 8 * GHOST_DOUBLES * sent
    assert rows[("wait", "Halo.finish_update")]["calls"] == STEPS
    assert not any(kind == "counts" for kind, _ in rows)  # the counts are known since the rebuild
    assert rows[("allreduce", "Halo.needs_rebuild")]["calls"] == 1  # a check, then the motion bound skips the rest
