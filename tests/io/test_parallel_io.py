"""Parallel HDF5 output (issue 5): the mpio file and the gathered file hold the same data, bit for bit,
whether the ranks write their own rows or pass them on; the write mode is chosen from h5py and
PICE_HDF5_MODE.

The 2-rank tests need h5py built against a parallel HDF5 and run in the environment that
``bash mpi/setup_parallel_hdf5.sh`` builds (.ci/run does so after the main suite)::

    .venv-phdf5/bin/mpiexec -n 2 .venv-phdf5/bin/python -m pytest -m io tests

Elsewhere (the project venv's h5py has no MPI) they skip and say why. The serial tests run in the
main suite too. A denied path and a full disk: tests/io/test_output_errors.py.
"""

from __future__ import annotations

import types

import h5py
import numpy as np
import pytest
from launch import need_two_ranks
from scenes import barge_job, contract_job

from pice.io import mpio
from pice.io.mpio import MODE_ENV, choose_mode
from pice.io.errors import OutputError
from pice.io.run_file import RunFile
from pice.job import load_job
from pice.parallel.comm import SerialComm
from pice.runner import run_job

pytestmark = pytest.mark.io

JOB = types.SimpleNamespace(text="# synthetic\n", source="synthetic.toml")
#: series datasets that hold wall-clock times: they differ between any two runs
WALL_CLOCK = ("wall_time", "elapsed")


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
    depth = rng.uniform(0.0, 0.3, n)
    i = rng.integers(0, n, 4 * n)
    j = rng.integers(0, n, 4 * n)
    keep = gids[i] < gids[j]
    pairs = np.unique(np.stack([gids[i][keep], gids[j][keep]], axis=1), axis=0)
    pairs = pairs[rng.permutation(len(pairs))]
    owner_of = dict(zip(gids.tolist(), owner.tolist()))
    bond_owner = np.array([owner_of[a] for a in pairs[:, 0]])
    perm = rng.permutation(n)   # the ranks hold their particles in no particular order
    gids, owner, x, v, w, radius, kind, depth = (a[perm] for a in (gids, owner, x, v, w, radius, kind, depth))
    parts = []
    for r in range(size):
        mine = owner == r
        parts.append(dict(gid=gids[mine], x=x[mine], v=v[mine], w=w[mine], radius=radius[mine], kind=kind[mine],
                          crush_depth=depth[mine], bonds=pairs[bond_owner == r]))
    events = [[(10 * r + k, 0.5 * k, float(k), float(k + r + 1), 1.0) for k in range(r + 2)] for r in range(size)]
    return parts[rank], parts, events


@pytest.mark.mpi
@pytest.mark.timeout(300)
@pytest.mark.parametrize("runs", ["few", "many"])
@pytest.mark.parametrize("dense,empty_rank", [(True, False), (False, False), (True, True)])
def test_mpio_writes_what_the_gathered_write_writes(tmp_out, monkeypatch, runs, dense, empty_rank):
    """Made-up arrays through both writers: every dataset bit for bit, whether the ranks write their
    own runs of rows (few runs) or first pass them to the owners of contiguous blocks (many)."""
    comm = need_two_ranks(mpio=True)
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
    comm = need_two_ranks(mpio=True)

    job = load_job(contract_job(tmp_out / f"job{comm.rank}"))
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
    """The moored barge of tests/scenes.py (rank 0's body poses, line polylines and hull
    meshes in the snapshots, platform series) written through mpio and gathered: bit for bit."""
    comm = need_two_ranks(mpio=True)

    path = tmp_out / f"moored{comm.rank}.toml"
    path.write_text(barge_job(duration=0.03, series_every=50, current=1.0, drag=1.0, mooring="dem"))
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


