"""Pieces of the run file's writer (io/run_file.py): a block of series rows appended at once, a
snapshot's small arrays, and what a restart drops (the series rows, broken-bond events and
snapshots recorded after its checkpoint's step)."""

from __future__ import annotations

import h5py
import numpy as np


def append_rows(series: h5py.Group, rows: list[dict[str, np.ndarray]], first: int, *, values: bool = True) -> None:
    """Write ``rows`` (float64 arrays by key) as rows first, first + 1, ... of /series/<key>: one
    resize and one write per dataset for the block. A key first seen in a later row gets its
    dataset then, zeros before it (as row-by-row writing gave). ``values`` False: the datasets are
    created and resized only (the ranks other than 0 of a parallel write, which make the same
    metadata calls)."""
    for key in dict.fromkeys(key for row in rows for key in row):
        present = [(k, row[key]) for k, row in enumerate(rows) if key in row]
        shape = present[0][1].shape
        if key not in series:
            series.create_dataset(key, shape=(0, *shape), maxshape=(None, *shape), dtype="f8",
                                  chunks=(256, *shape) if all(shape) else True)
        ds = series[key]
        last = first + present[-1][0] + 1
        ds.resize(last, axis=0)
        if not values:
            continue
        if len(present) == len(rows):  # the usual case: every row has every key
            ds[first:last] = np.stack([value for _, value in present])
        else:
            for k, value in present:
                ds[first + k] = value


def drop_after(series: h5py.Group, events: h5py.Dataset, snapshots: h5py.Group, step: int) -> int:
    """Drop the series rows, broken-bond events and snapshots recorded after ``step``; returns the
    rows kept. A crash may have left the series datasets at unequal lengths: their common part is
    kept."""
    rows = min((ds.shape[0] for ds in series.values()), default=0)
    if "step" in series:  # steps increase row by row
        rows = int(np.searchsorted(series["step"][:rows], step, side="right"))
    for ds in series.values():
        ds.resize(rows, axis=0)
    old = events[()]
    keep = old[:, 0] <= step
    if not keep.all():
        events.resize(int(keep.sum()), axis=0)
        events[:] = old[keep]
    for name in list(snapshots):
        if snapshots[name].attrs.get("step", np.inf) > step:
            del snapshots[name]
    return rows


def write_extras(g: h5py.Group, extras: dict | None, mine: bool) -> None:
    """Rank 0's small arrays into snapshot group ``g`` (in mpio mode every rank creates them)."""
    for name, value in (extras or {}).items():
        value = np.asarray(value)
        ds = g.create_dataset(name, shape=value.shape, dtype=value.dtype)
        if mine and value.size:
            ds[...] = value
