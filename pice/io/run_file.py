"""The HDF5 run file: attributes, a per-step time series, snapshots and the broken-bond log.

Layout::

    /                 attrs: job_text, job_source, pice_version, ranks, units, started, status
    /series/<name>    one row per recorded step (resizable, flushed as written)
    /snapshots/NNNNN  attrs time, step; datasets gid, x, v, w, radius, kind, bonds (m,2 gids)
    /events/broken_bonds  (k,5) float64 rows: step, time, gid_a, gid_b, mode (1 tension/bending, 2 shear)

Rows are flushed as they are written, so a run that stops keeps everything recorded until then.
"""

from __future__ import annotations

import datetime
import os
import pathlib

import h5py
import numpy as np

from .. import __version__
from ..errors import PiceError

UNITS = "SI: m, s, kg, N, N m, J, Pa; angles in rad"


class OutputError(PiceError):
    """The run file cannot be created or written. Exit status 4."""

    exit_code = 4


class RunFile:
    """Writer of one run's HDF5 file (serial; a parallel writer joins in the output issue)."""

    def __init__(self, path: str | os.PathLike, *, job, overwrite: bool = False, ranks: int = 1,
                 extra_attrs: dict | None = None):
        self.path = pathlib.Path(path)
        if self.path.exists() and not overwrite:
            raise OutputError(f"{self.path}: already exists; pass --overwrite to replace it or choose "
                              "another output with -o")
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            self.h5 = h5py.File(self.path, "w")
        except OSError as exc:
            raise OutputError(f"{self.path}: cannot create the run file ({exc.strerror or exc}); "
                              "choose a writable path with -o") from None
        a = self.h5.attrs
        a["job_text"] = job.text
        a["job_source"] = job.source
        a["pice_version"] = __version__
        a["ranks"] = ranks
        a["units"] = UNITS
        a["started"] = datetime.datetime.now(datetime.timezone.utc).isoformat()
        a["status"] = "running"
        for k, v in (extra_attrs or {}).items():
            a[k] = v
        self.series = self.h5.create_group("series")
        self.snapshots = self.h5.create_group("snapshots")
        self.events = self.h5.create_dataset("events/broken_bonds", shape=(0, 5), maxshape=(None, 5),
                                             dtype="f8", chunks=(1024, 5))
        self.rows = 0

    def append_series(self, row: dict) -> None:
        """Append one row; each key becomes /series/<key> with shape (rows, *value.shape)."""
        for key, value in row.items():
            value = np.asarray(value, dtype=np.float64)
            if key not in self.series:
                self.series.create_dataset(key, shape=(0, *value.shape), maxshape=(None, *value.shape),
                                           dtype="f8", chunks=(256, *value.shape) if all(value.shape) else True)
            ds = self.series[key]
            ds.resize(self.rows + 1, axis=0)
            ds[self.rows] = value
        self.rows += 1
        self.h5.flush()

    def append_events(self, events: list) -> None:
        """Append broken-bond events (step, time, gid_a, gid_b, mode)."""
        if not events:
            return
        arr = np.asarray(events, dtype=np.float64)
        n0 = self.events.shape[0]
        self.events.resize(n0 + len(arr), axis=0)
        self.events[n0:] = arr

    def write_snapshot_arrays(self, index: int, *, time: float, step: int, arrays: dict) -> None:
        """Particles sorted by gid (gid, x, v, w, radius, kind) and intact bonds as sorted gid pairs."""
        order = np.argsort(arrays["gid"], kind="stable")
        g = self.snapshots.create_group(f"{index:05d}")
        g.attrs["time"] = time
        g.attrs["step"] = step
        for name in ("gid", "x", "v", "w", "radius", "kind"):
            g.create_dataset(name, data=arrays[name][order])
        bonds = arrays["bonds"].reshape(-1, 2)
        g["bonds"] = bonds[np.lexsort((bonds[:, 1], bonds[:, 0]))] if len(bonds) else bonds
        self.h5.flush()

    def close(self, status: str = "finished") -> None:
        if self.h5:
            self.h5.attrs["status"] = status
            self.h5.attrs["ended"] = datetime.datetime.now(datetime.timezone.utc).isoformat()
            self.h5.close()
            self.h5 = None
