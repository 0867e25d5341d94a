"""A killed study continues an unfinished variant from its checkpoint (issue 16: "a killed sweep
restarts and runs only the variants not yet finished"; the standards: "a killed run restarts from
its last checkpoint"), and the run it finishes is the one an unkilled study writes: its series rows
agree bit for bit (the restart contract of tests/parallel/test_restart_after_kill.py)."""

from __future__ import annotations

import json
import time

import h5py
import numpy as np
import pytest
from launch import BIN, kill9, on_ranks, run_cmd, start
from scenes import slope_job


def _series(path):
    with h5py.File(path) as f:
        assert f.attrs["status"] == "finished"
        return f["series/step"][:], f["series/kinetic_energy"][:], f["series/wall_force"][:]


def test_sigkill_mid_variant_then_the_study_continues_it_from_its_checkpoint(tmp_path):
    text = slope_job(duration=0.8, snapshots=1).replace("[run]\n", "[run]\ncheckpoint_every = 0.1\n", 1)
    job = tmp_path / "slope.toml"
    job.write_text(text)
    out = tmp_path / "study"
    cmd = [str(BIN / "pice"), "study", str(job), "--vary", "run.dt=2e-4", "--out", str(out)]
    ckpt = out / "slope_0.ckpt.h5"
    proc = start(cmd)
    end = time.monotonic() + 300
    while not ckpt.exists() and proc.poll() is None and time.monotonic() < end:
        time.sleep(0.05)
    assert proc.poll() is None, "the study ended before it could be killed"
    kill9(proc)
    with h5py.File(ckpt) as f:  # the time loop's seconds before the kill, to the checkpoint's step
        before = float(f.attrs["wall_time"])
    res = run_cmd(cmd)
    assert f"variant 0: continued from its checkpoint {ckpt}" in res.stderr, res.stderr
    # its cost counts both calls (the checkpoint's time, then the last call's), not the last one alone
    row = json.loads((out / "slope_0.outcome.json").read_text())
    assert before > 0.0 and row["wall_time"] == pytest.approx(before + row["wall_time_last_call"], rel=1e-12)
    steps, ke, wall = _series(out / "slope_0.h5")
    whole = tmp_path / "whole"
    run_cmd(cmd[:-1] + [str(whole)])
    steps_w, ke_w, wall_w = _series(whole / "slope_0.h5")
    common, ia, ib = np.intersect1d(steps, steps_w, return_indices=True)
    assert common[-1] == steps_w[-1] and len(common) == len(steps_w)
    assert np.array_equal(ke[ia], ke_w[ib]) and np.array_equal(wall[ia], wall_w[ib])


def test_sigterm_stops_a_grouped_study_and_the_same_command_continues_it(tmp_path):
    """`mpiexec -n 2 pice study --group-size 1`, two variants: a short one (0.05 s) and a long one
    (0.8 s, checkpoints every 0.1 s). SIGTERM to mpiexec once the short one is recorded and the long
    one has a checkpoint: the running variant writes its checkpoint and stops, the idle rank waits for
    it instead of dying (which made mpiexec kill the other rank before its checkpoint), the study
    exits with status 130 and records no outcome for the long variant. The same command then
    continues it from its checkpoint to a finished run, and does not run the short one again."""
    import signal

    text = slope_job(duration=0.8, snapshots=1).replace("[run]\n", "[run]\ncheckpoint_every = 0.1\n", 1)
    job = tmp_path / "slope.toml"
    job.write_text(text)
    out = tmp_path / "study"
    cmd = on_ranks(2, [str(BIN / "pice"), "study", str(job), "--vary", "run.duration=0.05,0.8", "--group-size", "1",
                       "--out", str(out)])
    short, ckpt = out / "slope_0.outcome.json", out / "slope_1.ckpt.h5"
    proc = start(cmd)
    end = time.monotonic() + 300
    while not (short.exists() and ckpt.exists()) and proc.poll() is None and time.monotonic() < end:
        time.sleep(0.05)
    assert proc.poll() is None, "the study ended before it could be stopped"
    proc.send_signal(signal.SIGTERM)
    assert proc.wait(timeout=120) == 130, proc.stderr.read() if proc.stderr else ""
    assert short.exists() and not (out / "slope_1.outcome.json").exists()
    res = run_cmd(cmd)
    assert "variant 1: continued from its checkpoint" in res.stderr, res.stderr
    assert "variant 0: done before" in res.stderr, res.stderr
    with h5py.File(out / "slope_1.h5") as f:
        assert f.attrs["status"] == "finished"
