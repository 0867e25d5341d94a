"""Checkpoints in process (issue 5): a checkpoint written and read back continues bit for bit; a
restart refuses another time step or other physics; the command line's errors; an unwritable
checkpoint stops the run with a clear error and keeps the run file.

The restarts of killed `pice run` processes (1 and 2 ranks, across rank counts) are in
tests/parallel/test_restart_after_kill.py.
"""

from __future__ import annotations

import pathlib

import h5py
import numpy as np
import pytest
from scenes import slope_job, tomllib

from pice.cli import main
from pice.io.checkpoint import CheckpointError, default_path, read_checkpoint, write_checkpoint
from pice.job import parse_job
from pice.parallel.comm import SerialComm
from pice.simulation import Simulation
from pice.state import PER_PARTICLE

# the slope job for 100 steps of 2e-4 s
TINY = tomllib.loads(slope_job(duration=0.02, snapshots=2, series_every=10, dt=2e-4))


def _tiny(**changes):
    data = {k: dict(v) if isinstance(v, dict) else v for k, v in TINY.items()}
    for key, value in changes.items():
        section, name = key.split(".")
        data[section][name] = value
    return parse_job(data, source="tiny.toml", text=repr(data))


def test_checkpoint_round_trip_continues_bit_for_bit(tmp_path):
    job = _tiny()
    a = Simulation(job, comm=SerialComm())
    a.advance(60)
    path = write_checkpoint(a, tmp_path / "tiny.ckpt.h5")
    assert not (tmp_path / "tiny.ckpt.h5.tmp").exists()
    a.rebuild_for_checkpoint()
    data = read_checkpoint(path)
    assert data["attrs"]["step"] == 60 and data["attrs"]["ranks"] == 1 and data["attrs"]["dt"] == a.dt
    b = Simulation.from_checkpoint(job, data, comm=SerialComm())
    assert b.c.step == a.c.step and b.c.time == a.c.time and b.c.broken == a.c.broken
    for name in (*PER_PARTICLE, "bond_j"):
        assert np.array_equal(getattr(a.p, name), getattr(b.p, name)), name
    a.advance(40)
    b.advance(40)
    for name in ("x", "v", "w", "force", "bond_hist", "contact_hist", "wall_hist"):
        assert np.array_equal(getattr(a.p, name), getattr(b.p, name)), name
    ra, rb = a.series_row(), b.series_row()
    assert ra.keys() == rb.keys()
    for key in ra:
        assert np.array_equal(ra[key], rb[key]), key


def test_restart_refuses_another_dt_or_other_physics(tmp_path):
    a = Simulation(_tiny(), comm=SerialComm())
    a.advance(5)
    data = read_checkpoint(write_checkpoint(a, tmp_path / "c.h5"))
    with pytest.raises(CheckpointError, match=r"written with dt = 0\.0002 s.*now gives dt = 0\.0001 s"):
        Simulation.from_checkpoint(_tiny(**{"run.dt": 1e-4}), data, comm=SerialComm())
    with pytest.raises(CheckpointError, match=r"physics differs.*bond\.normal_strength = 2000000\.0 "
                                              r"\(checkpoint: 1500000\.0\)"):
        Simulation.from_checkpoint(_tiny(**{"bond.normal_strength": 2.0e6}), data, comm=SerialComm())
    # the schedule may change: a longer run continues from the checkpoint
    b = Simulation.from_checkpoint(_tiny(**{"run.duration": 0.04, "run.snapshots": 5}), data, comm=SerialComm())
    assert b.c.step == 5


def test_a_checkpoint_from_before_a_key_existed_restarts_when_the_job_leaves_it_at_its_default(tmp_path):
    """A key added to the job after a checkpoint was written (its physics then lacked it) is no
    difference while the job leaves it at its default, which keeps the code's behaviour from before the
    key (the convention of every defaulted key; e.g. keel.form_drag_coefficient); set otherwise it is
    refused, naming it. Here water.skin_drag_coefficient (default 0.0055) plays the new key."""
    import json

    a = Simulation(_tiny(), comm=SerialComm())
    a.advance(5)
    data = read_checkpoint(write_checkpoint(a, tmp_path / "c.h5"))
    physics = json.loads(data["attrs"]["physics"])
    assert physics["water"].pop("skin_drag_coefficient") == 0.0055  # as written before the key existed
    data["attrs"]["physics"] = json.dumps(physics, sort_keys=True)
    b = Simulation.from_checkpoint(_tiny(), data, comm=SerialComm())
    assert b.c.step == 5
    with pytest.raises(CheckpointError, match=r'physics differs.*water\.skin_drag_coefficient = 0\.01 '
                                              r'\(checkpoint: "absent"\)'):
        Simulation.from_checkpoint(_tiny(**{"water.skin_drag_coefficient": 0.01}), data, comm=SerialComm())


def test_restart_cli_errors(tmp_path, capsys):
    job = tmp_path / "tiny.toml"
    job.write_text('[run]\nduration = 0.004\ndt = 2e-4\ncheckpoint_every = 0.002\n[ice]\nlength = 3.0\n'
                   'width = 2.0\n[bond]\nnormal_stiffness = 1.72e7\nnormal_strength = 1.5e6\n')
    out = tmp_path / "tiny.h5"
    assert main(["run", str(job), "-o", str(out)]) == 0
    ckpt = tmp_path / "tiny.ckpt.h5"
    assert read_checkpoint(ckpt)["attrs"]["step"] == 20  # the last one, at the end of the run
    capsys.readouterr()
    assert main(["run", str(job), "-o", str(out), "--restart", str(tmp_path / "none.h5")]) == 6
    assert "checkpoint not found" in capsys.readouterr().err
    assert main(["run", str(job), "-o", str(out), "--restart", str(out)]) == 6
    assert "not a pice checkpoint" in capsys.readouterr().err
    assert main(["run", str(job), "-o", str(tmp_path / "other.h5"), "--restart", str(ckpt)]) == 4
    assert "run file not found" in capsys.readouterr().err
    job.write_text(job.read_text().replace("length = 3.0", "length = 4.0"))
    assert main(["run", str(job), "-o", str(out), "--restart", str(ckpt)]) == 6
    assert "ice.length = 4.0 (checkpoint: 3.0)" in capsys.readouterr().err


def test_default_checkpoint_path():
    assert default_path("runs/demo.h5") == pathlib.Path("runs/demo.ckpt.h5")
    assert default_path("out/run") == pathlib.Path("out/run.ckpt.h5")


def test_unwritable_checkpoint_stops_the_run_with_a_clear_error(tmp_path, capsys):
    blocker = tmp_path / "not_a_folder"
    blocker.write_text("a file where the checkpoint's folder should be")
    job = tmp_path / "tiny.toml"
    job.write_text('[run]\nduration = 0.004\ndt = 2e-4\nseries_every = 5\ncheckpoint_every = 0.002\n'
                   f'checkpoint = "{blocker / "c.h5"}"\n[ice]\nlength = 3.0\nwidth = 2.0\n'
                   '[bond]\nnormal_stiffness = 1.72e7\nnormal_strength = 1.5e6\n')
    out = tmp_path / "tiny.h5"
    assert main(["run", str(job), "-o", str(out)]) == 6
    assert "cannot write the checkpoint" in capsys.readouterr().err
    with h5py.File(out) as f:  # the run file keeps its rows and says why it stopped
        assert f.attrs["status"] == "failed" and f["series/step"][-1] == 10


def test_a_continued_run_counts_its_wall_time_over_its_calls(tmp_path, capsys):
    """The time loop's wall time is kept in each checkpoint, so a run continued from one reports its
    time from t = 0 (a study's cost of a killed and continued variant, not only its last call's): the
    second call's total is the checkpoint's plus its own, and its steps are its own for the rate. A
    checkpoint of a pice that did not keep it leaves the total unknown (NaN), said as such."""
    from pice.runner import run_job

    out, ckpt = tmp_path / "tiny.h5", tmp_path / "tiny.ckpt.h5"
    first = run_job(_tiny(**{"run.checkpoint_every": 0.01}), output=str(out), progress=None)
    assert first["steps"] == first["steps_run"] == 100 and first["wall_time_total"] == first["wall_time"]
    kept = read_checkpoint(ckpt)["attrs"]["wall_time"]  # written at the last step, before the loop's end
    assert 0.0 < kept <= first["wall_time"]
    longer = _tiny(**{"run.duration": 0.03, "run.checkpoint_every": 0.0})
    second = run_job(longer, output=str(out), progress=None, restart=str(ckpt))
    assert second["steps"] == 150 and second["steps_run"] == 50
    assert second["wall_time_total"] == pytest.approx(kept + second["wall_time"], rel=1e-12)
    from pice.cli import _summary_lines

    line = next(s for s in _summary_lines(second, longer) if "wall time" in s)
    assert f"{second['wall_time_total']:.1f} s to t = 0.03 s over the run's calls" in line
    with h5py.File(ckpt, "r+") as f:  # as an older pice wrote it
        del f.attrs["wall_time"]
    again = run_job(longer, output=str(out), progress=None, restart=str(ckpt))
    assert np.isnan(again["wall_time_total"]) and again["steps_run"] == 50
    line = next(s for s in _summary_lines(again, longer) if "wall time" in s)
    assert "this call only" in line
