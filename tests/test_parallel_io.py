"""Parallel HDF5 output (issue 5): the mpio file and the gathered file hold the same data; a denied
path or a full disk is a clear OutputError naming the path and the fix; nothing written before is lost.

The 2-rank tests need h5py built against a parallel HDF5 and run in the environment that
``bash mpi/setup_parallel_hdf5.sh`` builds (.ci/run does so after the main suite)::

    .venv-phdf5/bin/mpiexec -n 2 .venv-phdf5/bin/python -m pytest -m io tests

Elsewhere (the project venv's h5py has no MPI) they skip and say why. The serial tests run in the
main suite too.
"""

from __future__ import annotations

import contextlib
import os
import pathlib
import shutil
import subprocess
import sys
import types

import h5py
import numpy as np
import pytest
from launcher import clean_env as _clean_env

from pice.io import mpio
from pice.io.mpio import MODE_ENV, choose_mode, h5py_has_mpi
from pice.io.errors import OutputError
from pice.io.run_file import RunFile
from pice.parallel.comm import SerialComm, world

from test_parallel_contract import contract_job

pytestmark = pytest.mark.io

JOB = types.SimpleNamespace(text="# synthetic\n", source="synthetic.toml")
#: series datasets that hold wall-clock times: they differ between any two runs
WALL_CLOCK = ("wall_time", "elapsed")


def _comm():
    return world()


def _need_mpio(mode="mpio"):
    comm = _comm()
    if comm.size < 2:
        pytest.skip("needs 2 MPI ranks: mpiexec -n 2 python -m pytest -m io tests")
    if mode == "mpio" and not h5py_has_mpi():
        pytest.skip("h5py has no MPI (h5py.get_config().mpi is False): run these in the parallel-HDF5 "
                    "environment, bash mpi/setup_parallel_hdf5.sh")
    return comm


def _serial_only():
    if _comm().size > 1:
        pytest.skip("serial test (it runs in the serial stage of mpi/run_tests.sh)")


def datasets(path, groups=("series", "snapshots", "events")) -> dict:
    """{name: (dtype, shape, bytes)} of every dataset under ``groups``, plus the snapshots' attributes."""
    out = {}
    with h5py.File(path, "r") as f:
        for grp in groups:
            if grp not in f:
                continue

            def visit(name, obj, grp=grp):
                if isinstance(obj, h5py.Dataset):
                    a = obj[()]
                    out[f"{grp}/{name}"] = (a.dtype.str, a.shape, a.tobytes())
                else:
                    out[f"{grp}/{name}@attrs"] = sorted((k, repr(v)) for k, v in obj.attrs.items())

            f[grp].visititems(visit)
    return {k: v for k, v in out.items() if not any(w in k for w in WALL_CLOCK)}


def assert_same_data(a, b):
    da, db = datasets(a), datasets(b)
    assert sorted(da) == sorted(db)
    for name in da:
        assert da[name] == db[name], f"{name} differs between {a} and {b}"


# ---------------------------------------------------------------------------------------- mode choice


class _Size2:
    rank, size = 0, 2


def test_mode_choice(monkeypatch):
    monkeypatch.delenv(MODE_ENV, raising=False)
    assert choose_mode(SerialComm()) == "gathered"
    monkeypatch.setattr(mpio, "h5py_has_mpi", lambda: True)
    assert choose_mode(_Size2()) == "mpio"
    monkeypatch.setenv(MODE_ENV, "gathered")
    assert choose_mode(_Size2()) == "gathered"
    monkeypatch.setattr(mpio, "h5py_has_mpi", lambda: False)
    monkeypatch.setenv(MODE_ENV, "auto")
    assert choose_mode(_Size2()) == "gathered"  # the clean fallback
    monkeypatch.setenv(MODE_ENV, "mpio")
    with pytest.raises(OutputError, match="setup_parallel_hdf5.sh"):
        choose_mode(_Size2())
    monkeypatch.setenv(MODE_ENV, "fast")
    with pytest.raises(OutputError, match="auto, gathered or mpio"):
        choose_mode(_Size2())


# ------------------------------------------------------------------------------------------ safety


def test_denied_path_is_a_clear_error(tmp_path):
    """Tests run as root, so a read-only folder would not deny: use /proc and a path under a file."""
    a_file = tmp_path / "notes.txt"
    a_file.write_text("a file, not a folder")
    for bad in (pathlib.Path("/proc/forbidden.h5"), a_file / "run.h5", a_file / "deeper" / "run.h5"):
        with pytest.raises(OutputError) as err:
            RunFile(bad, job=JOB)
        msg = str(err.value)
        assert str(bad) in msg and "-o" in msg, msg
        assert "Traceback" not in msg and "H5F" not in msg, msg
    assert a_file.read_text() == "a file, not a folder"
    with pytest.raises(OutputError, match="is a directory"):
        RunFile(tmp_path, job=JOB, overwrite=True)


def test_denied_path_from_the_command_line(tmp_path, capsys):
    _serial_only()
    from pice.cli import main

    job = tmp_path / "tiny.toml"
    from tiny_jobs import slope_job

    job.write_text(slope_job(duration=0.1, snapshots=3))
    assert main(["run", str(job), "-o", "/proc/forbidden.h5"]) == 4
    err = capsys.readouterr().err
    assert "/proc/forbidden.h5: cannot create the run file" in err and "-o" in err, err


@contextlib.contextmanager
def tiny_tmpfs(where: pathlib.Path, size: str):
    """A small tmpfs at ``where`` (root only); skips the test where mounting is not allowed."""
    where.mkdir(parents=True, exist_ok=True)
    if os.geteuid() != 0 or not shutil.which("mount"):
        pytest.skip("a full disk is simulated with a tmpfs, which needs root and mount(8)")
    res = subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size}", "tmpfs", str(where)],
                         capture_output=True, text=True)
    if res.returncode:
        pytest.skip(f"cannot mount a tmpfs here to simulate a full disk: {res.stderr.strip()}")
    try:
        yield where
    finally:
        subprocess.run(["umount", "-l", str(where)], capture_output=True)


def _contract(folder: pathlib.Path):
    """The contract job of test_parallel_contract (2,000 steps, fracture, a rebalance every 400)."""
    from pice.job import load_job

    folder.mkdir(parents=True, exist_ok=True)
    return load_job(contract_job(folder))


def _check_kept(path: pathlib.Path):
    """The run file of a run stopped by a full disk still opens, with the rows written before."""
    with h5py.File(path, "r") as f:
        t = f["series/time"][()]
        assert len(t) >= 1 and t[0] == 0.0 and np.all(np.diff(t) > 0)
        for name, ds in f["series"].items():
            assert ds.shape[0] >= len(t) - 1, name
        for name in f["snapshots"]:  # (the tmpfs sizes below let the first one or two in)
            g = f["snapshots"][name]
            if "bonds" in g:
                assert len(g["gid"][()]) > 0 and g["x"].shape == (len(g["gid"]), 3)


def test_full_disk_is_a_clear_error_and_keeps_what_was_written(tmp_path):
    _serial_only()
    from pice.runner import run_job

    job = _contract(tmp_path)
    with tiny_tmpfs(tmp_path / "disk", "640k") as disk:
        out = disk / "run.h5"
        with pytest.raises(OutputError) as err:
            run_job(job, output=out, comm=SerialComm(), progress=None)
        msg = str(err.value)
        assert str(out) in msg and "No space left on device" in msg and "disk is full" in msg, msg
        assert "-o" in msg and "kept" in msg, msg
        _check_kept(out)


_CHILD = """
import sys
import pice.io.disk as disk
disk.SPACE_MARGIN = -10**15   # no free-space check: HDF5 itself meets ENOSPC
from pice.cli import main
sys.exit(main(sys.argv[1:]))
"""


def _hdf5_meets_a_full_disk(tmp: pathlib.Path, disk: pathlib.Path, ranks: int, mode: str = "auto"):
    """`pice run` with the free-space check off, so that a write fails inside HDF5, which can then
    neither flush nor close the file (and would crash at exit): exit status 4, a one-line error,
    and the file as last flushed."""
    job = _contract(tmp)
    out = disk / "run.h5"
    cmd = [sys.executable, "-c", _CHILD, "run", str(job.source), "-o", str(out)]
    if ranks > 1:
        cmd = [str(pathlib.Path(sys.executable).parent / "mpiexec"), "-n", str(ranks)] + cmd
    res = subprocess.run(cmd, env={**_clean_env(), MODE_ENV: mode}, capture_output=True, text=True, timeout=600)
    assert res.returncode == 4, (res.returncode, res.stderr[-3000:])
    assert f"{out}: writing" in res.stderr and "No space left on device" in res.stderr, res.stderr[-3000:]
    assert "disk is full" in res.stderr and "Traceback" not in res.stderr, res.stderr[-3000:]
    _check_kept(out)
    return res.returncode


def test_full_disk_inside_hdf5_exits_cleanly(tmp_path):
    _serial_only()
    with tiny_tmpfs(tmp_path / "disk", "400k") as disk:
        assert _hdf5_meets_a_full_disk(tmp_path / "job", disk, 1) == 4  # exit status of OutputError


# --------------------------------------------------------------------------- the mpio writer, 2 ranks


def _synthetic(rank: int, size: int, *, n: int, dense: bool, empty_rank: bool, runs: str, seed=5):
    """Every rank's share of a made-up snapshot: interleaved gid ranges, bonds listed by the rank
    holding their lower gid, a rank with nothing when ``empty_rank``."""
    rng = np.random.default_rng(seed)
    gids = np.arange(n, dtype=np.int64) if dense else 3 * rng.permutation(n).astype(np.int64) + 7
    if runs == "few":   # stretches of 40 consecutive gids alternate between the ranks
        owner = (np.arange(n) // 40) % size
    else:               # every particle on a random rank: thousands of runs
        owner = rng.integers(0, size, n)
    if empty_rank:
        owner[owner == size - 1] = 0
    x, v, w = (rng.standard_normal((n, 3)) for _ in range(3))
    radius = rng.uniform(0.4, 0.6, n)
    kind = rng.integers(0, 3, n).astype(np.int8)
    i = rng.integers(0, n, 4 * n)
    j = rng.integers(0, n, 4 * n)
    keep = gids[i] < gids[j]
    pairs = np.unique(np.stack([gids[i][keep], gids[j][keep]], axis=1), axis=0)
    pairs = pairs[rng.permutation(len(pairs))]
    owner_of = dict(zip(gids.tolist(), owner.tolist()))
    bond_owner = np.array([owner_of[a] for a in pairs[:, 0]])
    perm = rng.permutation(n)   # the ranks hold their particles in no particular order
    gids, owner, x, v, w, radius, kind = (a[perm] for a in (gids, owner, x, v, w, radius, kind))
    parts = []
    for r in range(size):
        mine = owner == r
        parts.append(dict(gid=gids[mine], x=x[mine], v=v[mine], w=w[mine], radius=radius[mine], kind=kind[mine],
                          bonds=pairs[bond_owner == r]))
    events = [[(10 * r + k, 0.5 * k, float(k), float(k + r + 1), 1.0) for k in range(r + 2)] for r in range(size)]
    return parts[rank], parts, events


@pytest.mark.mpi
@pytest.mark.timeout(300)
@pytest.mark.parametrize("runs", ["few", "many"])
@pytest.mark.parametrize("dense,empty_rank", [(True, False), (False, False), (True, True)])
def test_mpio_writes_what_the_gathered_write_writes(tmp_out, monkeypatch, runs, dense, empty_rank):
    """Made-up arrays through both writers: every dataset bit for bit, whether the ranks write their
    own runs of rows (few runs) or first pass them to the owners of contiguous blocks (many)."""
    comm = _need_mpio()
    n = 2000 if runs == "few" else 6000
    mine, parts, events = _synthetic(comm.rank, comm.size, n=n, dense=dense, empty_rank=empty_rank, runs=runs)
    if runs == "many":  # ~1,500 runs a rank; take the block path even with a rank that has none
        monkeypatch.setattr(mpio, "RUNS_DIRECT", 0)
    tag = f"{runs}-{int(dense)}-{int(empty_rank)}"
    a, b = tmp_out / f"mpio-{tag}.h5", tmp_out / f"gathered-{tag}.h5"
    rows = [dict(time=0.0, step=0.0, energy=np.arange(3.0)), dict(time=0.1, step=10.0, energy=np.arange(3.0) + 1)]
    for row in rows:
        row["wall_force"] = np.ones((2, 3)) * row["time"]

    f = RunFile(a, job=JOB, ranks=comm.size, comm=comm)
    for k, row in enumerate(rows):
        # only rank 0's row counts (others lack the rank-0-reduced wall force, as in a real run)
        f.append_series(row if comm.rank == 0 else {key: v for key, v in row.items() if key != "wall_force"})
        f.append_events(events[comm.rank] if k == 1 else [])
        f.write_snapshot_arrays(k, time=row["time"], step=int(row["step"]), arrays=mine)
    f.close("finished")
    comm.barrier()
    if comm.rank == 0:
        g = RunFile(b, job=JOB, ranks=comm.size)
        for k, row in enumerate(rows):
            g.append_series(row)
            g.append_events(sorted(e for part in events for e in part) if k == 1 else [])
            g.write_snapshot_arrays(k, time=row["time"], step=int(row["step"]),
                                    arrays={key: np.concatenate([p[key] for p in parts]) for key in mine})
        g.close("finished")
        assert_same_data(a, b)
        with h5py.File(a) as fa:
            assert fa.attrs["status"] == "finished" and fa.attrs["ranks"] == comm.size
            assert ("point_index" in fa["snapshots/00000"]) == (not dense)
            assert len(fa["events/broken_bonds"]) == sum(len(e) for e in events)
    comm.barrier()


@pytest.mark.mpi
@pytest.mark.timeout(600)
def test_same_data_mpio_and_gathered_run(tmp_out, monkeypatch):
    """'Same data': the contract run (fracture, interleaved gid ranges, a rebalance) written through
    mpio and gathered on 2 ranks: every dataset of /series, /snapshots and /events bit for bit."""
    comm = _need_mpio()
    from pice.runner import run_job

    job = _contract(tmp_out / f"job{comm.rank}")
    outs = {}
    for mode in ("mpio", "gathered"):
        monkeypatch.setenv(MODE_ENV, mode)
        outs[mode] = tmp_out / f"{mode}.h5"
        summary = run_job(job, output=outs[mode], comm=comm, progress=None)
        assert summary["broken_bonds"] > 10
    comm.barrier()
    if comm.rank == 0:
        assert_same_data(outs["mpio"], outs["gathered"])
        with h5py.File(outs["mpio"]) as f:
            assert f.attrs["status"] == "finished" and f.attrs["ranks"] == 2
            assert len(f["events/broken_bonds"]) > 10 and len(f["snapshots"]) == 3
    comm.barrier()


@pytest.mark.mpi
@pytest.mark.timeout(600)
def test_same_data_mpio_and_gathered_with_a_platform(tmp_out, monkeypatch):
    """The moored barge of tests/test_platform_run.py (rank 0's body poses, line polylines and hull
    meshes in the snapshots, platform series) written through mpio and gathered: bit for bit."""
    comm = _need_mpio()
    from test_platform_run import job_text

    from pice.job import load_job
    from pice.runner import run_job

    path = tmp_out / f"moored{comm.rank}.toml"
    path.write_text(job_text(duration=0.03, series_every=50, current=1.0, drag=1.0, mooring="dem"))
    outs = {}
    for mode in ("mpio", "gathered"):
        monkeypatch.setenv(MODE_ENV, mode)
        outs[mode] = tmp_out / f"moored_{mode}.h5"
        run_job(load_job(path), output=outs[mode], comm=comm, progress=None)
    comm.barrier()
    if comm.rank == 0:
        assert_same_data(outs["mpio"], outs["gathered"])
        with h5py.File(outs["mpio"]) as f:
            assert "body_pose" in f["snapshots/00002"] and "hull0_vertices" in f["snapshots/00000"]
            assert f["series/fairlead_tension"].shape[1] == 4
    comm.barrier()


@pytest.mark.mpi
@pytest.mark.timeout(120)
def test_mpio_never_replaces_an_existing_file(tmp_out):
    comm = _need_mpio()
    out = tmp_out / "precious.h5"
    if comm.rank == 0:
        out.write_bytes(b"precious")
    comm.barrier()
    with pytest.raises(OutputError, match="--overwrite"):
        RunFile(out, job=JOB, ranks=2, comm=comm)
    assert out.read_bytes() == b"precious"
    comm.barrier()
    with pytest.raises(OutputError, match="-o"):   # a denied path: every rank raises, none hangs
        RunFile("/proc/forbidden.h5", job=JOB, ranks=2, comm=comm)
    f = RunFile(out, job=JOB, ranks=2, comm=comm, overwrite=True)
    f.close("finished")
    with h5py.File(out, "r") as h:
        assert h.attrs["status"] == "finished"


@pytest.mark.mpi
@pytest.mark.timeout(300)
@pytest.mark.parametrize("mode", ["mpio", "gathered"])
def test_full_disk_fails_on_every_rank_and_keeps_what_was_written(tmp_out, monkeypatch, mode):
    comm = _need_mpio(mode)
    monkeypatch.setenv(MODE_ENV, mode)
    from pice.runner import run_job

    job = _contract(tmp_out / f"job{comm.rank}")
    disk = tmp_out / "disk"
    skip = None
    if comm.rank == 0:
        try:
            ctx = tiny_tmpfs(disk, "640k")
            ctx.__enter__()
        except pytest.skip.Exception as exc:
            skip = str(exc)
    skip = comm.bcast(skip)
    if skip:
        pytest.skip(skip)
    try:
        out = disk / "run.h5"
        with pytest.raises(OutputError) as err:
            run_job(job, output=out, comm=comm, progress=None)
        msg = str(err.value)
        assert str(out) in msg and "disk is full" in msg and "kept" in msg, msg
        comm.barrier()
        if comm.rank == 0:
            _check_kept(out)
        comm.barrier()
    finally:
        if comm.rank == 0:
            ctx.__exit__(None, None, None)


@pytest.mark.mpi
@pytest.mark.timeout(600)
@pytest.mark.parametrize("mode", ["mpio", "gathered"])
def test_full_disk_inside_hdf5_exits_cleanly_on_2_ranks(tmp_out, mode):
    """As test_full_disk_inside_hdf5_exits_cleanly, on 2 ranks (rank 0 starts a separate 2-rank
    run; rank 1 waits): every rank exits with status 4, none hangs."""
    comm = _need_mpio(mode)
    outcome = None
    if comm.rank == 0:
        try:
            with tiny_tmpfs(tmp_out / "disk", "400k") as disk:
                _hdf5_meets_a_full_disk(tmp_out / "job", disk, 2, mode)
        except pytest.skip.Exception as exc:
            outcome = ("skip", str(exc))
        except BaseException as exc:  # report it on both ranks, not only here
            outcome = ("fail", f"{type(exc).__name__}: {exc}")
    outcome = comm.bcast(outcome)
    if outcome and outcome[0] == "skip":
        pytest.skip(outcome[1])
    assert outcome is None, outcome[1]
