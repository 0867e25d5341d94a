"""The run file's refusals (issue 5): a denied path or a full disk is a clear OutputError naming the
path and the fix, on one rank and on two, through mpio and gathered writes; nothing written before
is lost, and an existing file is never replaced without --overwrite.

A full disk is a small tmpfs (root and mount(8), else the test skips). The 2-rank tests run under
``mpiexec -n 2 python -m pytest -m io tests``, through mpio in the parallel-HDF5 environment
(``bash mpi/setup_parallel_hdf5.sh``); elsewhere the mpio ones skip and say why.
"""

from __future__ import annotations

import pathlib
import sys
import types

import h5py
import numpy as np
import pytest
from launch import need_two_ranks, on_ranks, run_cmd, serial_only, tiny_tmpfs
from scenes import contract_job, slope_job

from pice.cli import main
from pice.io.errors import OutputError
from pice.io.mpio import MODE_ENV
from pice.io.run_file import RunFile
from pice.job import load_job
from pice.parallel.comm import SerialComm
from pice.runner import run_job

pytestmark = pytest.mark.io

JOB = types.SimpleNamespace(text="# synthetic\n", source="synthetic.toml")


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
    serial_only()
    job = tmp_path / "tiny.toml"
    job.write_text(slope_job(duration=0.1, snapshots=3))
    assert main(["run", str(job), "-o", "/proc/forbidden.h5"]) == 4
    err = capsys.readouterr().err
    assert "/proc/forbidden.h5: cannot create the run file" in err and "-o" in err, err


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
    serial_only()
    job = load_job(contract_job(tmp_path))
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
    job = load_job(contract_job(tmp))
    out = disk / "run.h5"
    res = run_cmd(on_ranks(ranks, [sys.executable, "-c", _CHILD, "run", job.source, "-o", out]), expect=4,
              **{MODE_ENV: mode})
    assert f"{out}: writing" in res.stderr and "No space left on device" in res.stderr, res.stderr[-3000:]
    assert "disk is full" in res.stderr and "Traceback" not in res.stderr, res.stderr[-3000:]
    _check_kept(out)
    return res.returncode


def test_full_disk_inside_hdf5_exits_cleanly(tmp_path):
    serial_only()
    with tiny_tmpfs(tmp_path / "disk", "400k") as disk:
        assert _hdf5_meets_a_full_disk(tmp_path / "job", disk, 1) == 4  # exit status of OutputError


# ------------------------------------------------------------------------------------------ 2 ranks


@pytest.mark.mpi
@pytest.mark.timeout(120)
def test_mpio_never_replaces_an_existing_file(tmp_out):
    comm = need_two_ranks(mpio=True)
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
    comm = need_two_ranks(mpio=mode == "mpio")
    monkeypatch.setenv(MODE_ENV, mode)
    job = load_job(contract_job(tmp_out / f"job{comm.rank}"))
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
    comm = need_two_ranks(mpio=mode == "mpio")
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
