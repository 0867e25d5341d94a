"""Reading a run file back: the one reader behind `pice export`, `pice plot`, `pice study`, the XDMF
file and the summary `pice run` prints (the writer is io/run_file.py; the layout is described there).

::

    with open_run("runs/x.h5") as run:
        run.snapshots                 # ["00000", "00001", ...], in order
        run.snapshot(-1)["x"][()]     # a snapshot group (by index or name), run.time(k) its time [s]
        run.series("wall_force")      # a whole /series dataset, None when the run has none
        run.broken_bonds()            # /events/broken_bonds: (k,5) step, time, gid_a, gid_b, mode
        run.job                       # the job stored in the file, parsed again (on first use)
        run.wall_triangles()          # the job's walls as triangles, run.damage(k) per element

A missing or unreadable file is a RunFileError (exit status 5) naming it. The job is parsed only
when something asks for it, so reading series costs no job validation.
"""

from __future__ import annotations

import logging
import os
import pathlib
import sys
from dataclasses import dataclass, field

import h5py
import numpy as np

from .errors import RunFileError

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

log = logging.getLogger("pice")


@dataclass
class Run:
    """An open run file (use as a context manager; it closes the file)."""

    path: pathlib.Path
    h5: h5py.File
    snapshots: list[str]                 # group names under /snapshots, in order
    _job: tuple | None = field(default=None, repr=False)       # (job, job_dir, wall_index), parsed on use
    _initial: tuple | None = field(default=None, repr=False)
    _extent: np.ndarray | None = field(default=None, repr=False)

    def __enter__(self):
        return self

    def __exit__(self, *_):
        self.close()

    def close(self) -> None:
        self.h5.close()

    # -- attributes, series, events --

    @property
    def attrs(self) -> h5py.AttributeManager:
        """The root attributes: job_text, job_source, pice_version, ranks, units, status, dt, ..."""
        return self.h5.attrs

    def series_names(self) -> list[str]:
        """Names of the /series datasets (sorted)."""
        return sorted(self.h5["series"]) if "series" in self.h5 else []

    def series(self, name: str) -> np.ndarray | None:
        """The whole /series/<name> dataset (rows first), or None when the run has no such series."""
        s = self.h5.get("series")
        return s[name][()] if s is not None and name in s else None

    def broken_bonds(self) -> np.ndarray:
        """The broken-bond log, (k,5) rows of step, time, gid_a, gid_b, mode (1 tension/bending, 2 shear)."""
        return self.h5["events/broken_bonds"][()] if "events/broken_bonds" in self.h5 else np.zeros((0, 5))

    # -- snapshots --

    def snapshot(self, key: str | int) -> h5py.Group:
        """A snapshot group by index (negative from the end) or by name ("00003")."""
        return self.h5["snapshots"][self.snapshots[key] if isinstance(key, int) else key]

    def time(self, key) -> float:
        return float(self.snapshot(key).attrs["time"])

    def initial_bond_counts(self) -> tuple[np.ndarray, np.ndarray]:
        """(gid, number of bonds) per element in the first snapshot: the element's initial bonds."""
        if self._initial is None:
            g = self.snapshot(0)
            gid = g["gid"][()]
            self._initial = (gid, bond_counts(gid, g["bonds"][()]))
        return self._initial

    def damage(self, key) -> np.ndarray:
        """Per element of snapshot ``key``: the fraction of its initial bonds that are broken."""
        g = self.snapshot(key)
        gid = g["gid"][()]
        return bond_damage(gid, g["bonds"][()], *self.initial_bond_counts())

    def ice_extent(self) -> np.ndarray:
        """(2,3) bounding box of the ice over the first and last snapshots."""
        if self._extent is None:
            xs = [self.snapshot(k)["x"][()] for k in {0, len(self.snapshots) - 1}]
            xs = np.concatenate([x for x in xs if len(x)]) if any(len(x) for x in xs) else np.zeros((1, 3))
            self._extent = np.array([xs.min(axis=0), xs.max(axis=0)])
        return self._extent

    # -- the job stored in the file --

    @property
    def job(self):
        """pice.job.Job parsed from the job_text attribute (None when the file has none)."""
        return self._job_info()[0]

    @property
    def job_dir(self) -> pathlib.Path | None:
        """The folder the job's relative paths (mesh walls) resolve in."""
        return self._job_info()[1]

    @property
    def wall_index(self) -> list[int]:
        """The [[walls]] index of each of ``job.walls`` (a mesh wall whose file is missing is left out)."""
        return self._job_info()[2]

    def _job_info(self) -> tuple:
        if self._job is None:
            self._job = _job_of(self.h5, self.path)
        return self._job

    def wall_names(self) -> list[str]:
        """Name of each [[walls]] entry (as the series' wall axis), from the job text."""
        if not self.h5.attrs.get("job_text", ""):
            return []
        walls = tomllib.loads(self.h5.attrs["job_text"]).get("walls", ())
        return [w.get("name") or f"wall{k}" for k, w in enumerate(walls)]

    def wall_triangles(self) -> tuple[np.ndarray, np.ndarray]:
        """(k,3,3) triangles [m] of the job's walls and (k,) the index of the [[walls]] entry of each.

        A plane is a square patch around its point that covers the ice extent; a mesh wall is read
        as the run read it (physics/walls.py through io/mesh.py)."""
        from ..physics.walls import read_wall_mesh

        job = self.job
        if job is None or not job.walls:
            return np.zeros((0, 3, 3)), np.zeros(0, np.int64)
        box = self.ice_extent()
        corners = np.array([[box[i, 0], box[j, 1], box[k, 2]] for i in (0, 1) for j in (0, 1) for k in (0, 1)])
        tris, owner = [], []
        for wall, k in zip(job.walls, self.wall_index):
            if wall.type == "plane":
                p = np.asarray(wall.point, float)
                nrm = np.asarray(wall.normal, float)
                nrm /= np.linalg.norm(nrm)
                a = np.array([1.0, 0.0, 0.0]) if abs(nrm[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
                u = np.cross(nrm, a)
                u /= np.linalg.norm(u)
                w = np.cross(nrm, u)
                h = max(float(np.max(np.linalg.norm(corners - p, axis=1))), 1.0)
                c = [p + h * (su * u + sw * w) for su, sw in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
                new = [np.array([c[0], c[1], c[2]]), np.array([c[0], c[2], c[3]])]
            elif wall.type == "triangle":
                new = [np.asarray(wall.vertices, float)]
            else:
                new = read_wall_mesh(self.job_dir or pathlib.Path("."), wall.file, job.source, k)
            tris += new
            owner += [k] * len(new)
        return np.asarray(tris, float).reshape(-1, 3, 3), np.asarray(owner, np.int64)


def open_run(path: str | os.PathLike) -> Run:
    """Open a run file for reading; raise RunFileError with a clear message if it cannot be read."""
    path = pathlib.Path(path)
    if not path.is_file():
        raise RunFileError(f"{path}: no such run file (give the .h5 written by `pice run`)")
    try:
        h5 = h5py.File(path, "r")
    except OSError as exc:
        raise RunFileError(f"{path}: not a readable HDF5 run file ({exc})") from None
    snaps = sorted(h5["snapshots"]) if "snapshots" in h5 else []
    return Run(path=path, h5=h5, snapshots=snaps)


def _job_of(h5: h5py.File, run_path: pathlib.Path):
    """The job stored in the run file, parsed again, the folder its relative paths resolve in, and
    the [[walls]] index of each of its walls: a mesh wall whose file is not found is left out (with
    a warning) so the rest still exports."""
    from ..job import parse_job

    text = h5.attrs.get("job_text", "")
    if not text:
        return None, None, []
    source = str(h5.attrs.get("job_source", "<job>"))
    data = tomllib.loads(text)
    src = pathlib.Path(source)
    candidates = [src.parent] if src.is_absolute() else [src.parent, run_path.parent / src.parent, run_path.parent]
    walls = list(data.get("walls", ()))
    meshes = [w.get("file", "") for w in walls if w.get("type") == "mesh"]
    base = next((c for c in candidates if all((c / m).is_file() for m in meshes)), candidates[0])
    index = []
    for k, w in enumerate(walls):
        if w.get("type") == "mesh" and not (base / w.get("file", "")).is_file():
            log.warning("%s: walls[%d].file = %r not found beside the job %s: that wall is left out",
                        run_path, k, w.get("file"), source)
        else:
            index.append(k)
    data["walls"] = [walls[k] for k in index]
    return parse_job(data, source=source, text=text, base_dir=base), base, index


# ------------------------------------------------------------------------------------------------
# Derived fields


def bond_counts(gid: np.ndarray, bonds: np.ndarray) -> np.ndarray:
    """Number of intact bonds of each element (``gid`` sorted; ``bonds`` (m,2) gid pairs)."""
    if len(gid) == 0:
        return np.zeros(0, np.int64)
    idx = np.searchsorted(gid, np.asarray(bonds, np.int64).reshape(-1))
    return np.bincount(idx, minlength=len(gid)).astype(np.int64)


def bond_damage(gid, bonds, initial_gid, initial_counts) -> np.ndarray:
    """Fraction of each element's initial bonds that are broken (0 for an element that had none)."""
    now = bond_counts(gid, bonds)
    idx = np.searchsorted(initial_gid, gid)
    idx = np.minimum(idx, max(len(initial_gid) - 1, 0))
    init = np.where((len(initial_gid) > 0) & (initial_gid[idx] == gid), initial_counts[idx], 0) if len(gid) else now
    with np.errstate(invalid="ignore", divide="ignore"):
        dmg = np.where(init > 0, 1.0 - now / np.maximum(init, 1), 0.0)
    return np.clip(dmg, 0.0, 1.0)


def bond_point_indices(gid: np.ndarray, bonds: np.ndarray) -> np.ndarray:
    """(m,2) bonds as indices into the snapshot's (gid-sorted) arrays."""
    return np.searchsorted(gid, np.asarray(bonds, np.int64).reshape(-1, 2)).astype(np.int64)
