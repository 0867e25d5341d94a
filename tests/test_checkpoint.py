"""Checkpoint and restart (issue 5): a killed run, restarted from its last checkpoint, ends where an
uninterrupted run ends -- bit for bit on the same rank count, within 1e-9 m on another -- and a
SIGKILL at any moment leaves the run file and the last checkpoint readable.

The job is the contract test's fracturing demo (tests/test_parallel_contract.py) for 2,400 steps
with a checkpoint every 600 steps. Runs are real `pice run` processes (1 rank, or `mpiexec -n 2`),
killed with SIGKILL (every process of the MPI job) or interrupted with SIGINT.
"""

from __future__ import annotations

import os
import pathlib
import random
import shutil
import signal
import subprocess
import sys
import time

import h5py
import numpy as np
import pytest
from launcher import clean_env as _clean_env

from pice.cli import main
from pice.io.checkpoint import CheckpointError, default_path, read_checkpoint, write_checkpoint
from pice.job import parse_job
from pice.parallel.comm import SerialComm
from pice.simulation import Simulation
from pice.state import PER_PARTICLE

ROOT = pathlib.Path(__file__).resolve().parents[1]
BIN = pathlib.Path(sys.executable).parent
DT = 1.4e-4
STEPS = 2400
CKPT_EVERY = 600
SERIES = ("time", "step", "bonds", "broken_bonds", "contacts", "kinetic_energy", "total_energy", "wall_force")


def demo_job(folder: pathlib.Path, name: str = "ckpt", *, steps: int = STEPS, ckpt_every: int = CKPT_EVERY,
             series_every: int = 100, snapshots: int = 3) -> pathlib.Path:
    """The contract test's job (the demo, closer to the panel, driven at 2 m/s: it breaks early)."""
    text = (ROOT / "jobs" / "level_ice_demo.toml").read_text()
    for old, new in (("origin = [0.0, 0.0]", "origin = [0.45, 0.0]"),
                     ("velocity = [1.0, 0.0]", "velocity = [2.0, 0.0]"),
                     ("speed = 1.0 ", "speed = 2.0 "),
                     ('dt = "auto"', f"dt = {DT}"),
                     ("duration = 3.0 ", f"duration = {steps * DT!r}\ncheckpoint_every = {ckpt_every * DT!r} "),
                     ("series_every = 500 ", f"series_every = {series_every} "),
                     ("snapshots = 11", f"snapshots = {snapshots}"),
                     ("[bond]\n", "[parallel]\nbalance_every = 400\n\n[bond]\n")):
        assert old in text, old
        text = text.replace(old, new)
    job = folder / f"{name}.toml"
    job.write_text(text)
    return job


def _cmd(job, out, ranks, *extra):
    cmd = [str(BIN / "pice"), "run", str(job), "-o", str(out), *map(str, extra)]
    return [str(BIN / "mpiexec"), "-n", str(ranks)] + cmd if ranks > 1 else cmd


def _run(job, out, ranks, *extra, expect=0):
    res = subprocess.run(_cmd(job, out, ranks, *extra), env=_clean_env(), capture_output=True, text=True,
                         timeout=600)
    assert res.returncode == expect, res.stderr[-3000:]
    return res


def _start(job, out, ranks):
    return subprocess.Popen(_cmd(job, out, ranks), env=_clean_env(), stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, text=True)


def _descendants(pid: int) -> list[int]:
    """Every process below ``pid`` (mpiexec -> hydra proxy -> ranks), from /proc."""
    children: dict[int, list[int]] = {}
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                stat = pathlib.Path(f"/proc/{entry}/stat").read_text()
            except OSError:
                continue
            ppid = int(stat.rsplit(")", 1)[1].split()[1])
            children.setdefault(ppid, []).append(int(entry))
    out, todo = [], [pid]
    while todo:
        for child in children.get(todo.pop(), []):
            out.append(child)
            todo.append(child)
    return out


def _kill9(proc: subprocess.Popen) -> None:
    """SIGKILL the run: every rank, the proxy and the launcher at once (a crashed node)."""
    pids = [*_descendants(proc.pid), proc.pid]
    for pid in pids:
        try:
            os.kill(pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    proc.wait(timeout=30)
    deadline = time.monotonic() + 30
    while any(_alive(pid) for pid in pids) and time.monotonic() < deadline:
        time.sleep(0.01)  # the ranks are not our children: wait until every thread is gone (and its file locks)


def _alive(pid: int) -> bool:
    """Has the process a thread that is not yet dead (a zombie leader may have live threads)?"""
    try:
        tasks = os.listdir(f"/proc/{pid}/task")
    except OSError:
        return False
    for tid in tasks:
        try:
            state = pathlib.Path(f"/proc/{pid}/task/{tid}/stat").read_text().rsplit(")", 1)[1].split()[0]
        except OSError:
            continue
        if state not in "ZX":
            return True
    return False


def _ckpt_step(path: pathlib.Path) -> int:
    try:
        with h5py.File(path, "r", locking=False) as f:
            return int(f.attrs["step"])
    except (OSError, KeyError):
        return -1


def _last_row_step(run: pathlib.Path) -> int:
    """The step of the last series row of a run file being written (-1 while unreadable)."""
    try:
        with h5py.File(run, "r", locking=False) as f:
            return int(f["series/step"][-1])
    except Exception:  # mid-write: try again
        return -1


def _wait(proc, condition, what: str, timeout: float = 120.0) -> None:
    t0 = time.monotonic()
    while not condition():
        if proc.poll() is not None:
            raise AssertionError(f"the run ended (status {proc.returncode}) before {what}: "
                                 f"{proc.stderr.read()[-2000:]}")
        if time.monotonic() - t0 > timeout:
            raise AssertionError(f"timed out waiting for {what}")
        time.sleep(0.005)


def _final(run: pathlib.Path) -> dict:
    with h5py.File(run) as f:
        assert f.attrs["status"] == "finished"
        last = f["snapshots"][sorted(f["snapshots"])[-1]]
        assert last.attrs["step"] == STEPS
        events = f["events/broken_bonds"][:]
        return dict(gid=last["gid"][:], x=last["x"][:], v=last["v"][:], w=last["w"][:], events=events,
                    broken={(int(a), int(b)) for a, b in events[:, 2:4]},
                    series={k: f["series"][k][:] for k in SERIES},
                    snapshot_steps=[int(f["snapshots"][k].attrs["step"]) for k in sorted(f["snapshots"])])


class Killed:
    """A run SIGKILLed after a checkpoint, its files saved at that moment, and the uninterrupted run."""

    def __init__(self, folder: pathlib.Path, ranks: int):
        self.folder, self.ranks = folder, ranks
        self.job = demo_job(folder)
        self.reference = folder / "reference.h5"
        _run(self.job, self.reference, ranks)
        self.run = folder / "killed.h5"
        ckpt = default_path(self.run)
        proc = _start(self.job, self.run, ranks)
        # a checkpoint exists and the run file has rows beyond it: those must not appear twice
        _wait(proc, lambda: (s := _ckpt_step(ckpt)) > 0 and _last_row_step(self.run) > s,
              "a checkpoint and a series row after it")
        _kill9(proc)
        assert proc.returncode == -signal.SIGKILL
        _check_readable(self.run, ckpt)
        self.ckpt = folder / "killed.ckpt.saved.h5"
        shutil.copy(ckpt, self.ckpt)
        self.saved_run = folder / "killed.saved.h5"
        shutil.copy(self.run, self.saved_run)
        self.step = _ckpt_step(self.ckpt)
        assert 0 < self.step < STEPS and self.step % CKPT_EVERY == 0
        assert _last_row_step(self.run) > self.step

    def restarted(self, ranks: int, name: str) -> pathlib.Path:
        """Continue a copy of the killed run's file from its checkpoint on ``ranks`` ranks."""
        run = self.folder / f"{name}.h5"
        shutil.copy(self.saved_run, run)
        _run(self.job, run, ranks, "--restart", self.ckpt)
        return run


@pytest.fixture(scope="module")
def killed1(tmp_path_factory):
    return Killed(tmp_path_factory.mktemp("one_rank"), 1)


@pytest.fixture(scope="module")
def killed2(tmp_path_factory):
    return Killed(tmp_path_factory.mktemp("two_ranks"), 2)


def _assert_bitwise(a: dict, b: dict) -> None:
    for key in ("gid", "x", "v", "w"):
        assert np.array_equal(a[key], b[key]), f"{key} differs: max {np.abs(a[key] - b[key]).max():.3g}"
    assert a["broken"] == b["broken"] and len(a["broken"]) > 10, "the run must include fracture"
    assert np.array_equal(a["events"], b["events"])  # the same log, each break once, in the same order
    for key in SERIES:  # every row once (none recorded twice around the restart), identical
        assert np.array_equal(a["series"][key], b["series"][key]), key
    assert a["snapshot_steps"] == b["snapshot_steps"]


def _assert_close(a: dict, b: dict) -> None:
    assert np.array_equal(a["gid"], b["gid"])
    assert np.abs(a["x"] - b["x"]).max() < 1e-9
    assert a["broken"] == b["broken"] and len(a["broken"]) > 10
    assert np.array_equal(a["series"]["step"], b["series"]["step"])
    assert a["snapshot_steps"] == b["snapshot_steps"]


def test_restart_after_sigkill_is_bitwise_on_one_rank(killed1):
    _assert_bitwise(_final(killed1.restarted(1, "restarted")), _final(killed1.reference))


def test_restart_after_sigkill_is_bitwise_on_two_ranks(killed2):
    _assert_bitwise(_final(killed2.restarted(2, "restarted")), _final(killed2.reference))


def test_restart_on_another_rank_count_agrees_within_1e9(killed1, killed2):
    ref1, ref2 = _final(killed1.reference), _final(killed2.reference)
    one_to_two = _final(killed1.restarted(2, "on_two"))
    two_to_one = _final(killed2.restarted(1, "on_one"))
    for result in (one_to_two, two_to_one):
        _assert_close(result, ref1)
        _assert_close(result, ref2)
    with h5py.File(killed1.folder / "on_two.h5") as f:
        assert f.attrs["ranks"] == 2 and f.attrs["restarts"] == 1


def _check_readable(run: pathlib.Path, ckpt: pathlib.Path) -> tuple[int, int]:
    """The run file opens, its datasets are whole and of consistent lengths; the checkpoint reads."""
    with h5py.File(run, "r") as f:
        lengths = {k: f["series"][k].shape[0] for k in f["series"]}
        assert len(set(lengths.values())) <= 1, lengths
        rows = next(iter(lengths.values()), 0)
        for k in f["series"]:
            assert np.all(np.isfinite(f["series"][k][()]))
        steps = f["series/step"][()] if rows else np.zeros(0)
        assert np.all(np.diff(steps) > 0)
        for name in f["snapshots"]:
            g = f["snapshots"][name]
            if "step" not in g.attrs:  # the group being created when the run was killed
                continue
            data = {k: g[k][()] for k in g}
            n = len(data.get("gid", ()))
            for k in ("x", "v", "w"):
                if k in data:
                    assert data[k].shape == (n, 3)
        assert f["events/broken_bonds"].shape[1] == 5
        f["events/broken_bonds"][()]
    data = read_checkpoint(ckpt)
    n = int(data["attrs"]["n_particles"])
    assert all(len(a) == n for a in data["particles"].values())
    assert np.all(np.diff(data["particles"]["gid"]) > 0)
    return int(data["attrs"]["step"]), int(rows)


def test_sigkill_at_random_moments_leaves_run_file_and_checkpoint_readable(tmp_path):
    """Snapshots, series rows and checkpoints written all the time; killed at random moments."""
    job = demo_job(tmp_path, "busy", steps=1400, ckpt_every=100, series_every=10, snapshots=40)
    rng = random.Random(5)
    trials = 4
    for pair in range(trials // 2):  # two at a time (this machine has two cores)
        runs = [tmp_path / f"busy{pair}{k}.h5" for k in range(2)]
        procs = [_start(job, run, 1) for run in runs]
        for run, proc in zip(runs, procs):
            _wait(proc, lambda: default_path(run).exists(), "the first checkpoint")
        deadline = [time.monotonic() + rng.uniform(0.0, 1.5) for _ in procs]
        for d, proc in sorted(zip(deadline, procs), key=lambda t: t[0]):
            time.sleep(max(0.0, d - time.monotonic()))
            assert proc.poll() is None, f"the run ended ({proc.returncode}) before it was killed: {proc.stderr.read()}"
            _kill9(proc)
        for run in runs:
            step, rows = _check_readable(run, default_path(run))
            assert step >= 100 and rows > 0
    # the last one continues to the end from its checkpoint, without rows recorded twice
    last = runs[-1]
    quiet = demo_job(tmp_path, "quiet", steps=1400, ckpt_every=0, series_every=10, snapshots=40)
    _run(quiet, last, 1, "--restart", default_path(last))
    with h5py.File(last) as f:
        steps = f["series/step"][()]
        assert f.attrs["status"] == "finished"
        assert np.array_equal(steps, np.arange(0, 1401, 10))
        assert len(f["snapshots"]) == 40
        assert len({tuple(e) for e in f["events/broken_bonds"][:, 2:4]}) == len(f["events/broken_bonds"])


def test_sigint_writes_a_final_checkpoint_and_exits_130(killed1, tmp_path):
    run = tmp_path / "interrupted.h5"
    job = killed1.job
    proc = _start(job, run, 1)
    _wait(proc, lambda: _last_row_step(run) >= 700, "series rows past step 700")
    proc.send_signal(signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err[-2000:]
    assert "interrupted at step" in err and "--restart" in err
    ckpt = default_path(run)
    step, _ = _check_readable(run, ckpt)
    assert not pathlib.Path(str(ckpt) + ".tmp").exists()
    with h5py.File(run) as f:
        assert f.attrs["status"] == "interrupted"
        assert f["series/step"][-1] <= step < STEPS
    # on one rank the interrupted run continues exactly as if never stopped
    _run(job, run, 1, "--restart", ckpt)
    _assert_bitwise(_final(run), _final(killed1.reference))


# -- in-process checks (serial) --------------------------------------------------------------------

TINY = {
    "run": {"duration": 0.02, "dt": 2e-4, "series_every": 10, "snapshots": 2},
    "water": {"density": 1035.0, "current": [1.0, 0.0]},
    "ice": {"length": 6.0, "width": 4.0, "velocity": [1.0, 0.0]},
    "bond": {"normal_stiffness": 1.72e7, "normal_strength": 1.5e6, "friction": 0.3},
    "walls": [{"name": "slope", "type": "plane", "point": [6.53, 0.0, 0.0],
               "normal": [-0.7071068, 0.0, 0.7071068]}],
}


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
