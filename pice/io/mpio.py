"""Parallel HDF5 for the run file: which write mode a run uses, and collective writes at global offsets.

Two modes write the same file:

* ``"gathered"``: rank 0 owns the file (h5py's default driver); series rows are reduced and snapshot
  arrays gathered to it. Used on one rank, and on more when h5py was built without MPI.
* ``"mpio"``: every rank opens the file with h5py's ``mpio`` driver and makes the same metadata
  calls; each rank writes its own particles and bonds at their places in the gid-sorted datasets.

``PICE_HDF5_MODE=gathered`` forces the gathered mode (for comparisons); ``=mpio`` insists on the
mpio mode and fails when h5py has no MPI; unset or ``auto`` picks mpio whenever it can.

Where each particle goes: the ranks' gid ranges interleave (x-y cuts through a lattice numbered
row by row), so rank 0 gathers only the gids (8 bytes a particle) and each particle's count of
bonds it is the lower end of, sorts them, and scatters back every rank's target rows. A rank then
writes all its rows of a dataset in ONE collective H5Dwrite whose file selection is the union of
its contiguous runs of target rows (few: a rank's particles are whole stretches of lattice rows).
"""

from __future__ import annotations

import os

import h5py
import numpy as np
from h5py import h5fd, h5p, h5s

from .errors import OutputError

MODE_ENV = "PICE_HDF5_MODE"


def h5py_has_mpi() -> bool:
    """True when this h5py was built against a parallel HDF5 (it has the mpio driver)."""
    return bool(h5py.get_config().mpi)


def choose_mode(comm) -> str:
    """The write mode of a run on ``comm``: "mpio" or "gathered" (the same on every rank)."""
    want = os.environ.get(MODE_ENV, "auto").strip().lower() or "auto"
    if want not in ("auto", "gathered", "mpio"):
        raise OutputError(f"{MODE_ENV}={want!r}: expected auto, gathered or mpio")
    if comm.size == 1 or want == "gathered":
        return "gathered"
    if not h5py_has_mpi():
        if want == "mpio":
            raise OutputError(f"{MODE_ENV}=mpio, but this h5py has no MPI support (it was not built against "
                              "a parallel HDF5); build an environment that has it with "
                              "`bash mpi/setup_parallel_hdf5.sh`, or unset " + MODE_ENV)
        return "gathered"
    return "mpio"


def exclusive_scan(counts) -> np.ndarray:
    """Offsets of consecutive blocks of the given sizes: [0, c0, c0+c1, ...] without the total."""
    counts = np.asarray(counts, dtype=np.int64)
    out = np.zeros(len(counts), dtype=np.int64)
    np.cumsum(counts[:-1], out=out[1:])
    return out


def _collective_dxpl():
    dxpl = h5p.create(h5p.DATASET_XFER)
    dxpl.set_dxpl_mpio(h5fd.MPIO_COLLECTIVE)
    return dxpl


def write_rows(ds: h5py.Dataset, rows: np.ndarray, data: np.ndarray, *, collective: bool = True) -> None:
    """Write ``data[k]`` to row ``rows[k]`` of ``ds`` (rows strictly increasing) in one H5Dwrite.

    Under the mpio driver with ``collective=True`` every rank must call this once per dataset, with
    or without rows (a rank with none selects nothing and still takes part).
    """
    rows = np.asarray(rows, dtype=np.int64)
    tail = tuple(ds.shape[1:])
    data = np.ascontiguousarray(data, dtype=ds.dtype).reshape((len(rows),) + tail)
    fspace = ds.id.get_space()
    if len(rows):
        if np.any(np.diff(rows) <= 0):
            raise ValueError("write_rows: target rows must be strictly increasing")
        cut = np.flatnonzero(np.diff(rows) != 1) + 1
        starts = np.concatenate([[0], cut])
        stops = np.concatenate([cut, [len(rows)]])
        zeros = (0,) * len(tail)
        op = h5s.SELECT_SET
        for a, b in zip(starts, stops):
            fspace.select_hyperslab((int(rows[a]),) + zeros, (int(b - a),) + tail, op=op)
            op = h5s.SELECT_OR
        mspace = h5s.create_simple(data.shape)
    else:
        fspace.select_none()
        data = np.zeros((1,) + tail, dtype=ds.dtype)
        mspace = h5s.create_simple(data.shape)
        mspace.select_none()
    ds.id.write(mspace, fspace, data, dxpl=_collective_dxpl() if collective else None)


#: a rank writes its own rows directly while no rank has more contiguous runs of target rows than
#: this; past it (HDF5 1.10 builds a union of n hyperslabs in O(n^2): 5,000 runs 1 s, 25,000 runs
#: 97 s), the rows are first sent to the rank whose contiguous block of the dataset holds them
RUNS_DIRECT = 2000


def count_runs(rows: np.ndarray) -> int:
    """Number of maximal runs of consecutive integers in the increasing array ``rows``."""
    return int(len(rows) and 1 + np.count_nonzero(np.diff(rows) != 1))


def _row_bytes(a: np.ndarray) -> np.ndarray:
    a = np.ascontiguousarray(a)
    width = a.dtype.itemsize * int(np.prod(a.shape[1:], dtype=np.int64))
    return a.view(np.uint8).reshape(len(a), width)


def to_blocks(comm, rows: np.ndarray, fields: list, total: int):
    """Send each row (``rows[k]`` with ``f[k]`` of every field) to the rank whose contiguous block of
    ``total`` rows holds it (rank r: rows r*total//size .. (r+1)*total//size - 1). Collective.

    Returns (block_rows, block_fields), sorted by row: exactly this rank's block. The bytes travel
    unchanged (every dtype arrives bit for bit).
    """
    rows = np.asarray(rows, dtype=np.int64)
    bounds = (np.arange(comm.size + 1, dtype=np.int64) * total) // comm.size
    dest = np.searchsorted(bounds, rows, side="right") - 1          # nondecreasing: rows increase
    cols = [_row_bytes(rows)] + [_row_bytes(f) for f in fields]
    widths = [c.shape[1] for c in cols]
    width = sum(widths)
    pad = -width % 8
    packed = np.concatenate(cols + [np.zeros((len(rows), pad), np.uint8)], axis=1)
    per_row = (width + pad) // 8
    sendcounts = np.bincount(dest, minlength=comm.size).astype(np.int64) * per_row
    recv, _ = comm.exchange_doubles(packed.view(np.float64).ravel(), sendcounts)
    recv = np.ascontiguousarray(recv).view(np.uint8).reshape(-1, width + pad)
    edges = np.concatenate([[0], np.cumsum(widths)])
    got_rows = recv[:, edges[0]:edges[1]].copy().view(np.int64).ravel()
    order = np.argsort(got_rows, kind="stable")
    lo, hi = bounds[comm.rank], bounds[comm.rank + 1]
    if not np.array_equal(got_rows[order], np.arange(lo, hi, dtype=np.int64)):
        raise RuntimeError(f"to_blocks: rank {comm.rank} received rows that do not make up its block {lo}..{hi}")
    out = []
    for k, f in enumerate(fields, start=1):
        part = recv[order, edges[k]:edges[k + 1]].copy()
        out.append(part.view(f.dtype).reshape((len(order),) + tuple(f.shape[1:])))
    return got_rows[order], out


def placement(comm, gid: np.ndarray, bonds: np.ndarray):
    """Where this rank's particles and bonds go in the gid-sorted snapshot datasets (collective).

    ``gid``: this rank's particles (any order); ``bonds``: (m,2) gid pairs, lower gid first, each
    listed by the rank holding its lower-gid particle (as ``Particles.intact_bonds`` gives them).
    Returns (order, rows, border, brows, n_total, m_total, gids) where ``gid[order]`` and
    ``bonds[border]`` go to rows ``rows`` and ``brows`` (both increasing); ``gids`` is the sorted
    gid array of all ranks on rank 0 (None elsewhere). The order of equal gids (and equal pairs) is
    the one the gathered write gives: by rank, then by position on the rank.
    """
    gid = np.asarray(gid, dtype=np.int64)
    bonds = np.asarray(bonds, dtype=np.int64).reshape(-1, 2)
    order = np.argsort(gid, kind="stable")
    gs = gid[order]
    border = np.lexsort((bonds[:, 1], bonds[:, 0])) if len(bonds) else np.zeros(0, dtype=np.int64)
    bs = bonds[border]
    # each bond belongs to the sorted particle that is its lower end (first with that gid)
    owner = np.searchsorted(gs, bs[:, 0])
    if len(bs) and (np.any(owner >= len(gs)) or np.any(gs[np.minimum(owner, len(gs) - 1)] != bs[:, 0])):
        raise ValueError("placement: a bond's lower-gid particle is not on the rank that lists the bond")
    cnt = np.bincount(owner, minlength=len(gs)).astype(np.int64)
    parts = comm.gather((gs, cnt))
    gids = None
    if comm.rank == 0:
        g_all = np.concatenate([p[0] for p in parts])
        c_all = np.concatenate([p[1] for p in parts])
        perm = np.argsort(g_all, kind="stable")
        rows_all = np.empty(len(g_all), dtype=np.int64)
        rows_all[perm] = np.arange(len(g_all), dtype=np.int64)
        boff_all = np.empty(len(g_all), dtype=np.int64)
        boff_all[perm] = exclusive_scan(c_all[perm])
        n_tot, m_tot = len(g_all), int(c_all.sum())
        cuts = np.cumsum([len(p[0]) for p in parts])[:-1]
        out = [(r, b, n_tot, m_tot) for r, b in zip(np.split(rows_all, cuts), np.split(boff_all, cuts))]
        gids = g_all[perm]
    else:
        out = None
    rows, boff, n_tot, m_tot = comm.scatter(out)
    # bonds of one particle are consecutive in bs (sorted by lower gid, then partner)
    first = exclusive_scan(cnt)
    brows = boff[owner] + (np.arange(len(bs), dtype=np.int64) - first[owner])
    return order, rows, border, brows, int(n_tot), int(m_tot), gids
