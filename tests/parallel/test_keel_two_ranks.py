"""A ship's run through a keel on 1 and 2 ranks (issue 15): the blocks are rigid pieces, so the
floes' contract holds (tests/parallel/test_floes_two_ranks.py: the series bit for bit), and a run
that ends past its peak (keel.end_after_peak, decided on rank 0 and told to every rank) ends at the
same row on any rank count, also when continued from a checkpoint.
"""

from __future__ import annotations

import h5py
import numpy as np
from launch import BIN, pice_run, run_cmd
from scenes import MICRO_KEEL, ship_ends_job

KEYS = ("time", "ice_force_mean", "body_position", "floe_contacts", "floe_wall_force", "body_piece_force")


def _series(path):
    with h5py.File(path) as f:
        assert f.attrs["status"] == "finished"
        return {k: f["series"][k][:] for k in KEYS}


def test_a_ship_run_ends_past_its_peak_at_the_same_row_on_two_ranks(tmp_path):
    """The mini half ship through the micro keel (tests/scenes.py): on 1 rank it ends at about
    t = 14 s of its 30 s (measured); on 2 ranks at the same row with the same record, bit for bit;
    and on 2 ranks continued from the 2-rank run's last checkpoint (t = 12 s, between two rows), again."""
    keel = tmp_path / "micro.toml"
    keel.write_text(MICRO_KEEL.format(duration=2.0, seed=1))
    run_cmd([BIN / "pice", "keel", keel])
    job = tmp_path / "ship.toml"
    job.write_text(ship_ends_job(duration=30.0, checkpoint_every=2.0))
    run_cmd(pice_run(job, tmp_path / "r1.h5", 1))
    run_cmd(pice_run(job, tmp_path / "r2.h5", 2))
    one, two = _series(tmp_path / "r1.h5"), _series(tmp_path / "r2.h5")
    assert 5.0 < one["time"][-1] < 25.0, one["time"][-1]  # ended past the peak, not at run.duration
    assert np.abs(one["ice_force_mean"][:, 0, 0]).max() > 300.0  # the bow met the rubble
    for k in KEYS:
        assert np.array_equal(one[k], two[k]), k
    res = run_cmd(pice_run(job, tmp_path / "r2.h5", 2, "--restart", tmp_path / "r2.ckpt.h5"))
    assert "the run ends here (keel.end_after_peak)" in res.stdout + res.stderr
    again = _series(tmp_path / "r2.h5")
    for k in KEYS:
        assert np.array_equal(one[k], again[k]), k
