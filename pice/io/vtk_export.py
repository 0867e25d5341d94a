"""VTK export of a run file: a .vtu per snapshot and block, static geometry once, a .pvd collection.

``export_vtk("runs/x.h5", "runs/x_vtk")`` writes::

    ice_NNNNN.vtu   one per snapshot: the particles (vertex cells) with point data radius,
                    velocity, angular_velocity, kind, gid and damage (fraction of the element's
                    bonds of snapshot 0 that are broken), and the intact bonds as line cells
    walls.vtu       the job's [[walls]] as triangles (planes as a square patch around their point
                    sized to the ice extent), cell data ``wall`` = index of the [[walls]] entry
    bodies_NNNNN.vtu  every hull at its pose (triangles), cell data ``body``
    moorings_NNNNN.vtu  the mooring lines as polylines, cell data ``line``
    x.pvd           the collection: every block of every snapshot with its time

Blocks are plain functions in two tables, ``SNAPSHOT_BLOCKS`` (one file per snapshot) and
``STATIC_BLOCKS`` (one file per run): a new kind of output is one more entry with a builder
returning a ``meshio.Mesh`` or None when the run has none.
"""

from __future__ import annotations

import logging
import os
import pathlib
import sys
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field

import h5py
import numpy as np

from ..errors import PiceError
from .run_file import OutputError

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

log = logging.getLogger("pice")


class RunFileError(PiceError):
    """The run file to post-process cannot be read. Exit status 5."""

    exit_code = 5


# ------------------------------------------------------------------------------------------------
# Reading a run file


@dataclass
class Run:
    """An open run file with what every block builder needs (use as a context manager)."""

    path: pathlib.Path
    h5: h5py.File
    snapshots: list[str]                 # group names under /snapshots, in order
    job: object = None                   # pice.job.Job parsed from the job_text attribute, or None
    job_dir: pathlib.Path | None = None  # where the job's relative paths (mesh walls) resolve
    wall_index: list = field(default_factory=list)  # [[walls]] index of each of job.walls
    _initial: tuple | None = field(default=None, repr=False)
    _extent: np.ndarray | None = field(default=None, repr=False)

    def __enter__(self):
        return self

    def __exit__(self, *_):
        self.h5.close()

    def snapshot(self, key: str | int) -> h5py.Group:
        return self.h5["snapshots"][self.snapshots[key] if isinstance(key, int) else key]

    def time(self, key) -> float:
        return float(self.snapshot(key).attrs["time"])

    def wall_names(self) -> list[str]:
        """Name of each [[walls]] entry (as the series' wall axis), from the job text."""
        if not self.h5.attrs.get("job_text", ""):
            return []
        walls = tomllib.loads(self.h5.attrs["job_text"]).get("walls", ())
        return [w.get("name") or f"wall{k}" for k, w in enumerate(walls)]

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
    run = Run(path=path, h5=h5, snapshots=snaps)
    run.job, run.job_dir, run.wall_index = _job_of(h5, path)
    return run


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


# ------------------------------------------------------------------------------------------------
# Blocks: builders returning a meshio.Mesh (or None when the run has nothing of that kind)


def ice_block(run: Run, key: str):
    import meshio

    g = run.snapshot(key)
    gid = g["gid"][()]
    n = len(gid)
    cells = [meshio.CellBlock("vertex", np.arange(n, dtype=np.int64).reshape(-1, 1)),
             meshio.CellBlock("line", bond_point_indices(gid, g["bonds"][()]))]
    point_data = {"radius": g["radius"][()], "velocity": g["v"][()], "angular_velocity": g["w"][()],
                  "kind": g["kind"][()].astype(np.int32), "gid": gid,
                  "damage": bond_damage(gid, g["bonds"][()], *run.initial_bond_counts())}
    return meshio.Mesh(g["x"][()], cells, point_data=point_data)


def wall_triangles(run: Run) -> tuple[np.ndarray, np.ndarray]:
    """(k,3,3) triangles of the job's walls and (k,) the index of the [[walls]] entry of each."""
    from ..physics.walls import _read_mesh

    job = run.job
    if job is None or not job.walls:
        return np.zeros((0, 3, 3)), np.zeros(0, np.int64)
    box = run.ice_extent()
    corners = np.array([[box[i, 0], box[j, 1], box[k, 2]] for i in (0, 1) for j in (0, 1) for k in (0, 1)])
    tris, owner = [], []
    for wall, k in zip(job.walls, run.wall_index):
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
            new = _read_mesh(run.job_dir or pathlib.Path("."), wall.file, job.source, k)
        tris += new
        owner += [k] * len(new)
    return np.asarray(tris, float).reshape(-1, 3, 3), np.asarray(owner, np.int64)


def walls_block(run: Run):
    import meshio

    tris, owner = wall_triangles(run)
    if not len(tris):
        return None
    return meshio.Mesh(tris.reshape(-1, 3), [("triangle", np.arange(3 * len(tris)).reshape(-1, 3))],
                       cell_data={"wall": [owner.astype(np.int32)]})


def bodies_block(run: Run, key: str):
    """Every hull at its pose of this snapshot (triangles), cell data ``body`` = its [[bodies]] index."""
    import meshio

    from ..kernels.hull import transform
    from ..kernels.geometry import rotation_matrix

    g, first = run.snapshot(key), run.snapshot(0)
    if "body_pose" not in g:
        return None
    pts, tris, body, off = [], [], [], 0
    for k, pose in enumerate(g["body_pose"][()]):
        if f"hull{k}_vertices" not in first:
            return None
        v = transform(first[f"hull{k}_vertices"][()], rotation_matrix(pose[3:7]), pose[:3])
        t = first[f"hull{k}_triangles"][()]
        pts.append(v)
        tris.append(t + off)
        body.append(np.full(len(t), k, np.int32))
        off += len(v)
    return meshio.Mesh(np.vstack(pts), [("triangle", np.vstack(tris))], cell_data={"body": [np.concatenate(body)]})


def moorings_block(run: Run, key: str):
    """The mooring lines as polylines (one line cell per element), cell data ``line`` = line index."""
    import meshio

    g = run.snapshot(key)
    if "mooring_x" not in g:
        return None
    x, line = g["mooring_x"][()], g["mooring_line"][()]
    seg = np.nonzero(line[1:] == line[:-1])[0]
    cells = np.column_stack([seg, seg + 1]).astype(np.int64)
    return meshio.Mesh(x, [("line", cells)], cell_data={"line": [line[seg].astype(np.int32)]})


# name -> builder(run, snapshot key); written as <name>_NNNNN.vtu for every snapshot
SNAPSHOT_BLOCKS = {"ice": ice_block, "bodies": bodies_block, "moorings": moorings_block}
# name -> builder(run); written once as <name>.vtu and listed at every time of the .pvd
STATIC_BLOCKS = {"walls": walls_block}


# ------------------------------------------------------------------------------------------------


def _write(mesh, path: pathlib.Path) -> None:
    import meshio

    try:
        meshio.write(path, mesh, file_format="vtu", binary=True)
    except OSError as exc:
        raise OutputError(f"{path}: cannot write ({exc.strerror or exc})") from None


def write_pvd(path: pathlib.Path, entries: list[tuple[float, int, str, str]]) -> None:
    """A ParaView collection: ``entries`` of (time, part, file relative to the .pvd, block name)."""
    root = ET.Element("VTKFile", type="Collection", version="1.0", byte_order="LittleEndian")
    coll = ET.SubElement(root, "Collection")
    for t, part, file, name in entries:
        ET.SubElement(coll, "DataSet", timestep=repr(float(t)), group="", part=str(part), file=file, name=name)
    ET.indent(root)
    path.write_bytes(b'<?xml version="1.0"?>\n' + ET.tostring(root, encoding="utf-8") + b"\n")


def export_vtk(run_path: str | os.PathLike, out_dir: str | os.PathLike) -> dict:
    """Write the VTK files of a run into ``out_dir``; return {"pvd": path, "files": [paths]}."""
    out = pathlib.Path(out_dir)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OutputError(f"{out}: cannot create the output folder ({exc.strerror or exc})") from None
    files, entries = [], []
    with open_run(run_path) as run:
        if not run.snapshots:
            raise RunFileError(f"{run.path}: the run file holds no snapshots to export")
        static = []
        for name, build in STATIC_BLOCKS.items():
            mesh = build(run)
            if mesh is not None:
                _write(mesh, out / f"{name}.vtu")
                files.append(out / f"{name}.vtu")
                static.append((name, f"{name}.vtu"))
        for key in run.snapshots:
            t = run.time(key)
            part = 0
            for name, build in SNAPSHOT_BLOCKS.items():
                mesh = build(run, key)
                if mesh is None:
                    continue
                file = f"{name}_{key}.vtu"
                _write(mesh, out / file)
                files.append(out / file)
                entries.append((t, part, file, name))
                part += 1
            for name, file in static:
                entries.append((t, part, file, name))
                part += 1
        pvd = out / f"{run.path.stem}.pvd"
        try:
            write_pvd(pvd, entries)
        except OSError as exc:
            raise OutputError(f"{pvd}: cannot write ({exc.strerror or exc})") from None
    return {"pvd": pvd, "files": files}
