"""Broken ice on 1 and 2 ranks (issue 14: "floes are distributed over MPI ranks like the level ice,
with the same rank-invariance contract").

Every rank holds every floe; each computes the contacts and water loads of its floes (dealt round
the ranks) as records, gathered and merged by floe (physics/floe_system.py). The forces are then summed in the same
order on any rank count, so the contract here is stricter than the level ice's round-off bound:
the series (floe contacts, their kinetic energy, the ice load on the structure, the walls' load)
agree bit for bit. A restart from a 1-rank checkpoint continued on 2 ranks joins the 1-rank run
bit for bit too (with waves: the sea at the floes, taken at the ends of intervals of steps and
interpolated, is checkpointed with them).
"""

from __future__ import annotations

import h5py
import numpy as np
import pytest
from launch import pice_run, run_cmd
from scenes import floe_job

KEYS = ("floe_contacts", "floe_structure_contacts", "floe_kinetic_energy", "ice_force", "floe_wall_force",
        "floe_water_force")


def _series(path):
    with h5py.File(path) as f:
        assert f.attrs["status"] == "finished"
        s = f["series"]
        return s["step"][:], {k: s[k][:] for k in KEYS}


@pytest.mark.parametrize("waves", [False, True], ids=["still", "waves"])
def test_floes_agree_bit_for_bit_on_one_and_two_ranks(tmp_path, waves):
    job = tmp_path / "floes.toml"
    job.write_text(floe_job(duration=6.0, checkpoint_every=3.0, waves=waves))
    run_cmd(pice_run(job, tmp_path / "r1.h5", 1))
    run_cmd(pice_run(job, tmp_path / "r2.h5", 2))
    steps1, one = _series(tmp_path / "r1.h5")
    steps2, two = _series(tmp_path / "r2.h5")
    assert np.array_equal(steps1, steps2)
    assert one["floe_contacts"].max() > 0 and one["floe_structure_contacts"].max() > 0, "the floes must meet"
    assert np.abs(one["ice_force"]).max() > 1e4
    for k in KEYS:
        assert np.array_equal(one[k], two[k]), k

    # half the run on 1 rank, the rest restarted on 2 from its checkpoint: the same rows
    half = tmp_path / "half.toml"
    half.write_text(floe_job(duration=3.0, checkpoint_every=3.0, waves=waves))
    run_cmd(pice_run(half, tmp_path / "h.h5", 1))
    run_cmd(pice_run(job, tmp_path / "h.h5", 2, "--restart", tmp_path / "h.ckpt.h5"))
    steps_h, cont = _series(tmp_path / "h.h5")
    common, ia, ib = np.intersect1d(steps1, steps_h, return_indices=True)
    assert common[-1] == steps1[-1] and len(common) >= len(steps1) - 1
    for k in KEYS:
        assert np.array_equal(one[k][ia], cont[k][ib]), k


def test_breakable_floes_keep_the_level_ice_contract_on_two_ranks(tmp_path):
    """Breakable floes are elements of the sheet, decomposed like it, so they keep its contract
    (tests/parallel/test_parallel_contract.py): the front floe driven at 1 m/s into a wall 0.02 m
    ahead of it breaks; positions by gid within 1e-9 m and the same broken bonds on 1 and 2 ranks."""
    from scenes import bonded_floe_job, job_from_text

    from pice.scenes.level_ice import build_level_ice

    p, _ = build_level_ice(job_from_text(bonded_floe_job()))
    front = float((p.x[:, 0] + p.radius).max())
    job = tmp_path / "bonded.toml"
    job.write_text(bonded_floe_job(wall_x=front + 0.02, duration=0.4, series_every=100))
    final = {}
    for ranks in (1, 2):
        run_cmd(pice_run(job, tmp_path / f"b{ranks}.h5", ranks))
        with h5py.File(tmp_path / f"b{ranks}.h5") as f:
            assert f.attrs["status"] == "finished" and int(f.attrs["ranks"]) == ranks
            last = f["snapshots"][sorted(f["snapshots"])[-1]]
            broken = {(int(a), int(b)) for a, b in f["events/broken_bonds"][:, 2:4]}
            final[ranks] = last["gid"][:], last["x"][:], broken
    gid1, x1, broken1 = final[1]
    gid2, x2, broken2 = final[2]
    assert len(broken1) > 0, "the floe must break"
    assert np.array_equal(gid1, gid2) and np.abs(x2 - x1).max() < 1e-9
    assert broken1 == broken2
