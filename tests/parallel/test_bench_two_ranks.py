"""pice bench on two ranks (run under `mpiexec -n 2 python -m pytest -m mpi`): the report gathers
both ranks' split and their waits for the ghost update, and the benchmark sheet breaks the same
bonds on two ranks as on one.

No assertion here is on speed: tests/unit/test_bench.py says why.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
import scenes
from launch import need_two_ranks

from pice.bench import run_bench
from pice.bench.sheet import reference_sheet
from pice.parallel.comm import SerialComm
from pice.timers import PARTS

pytestmark = pytest.mark.mpi


def test_bench_gathers_both_ranks_split(tmp_out):
    comm = need_two_ranks()
    job = tmp_out / "barge.toml"
    if comm.rank == 0:
        job.write_text(scenes.barge_job(duration=0.05, series_every=3, mooring="dem"))
    comm.barrier()
    out = tmp_out / "bench2.json"
    result = run_bench(scene="both", steps=4, warmup=2, job=job, length=12.0, width=8.0, broken=5, json_path=out)
    if comm.rank != 0:
        assert result is None
        return
    data = json.loads(out.read_text())
    assert data["ranks"] == 2 and data["software"]["mpi_library"]
    for split in (data["sheet"]["split"], data["full"]["split"]):
        assert split["ranks"] == 2 and set(split["parts"]) == set(PARTS)
        for part in split["parts"].values():
            assert len(part["per_rank_ms_per_step"]) == 2
            assert part["max_ms_per_step"] == max(part["per_rank_ms_per_step"])
        assert split["parts"]["halo"]["max_ms_per_step"] > 0 and split["parts"]["waiting"]["max_ms_per_step"] > 0
        assert split["sum_over_outside"] <= 1.0 + 1e-9
        # each rank's waits for the ghost update are part of its "waiting": none can exceed its total
        for waits, waiting in zip(split["ghost_wait_ms"], split["parts"]["waiting"]["per_rank_ms_per_step"]):
            assert waits is not None and 0 <= waits["median"] <= waits["p90"] <= waits["max"]
            assert waits["max"] <= waiting * split["steps"] * (1 + 1e-9)


def test_the_sheet_breaks_the_same_bonds_on_two_ranks_as_on_one():
    comm = need_two_ranks()
    sim, count = reference_sheet(length=14.0, width=10.0, broken=12, comm=comm)
    parts = comm.gather(sim.p.intact_bonds())
    if comm.rank == 0:
        one, count_one = reference_sheet(length=14.0, width=10.0, broken=12, comm=SerialComm())
        two = np.concatenate(parts)
        assert count == count_one == 12
        assert sorted(map(tuple, two)) == sorted(map(tuple, one.p.intact_bonds()))
