"""Restart after a kill (issue 5): a killed run, restarted from its last checkpoint, ends where an
uninterrupted run ends -- bit for bit on the same rank count, within 1e-9 m on another -- and a
SIGKILL at any moment leaves the run file and the last checkpoint readable. Issue 13 added kills
while bonds are breaking and while elements are crushing (the restart crosses both).

The job is the contract test's fracturing demo (tests/scenes.py, contract_job) for 2,400 steps
with a checkpoint every 600 steps. Runs are real `pice run` processes (1 rank, or `mpiexec -n 2`),
killed with SIGKILL (every process of the MPI job) or interrupted with SIGINT. The in-process
checkpoint checks are in tests/io/test_checkpoint.py.
"""

from __future__ import annotations

import pathlib
import random
import re
import shutil
import signal
import time

import h5py
import numpy as np
import pytest
from launch import kill9_if, pice_run, run_cmd, start
from scenes import contract_job, crushing_face_job

from pice.io.checkpoint import default_path, read_checkpoint

DT = 1.4e-4
STEPS = 2400
CKPT_EVERY = 600
SERIES = ("time", "step", "bonds", "broken_bonds", "contacts", "kinetic_energy", "total_energy", "wall_force")


def demo_job(folder: pathlib.Path, name: str = "ckpt", *, steps: int = STEPS, ckpt_every: int = CKPT_EVERY,
             series_every: int = 100, snapshots: int = 3) -> pathlib.Path:
    """The contract test's job for ``steps`` steps with a checkpoint every ``ckpt_every`` (0: none)."""
    return contract_job(folder, name, dt=DT, duration=steps * DT, checkpoint_every=ckpt_every * DT,
                        series_every=series_every, snapshots=snapshots)


def _run(job, out, ranks, *extra):
    return run_cmd(pice_run(job, out, ranks, *extra))


def _start(job, out, ranks):
    return start(pice_run(job, out, ranks))


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
        _still_running(proc, t0, what, timeout)
        time.sleep(0.005)


def _kill_when(proc, condition, what: str, timeout: float = 120.0) -> None:
    """SIGKILL the run when ``condition()`` holds, checked again with the run stopped (kill9_if)."""
    t0 = time.monotonic()
    while not (condition() and kill9_if(proc, condition)):
        _still_running(proc, t0, what, timeout)
        time.sleep(0.005)


def _still_running(proc, t0: float, what: str, timeout: float) -> None:
    if proc.poll() is not None:
        raise AssertionError(f"the run ended (status {proc.returncode}) before {what}: "
                             f"{proc.stderr.read()[-2000:]}")
    if time.monotonic() - t0 > timeout:
        raise AssertionError(f"timed out waiting for {what}")


def _final(run: pathlib.Path, steps: int = STEPS) -> dict:
    with h5py.File(run) as f:
        assert f.attrs["status"] == "finished"
        last = f["snapshots"][sorted(f["snapshots"])[-1]]
        assert last.attrs["step"] == steps
        events = f["events/broken_bonds"][:]
        return dict(gid=last["gid"][:], x=last["x"][:], v=last["v"][:], w=last["w"][:], events=events,
                    broken={(int(a), int(b)) for a, b in events[:, 2:4]},
                    series={k: f["series"][k][:] for k in SERIES},
                    snapshot_steps=[int(f["snapshots"][k].attrs["step"]) for k in sorted(f["snapshots"])])


class Killed:
    """A run SIGKILLed after a checkpoint, its files saved at that moment, and the uninterrupted run."""

    def __init__(self, folder: pathlib.Path, ranks: int, job: pathlib.Path | None = None):
        self.folder, self.ranks = folder, ranks
        self.job = job or demo_job(folder)
        self.reference = folder / "reference.h5"
        self.reference_log = _run(self.job, self.reference, ranks).stderr
        self.run = folder / "killed.h5"
        ckpt = default_path(self.run)
        proc = _start(self.job, self.run, ranks)
        # a checkpoint exists and the run file has rows beyond it: those must not appear twice
        _kill_when(proc, lambda: (s := _ckpt_step(ckpt)) > 0 and _last_row_step(self.run) > s,
                   "a checkpoint and a series row after it")
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


def test_restart_under_balance_by_work_is_bitwise_on_two_ranks(tmp_path):
    """``balance_by = "work"`` (physics/work.py) moves the cuts from the state alone, so a restarted run
    must move them as the run never killed did. The fracturing demo on 2 ranks with the work checked
    every 400 steps and a threshold of 1.001 moves its cuts before its checkpoints (the reference run's
    log says so, and where); killed after a checkpoint and restarted, it ends bit for bit as that run."""
    job = demo_job(tmp_path)
    text = job.read_text().replace("[parallel]\nbalance_every = 400\n",
                                   '[parallel]\nbalance_every = 400\nbalance_by = "work"\nimbalance_threshold = 1.001\n')
    assert 'balance_by = "work"' in text
    job.write_text(text)
    killed = Killed(tmp_path, 2, job)
    moves = [int(m) for m in re.findall(r"step (\d+): load balance of the modelled work", killed.reference_log)]
    assert moves and min(moves) < killed.step, (moves, killed.step)  # the cuts moved before the checkpoint
    _assert_bitwise(_final(killed.restarted(2, "restarted")), _final(killed.reference))


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


def test_sigkill_at_random_steps_leaves_run_file_and_checkpoint_readable(tmp_path):
    """Snapshots, series rows and checkpoints written all the time; killed at random steps.

    Each run is killed at a step, not at a time: after a randomly chosen checkpoint (step 200 to 700
    of 1,400; one every 100 steps) and a random number of series rows past it (0 to 9; one every 10
    steps), both read from the files the run writes: the checkpoint's ``step`` attribute (it is
    written to a temporary name and renamed, so the final path always holds a whole one) and the
    run file's last row (read without locking; a row being written counts as not there yet). Why:
    this test used to kill at a random time (0 to 1.5 s after the first checkpoint), and on a loaded
    machine it sometimes found the run already finished. Now at least 600 steps (~8 s of this run
    here) remain after the latest kill point, and the run cannot pass that point unseen: the kill
    comes within a poll (5 ms) of the step it was chosen for."""
    job = demo_job(tmp_path, "busy", steps=1400, ckpt_every=100, series_every=10, snapshots=40)
    rng = random.Random(5)
    trials = 4
    for pair in range(trials // 2):  # two at a time (this machine has two cores)
        runs = [tmp_path / f"busy{pair}{k}.h5" for k in range(2)]
        targets = [(100 * rng.randint(2, 7), 10 * rng.randint(0, 9)) for _ in runs]
        procs = [_start(job, run, 1) for run in runs]
        waiting = set(range(len(procs)))
        while waiting:
            for k in sorted(waiting):
                ckpt_step, extra = targets[k]
                proc, run = procs[k], runs[k]
                assert proc.poll() is None, f"the run ended ({proc.returncode}) before it was killed: {proc.stderr.read()}"
                def reached(run=run, ckpt_step=ckpt_step, extra=extra):
                    return _ckpt_step(default_path(run)) >= ckpt_step and _last_row_step(run) >= ckpt_step + extra
                if reached() and kill9_if(proc, reached):
                    waiting.discard(k)
            time.sleep(0.005)
        for run, (ckpt_step, _) in zip(runs, targets):
            step, rows = _check_readable(run, default_path(run))
            assert ckpt_step <= step < 1400 and rows > 0
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


# -- restarts through fracture and crushing (issue 13, case 7) -------------------------------------

# 10 m x 6 m of 1 m plate cells driven at 4 m/s onto a vertical face that crushes ice at 1 MPa: the
# contacts at the face are in plastic flow from step ~200, and front elements are crushed through
# (removed, their bonds logged as mode 4) during its 2,500 steps (~3 s on one rank here).
CRUSHING_JOB = crushing_face_job(
    length=10.0, width=6.0, d=1.0, speed=4.0, stiffness=2.0e7, structure="1.0e6",
    run="duration = 0.4\ndt = 1.6e-4\nseries_every = 25\nsnapshots = 2\ncheckpoint_every = 0.016")


def _kill_at_checkpoint(job: pathlib.Path, run: pathlib.Path, wanted: set[int]) -> int:
    """Start `pice run JOB -o RUN` on one rank and SIGKILL it as soon as its latest checkpoint is one
    of the ``wanted`` steps (read from the checkpoint's step attribute every 5 ms: it is renamed into
    place whole). The wanted steps are consecutive checkpoints, so the kill has hundreds of steps to
    land in; returns the step of the checkpoint the killed run leaves."""
    proc = _start(job, run, 1)
    _kill_when(proc, lambda: _ckpt_step(default_path(run)) in wanted, f"a checkpoint at one of the steps {sorted(wanted)}")
    step = _ckpt_step(default_path(run))
    assert step in wanted, (step, sorted(wanted))
    return step


@pytest.mark.slow  # three runs of the demo (~1 min here)
def test_restart_through_fracture_is_bitwise(tmp_path):
    """The fracturing demo (600 steps, a checkpoint every 25; 31 bonds break between steps 207 and
    381) is killed at a checkpoint taken while bonds are breaking: some broken before it, more
    breaking after it. Restarted from it on the same rank count, it ends bit for bit as the run that
    was never killed: positions, velocities, spins, every series row once, the same broken set and
    the same break log in the same order."""
    steps, every = 600, 25
    job = demo_job(tmp_path, "fracture", steps=steps, ckpt_every=every, series_every=25, snapshots=3)
    reference = tmp_path / "reference.h5"
    _run(job, reference, 1)
    with h5py.File(reference) as f:
        breaks = f["events/broken_bonds"][:, 0]
    during = {c for c in range(every, steps, every) if (breaks <= c).any() and (breaks > c).any()}
    assert len(during) >= 4, f"the demo must break over several checkpoints: breaks at steps {sorted(set(breaks))}"
    run = tmp_path / "killed.h5"
    step = _kill_at_checkpoint(job, run, during)
    broken = int(read_checkpoint(default_path(run))["counters"]["broken"].sum())
    assert broken == (breaks <= step).sum() and 0 < broken < len(breaks)
    _run(job, run, 1, "--restart", default_path(run))
    _assert_bitwise(_final(run, steps), _final(reference, steps))


@pytest.mark.slow  # three runs of the crushing scene (~1 min here)
def test_restart_through_crushing_is_bitwise(tmp_path):
    """The crushing scene above is killed at a checkpoint taken while its front is crushing (contacts
    in plastic flow, their plastic penetration in the checkpoint), after the first elements were
    crushed through and before the next. Restarted on the same rank count, it ends bit for bit as
    the run never killed: the same elements left (gids), positions, velocities, spins, series rows
    (crushed elements and plastic contacts included) and broken set, crushed bonds (mode 4) too."""
    job = tmp_path / "crushing.toml"
    job.write_text(CRUSHING_JOB)
    steps, every = 2500, 100
    reference = tmp_path / "reference.h5"
    _run(job, reference, 1)
    with h5py.File(reference) as f:
        events = f["events/broken_bonds"][()]
        row = {int(k): r for k, r in zip(f["series/step"][()], f["series/crushing_contacts"][()])}
        crushed = f["series/crushed_elements"][()]
    crushed_at = events[events[:, 4] == 4, 0]
    during = {c for c in range(every, steps, every)
              if row[c][1] > 0 and (crushed_at <= c).any() and (crushed_at > c).any()}
    assert len(during) >= 4 and crushed[-1] > 0, f"crushed through at steps {sorted(set(crushed_at))}"
    run = tmp_path / "killed.h5"
    step = _kill_at_checkpoint(job, run, during)
    _run(job, run, 1, "--restart", default_path(run))
    a, b = _final(run, steps), _final(reference, steps)
    assert len(a["gid"]) < 60  # elements were removed (57 at the start)
    _assert_bitwise(a, b)
    with h5py.File(run) as f, h5py.File(reference) as g:
        for key in ("crushed_elements", "crushing_contacts"):
            assert np.array_equal(f["series"][key][()], g["series"][key][()]), key
    assert step in during
