"""The HDF5 run file: attributes, a per-step time series, snapshots and the broken-bond log.

Layout::

    /                 attrs: job_text, job_source, pice_version, commit, ranks, units, started, status
                     (a restart adds restarts, restarted_from, restart_step, restart_commit)
    /series/<name>    one row per recorded step (resizable; io/series_rows.py)
    /snapshots/NNNNN  attrs time, step; datasets gid, x, v, w, radius, kind, crush_depth (the largest
                      plastic penetration of the element's contacts, m), bonds (m,2 gids)
                      [+ point_index, bond_index when the gids are not 0..n-1: xdmf.point_index_arrays]
                      [+ body_pose (n_bodies,13: x, q, v, omega), mooring_x (k,3), mooring_line (k,)
                       when the job has [[bodies]] / [[moorings]]; snapshot 0 also holds each hull
                       in its body frame: hull<k>_vertices, hull<k>_triangles]
    /events/broken_bonds  (k,5) float64 rows: step, time, gid_a, gid_b, mode (1 tension/bending,
                          2 shear/twist, 3 compression, 4 crushed through: kernels.bonds)

A run that stops keeps every row (RunFile.append_series). During a run io/output.py drives this
writer; io/run_reader.py reads the file back.

Parallel runs write the same file in one of two modes (io/mpio.py): every rank through h5py's
``mpio`` driver when h5py has MPI, else rank 0 alone from gathered arrays. A write that fails (a
full disk, a denied path) raises OutputError naming the path and what to do, on every rank alike;
what was flushed before stays in the file, and an existing file is never replaced without
``overwrite``.
"""

from __future__ import annotations

import contextlib
import datetime
import errno
import io
import os
import pathlib
import sys

import h5py
import numpy as np

from .. import __version__
from ..provenance import commit_label
from . import disk
from .xdmf import point_index_arrays
from .errors import OutputError
from .mpio import RUNS_DIRECT, count_runs, placement, to_blocks, write_rows
from .series_rows import append_rows, drop_after, write_extras

UNITS = "SI: m, s, kg, N, N m, J, Pa; angles in rad"
SERIES_BLOCK = 64   # series rows held before they are written together (RunFile.append_series)


class RunFile:
    """Writer of one run's HDF5 file.

    Serial (``comm`` None or of size 1): one process writes; snapshot arrays and events are the
    whole run's (rank 0 of a gathered run). Parallel (``comm`` of size > 1, h5py with MPI, see
    io/mpio.py): every rank constructs it and calls every method in the same order; series rows
    may differ between ranks (rank 0's are written), snapshot arrays and events are the rank's own.
    """

    comm = None          # the communicator of the mpio mode (None: serial)
    rank = 0
    failed = None        # the OutputError message of a failed write (then close() stays quiet)
    broken = False       # a write failed inside HDF5: the file cannot be flushed or closed any more

    def __init__(self, path: str | os.PathLike, *, job, overwrite: bool = False, ranks: int = 1,
                 extra_attrs: dict | None = None, comm=None):
        self.path = pathlib.Path(path)
        self.h5 = None
        self._pending = []  # series rows not yet written (append_series)
        if comm is not None and comm.size > 1:
            self.comm, self.rank = comm, comm.rank
        refusal = disk.refusal(self.path, overwrite) if self.rank == 0 else None
        if self.comm:
            refusal = self.comm.bcast(refusal)
        if refusal:
            raise OutputError(refusal)
        reason = None
        try:
            if self.comm:  # collective; "w" only after the overwrite check above
                self.h5 = h5py.File(self.path, "w", driver="mpio", comm=self.comm.h5py_comm())
            else:
                self.h5 = h5py.File(self.path, "w")
        except OSError as exc:
            reason = disk.reason(exc)
        reason = self._agree(reason)
        if reason:
            self._drop()
            raise OutputError(f"{self.path}: cannot create the run file ({reason}); choose a writable path "
                              "with -o")
        # commit: the code that made the run (pice/provenance.py; "" outside git), read on rank 0 only
        commit = commit_label() if self.rank == 0 else ""
        attrs = dict(job_text=job.text, job_source=job.source, pice_version=__version__, commit=commit, ranks=ranks,
                     units=UNITS, started=datetime.datetime.now(datetime.timezone.utc).isoformat(),
                     status="running", **(extra_attrs or {}))
        if self.comm:  # the same attribute values on every rank (the clocks differ)
            attrs = self.comm.bcast(attrs)

        def start():
            for k, v in attrs.items():
                self.h5.attrs[k] = v
            self.series = self.h5.create_group("series")
            self.snapshots = self.h5.create_group("snapshots")
            self.events = self.h5.create_dataset("events/broken_bonds", shape=(0, 5), maxshape=(None, 5),
                                                 dtype="f8", chunks=(1024, 5))

        try:
            self._write("the run file's attributes", start, need=disk.nbytes(job.text.encode()))
            self._write("the run file's attributes", self.h5.flush)
        except OutputError:
            self.close("failed")  # quiet: self.failed is set (collective: every rank failed alike)
            raise
        self.rows = 0

    # -- failure handling: every rank learns of a failure on any rank, and raises the same error --

    def _agree(self, reason: str | None) -> str | None:
        """The first failure reason of any rank, on every rank (collective in the mpio mode)."""
        if self.comm is None:
            return reason
        if not self.comm.max(1 if reason else 0):
            return None
        reasons = self.comm.gather(reason)
        return self.comm.bcast(next(r for r in reasons if r) if self.comm.rank == 0 else None)

    def _write(self, what: str, fn, need: int | None = None) -> None:
        """Run ``fn`` (h5py calls); on any rank's failure raise OutputError on every rank.

        ``need``: bytes the write adds; with less than ``need + disk.SPACE_MARGIN`` free on the file's
        disk it is not attempted (the file stays whole and closes normally)."""
        if self.failed:
            raise self._error
        if need is not None:
            short = None
            if self.rank == 0:
                free = disk.free_bytes(self.path.parent)
                if free is not None and free < need + disk.SPACE_MARGIN:
                    short = (f"{os.strerror(errno.ENOSPC)}: {free / 2**20:.3g} MiB free, about "
                             f"{(need + disk.SPACE_MARGIN) / 2**20:.3g} MiB needed")
            short = self._agree(short)
            if short:
                self.failed = (f"{self.path}: writing {what} stopped ({short}); {disk.hint(short)}. What was "
                               "written before is kept in the file.")
                self._error = OutputError(self.failed)
                raise self._error
        reason = None
        ignored = []  # h5py reports a failed H5Dclose (a dataset object let go) as "Exception ignored"
        previous = sys.unraisablehook
        sys.unraisablehook = lambda u: (ignored.append(u.exc_value) if isinstance(u.exc_value, (OSError, RuntimeError))
                                        else previous(u))
        h5py_says = io.StringIO()  # ... after printing its traceback: shown only if it was not that
        try:
            with contextlib.redirect_stderr(h5py_says):
                fn()
        except (OSError, RuntimeError) as exc:
            reason = disk.reason(exc)
        finally:
            sys.unraisablehook = previous
            if h5py_says.getvalue() and not ignored:
                sys.stderr.write(h5py_says.getvalue())
        if ignored and not reason:  # then a flush would crash inside HDF5: stop here
            reason = disk.reason(ignored[0])
        reason = self._agree(reason)
        if reason:
            self.broken = True
            self.failed = (f"{self.path}: writing {what} failed ({reason}); {disk.hint(reason)}. What was written "
                           "before is kept in the file.")
            self._error = OutputError(self.failed)
            self._error.hard_exit = True
            raise self._error

    def _drop(self) -> None:
        """Forget the file without collective calls (HDF5 closes it when the process ends)."""
        if self.h5 is not None:
            _ABANDONED.append(self.h5)  # no garbage-collected close on one rank alone
        self.h5 = None

    def abandon(self) -> None:
        """Stop writing without closing collectively: for a failure that not every rank has seen.
        Everything flushed stays in the file; its status attribute stays "running"."""
        self._drop()

    # -- writing --

    def append_series(self, row: dict) -> None:
        """Append one row; each key becomes /series/<key> with shape (rows, *value.shape). Rows are held
        and written SERIES_BLOCK at a time (row by row: ~9 ms each on the buoy's 40 series), and before
        every snapshot, checkpoint and close: a run that fails or stops keeps every row; a killed one
        loses only rows after its last checkpoint, which its restart records again."""
        self._pending.append(row)  # mpio mode: every rank appends (rank 0's rows count), so all agree
        if len(self._pending) >= SERIES_BLOCK:
            self.write_series()

    def write_series(self) -> None:
        """Write the rows held by ``append_series`` (collective in the mpio mode)."""
        rows, self._pending = self._pending, []
        if not rows or self.failed:
            return
        if self.comm:  # rank 0 holds the reduced values; every rank makes the same metadata calls
            rows = self.comm.bcast(rows)
        rows = [{key: np.asarray(value, dtype=np.float64) for key, value in row.items()} for row in rows]
        first = self.rows

        def write():
            append_rows(self.series, rows, first, values=self.rank == 0)

        what = f"series rows {first}-{first + len(rows) - 1}"
        # the block may start a new 256-row chunk in every dataset
        self._write(what, write, need=(256 + len(rows)) * disk.nbytes(*rows[0].values()))
        self._write(what, self.h5.flush)
        self.rows += len(rows)

    def append_events(self, events: list) -> None:
        """Append broken-bond events (step, time, gid_a, gid_b, mode).

        Serial: the run's new events, sorted. mpio mode (collective): each rank's own new events."""
        if self.comm:
            parts = self.comm.gather(list(events))
            events = sorted(e for part in parts for e in part) if self.rank == 0 else []
            count = self.comm.bcast(len(events))
        else:
            count = len(events)
        if not count:
            return
        arr = np.asarray(events, dtype=np.float64)

        def write():
            n0 = self.events.shape[0]
            self.events.resize(n0 + count, axis=0)
            if self.rank == 0:
                self.events[n0:] = arr

        self._write("broken-bond events", write, need=(count + 1024) * 5 * 8)

    def write_snapshot_arrays(self, index: int, *, time: float, step: int, arrays: dict,
                              extras: dict | None = None) -> None:
        """Particles sorted by gid (gid, x, v, w, radius, kind) and intact bonds as sorted gid pairs.

        Serial: the whole run's arrays. mpio mode (collective): this rank's owned particles and the
        bonds whose lower-gid end it owns; each lands at its place in the gid-sorted datasets.
        ``extras``: small arrays held by rank 0 (body poses, mooring nodes), written as they are."""
        self.write_series()
        if self.comm:
            self._write_snapshot_mpio(index, time=time, step=step, arrays=arrays, extras=extras)
            return
        need = 2 * disk.nbytes(*arrays.values(), *(extras or {}).values())  # x2: the index arrays
        self._write(f"snapshot {index}", lambda: self._write_snapshot_serial(index, time, step, arrays, extras),
                    need=need)
        self._write(f"snapshot {index}", self.h5.flush)

    def _write_snapshot_mpio(self, index: int, *, time: float, step: int, arrays: dict,
                             extras: dict | None = None) -> None:
        comm = self.comm
        gid = np.asarray(arrays["gid"])
        bonds = np.asarray(arrays["bonds"]).reshape(-1, 2)
        order, rows, border, brows, n, m, gids = placement(comm, gid, bonds)
        fields = {name: np.asarray(arrays[name])[order] for name in _PARTICLE_FIELDS}
        fields["bonds"] = bonds[border]
        # rank 0's time, step, dtypes and extra arrays: metadata calls must be identical everywhere
        extra = None
        if self.rank == 0:
            extra = point_index_arrays(gids, np.zeros((0, 2), dtype=np.int64))
        need_all_bonds = comm.bcast(bool(extra))
        if need_all_bonds:  # gids are not 0..n-1 (not so far): rank 0 derives the index arrays
            parts = comm.gather(fields["bonds"])
            if self.rank == 0:
                b = np.concatenate(parts)
                extra = point_index_arrays(gids, b[np.lexsort((b[:, 1], b[:, 0]))] if len(b) else b)
        spec = {k: (a.dtype.str, a.shape[1:]) for k, a in fields.items()}
        time, step, spec, extra_spec, extras = comm.bcast(
            (time, step, spec, {k: (a.dtype.str, a.shape) for k, a in (extra or {}).items()}, extras))
        fields = {k: np.ascontiguousarray(a, dtype=np.dtype(spec[k][0])) for k, a in fields.items()}
        direct = comm.max(max(count_runs(rows), count_runs(brows))) <= RUNS_DIRECT
        if not direct:  # many runs: first give every rank one contiguous block of rows
            rows, moved = to_blocks(comm, rows, [fields[k] for k in _PARTICLE_FIELDS], n)
            fields.update(zip(_PARTICLE_FIELDS, moved))
            brows, (fields["bonds"],) = to_blocks(comm, brows, [fields["bonds"]], m)

        def write():
            g = self.snapshots.create_group(f"{index:05d}")
            g.attrs["time"] = time
            g.attrs["step"] = step
            for name, (dt, tail) in spec.items():
                total = m if name == "bonds" else n
                ds = g.create_dataset(name, shape=(total, *tail), dtype=np.dtype(dt))
                if total:
                    write_rows(ds, brows if name == "bonds" else rows, fields[name])
            for name, (dt, shape) in extra_spec.items():
                ds = g.create_dataset(name, shape=shape, dtype=np.dtype(dt))
                if shape[0]:
                    mine = self.rank == 0
                    write_rows(ds, np.arange(shape[0] if mine else 0),
                               extra[name] if mine else np.zeros((0, *shape[1:]), dtype=np.dtype(dt)))
            write_extras(g, extras, self.rank == 0)

        need = 2 * disk.nbytes(*fields.values())
        need = int(self.comm.sum(float(need)))
        self._write(f"snapshot {index}", write, need=need)
        self._write(f"snapshot {index}", self.h5.flush)

    def _write_snapshot_serial(self, index: int, time: float, step: int, arrays: dict, extras=None) -> None:
        order = np.argsort(arrays["gid"], kind="stable")
        g = self.snapshots.create_group(f"{index:05d}")
        g.attrs["time"] = time
        g.attrs["step"] = step
        for name in _PARTICLE_FIELDS:
            g.create_dataset(name, data=arrays[name][order])
        bonds = arrays["bonds"].reshape(-1, 2)
        bonds = bonds[np.lexsort((bonds[:, 1], bonds[:, 0]))] if len(bonds) else bonds
        g["bonds"] = bonds
        for name, data in point_index_arrays(arrays["gid"][order], bonds).items():
            g[name] = data
        write_extras(g, extras, True)

    @classmethod
    def open_for_restart(cls, path: str | os.PathLike, *, step: int, job=None, ranks: int = 1,
                         restarted_from: str = "") -> "RunFile":
        """Reopen a run file to continue it from a checkpoint of ``step``.

        Keeps every row recorded up to that step and drops the series rows, broken-bond events and
        snapshots recorded after it (the restarted run records them again, so none appears twice).
        A crash may have left the series datasets at unequal lengths: their common part is kept.
        """
        self = cls.__new__(cls)
        self.path = pathlib.Path(path)
        self._pending = []
        if not self.path.is_file():
            raise OutputError(f"{self.path}: run file not found; --restart continues the run file of the run "
                              "that wrote the checkpoint: give it with -o")
        try:
            self.h5 = h5py.File(self.path, "r+")
        except OSError as exc:
            raise OutputError(f"{self.path}: cannot open the run file to continue it ({exc.strerror or exc})") from None
        self.series = self.h5.require_group("series")
        self.snapshots = self.h5.require_group("snapshots")
        if "events/broken_bonds" not in self.h5:
            self.h5.create_dataset("events/broken_bonds", shape=(0, 5), maxshape=(None, 5), dtype="f8",
                                   chunks=(1024, 5))
        self.events = self.h5["events/broken_bonds"]
        self.rows = drop_after(self.series, self.events, self.snapshots, step)
        a = self.h5.attrs
        a["status"] = "running"
        a["ranks"] = ranks
        a["restarts"] = int(a.get("restarts", 0)) + 1
        a["restarted_from"] = str(restarted_from)
        a["restart_step"] = step
        a["restart_commit"] = commit_label()  # the code that continued it (commit: the one that started it)
        if job is not None and a.get("job_text") != job.text:
            a["job_text"] = job.text
        self.h5.flush()
        return self

    def flush(self) -> None:
        """Push everything written so far to the file (before a checkpoint refers to it)."""
        if self.h5:
            self.write_series()
            self._write("the run file", self.h5.flush)

    def close(self, status: str = "finished") -> None:
        """Record the status and close (collective in the mpio mode). After a failed write it only
        closes, quietly: the error that is already on its way is the one to report."""
        if not self.h5:
            return
        if self.broken:  # HDF5 would fail again, or crash: leave the file as last flushed
            self._drop()
            return
        unwritten = None  # the held rows' write failed: close what is there, then report that
        try:
            self.write_series()  # (nothing after an earlier failed write: self.failed)
        except OutputError as exc:
            unwritten = exc
            if self.broken:
                self._drop()
                raise
        ended = datetime.datetime.now(datetime.timezone.utc).isoformat()
        if self.comm:
            status, ended = self.comm.bcast((status, ended))
        reason = None
        try:
            self.h5.attrs["status"] = status
            self.h5.attrs["ended"] = ended
        except (OSError, RuntimeError) as exc:
            reason = disk.reason(exc)
        try:
            self.h5.close()
        except (OSError, RuntimeError) as exc:
            reason = reason or disk.reason(exc)
        self.h5 = None
        reason = self._agree(reason)
        if unwritten is not None:
            raise unwritten
        if reason and not self.failed:
            self.failed = f"{self.path}: closing the run file failed ({reason}); {disk.hint(reason)}"
            raise OutputError(self.failed)


_PARTICLE_FIELDS = ("gid", "x", "v", "w", "radius", "kind", "crush_depth")


_ABANDONED: list = []   # files dropped by RunFile.abandon (see there)
