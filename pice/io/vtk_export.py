"""VTK export of a run file: a .vtu per snapshot and block, static geometry once, a .pvd collection.

``export_vtk("runs/x.h5", "runs/x_vtk")`` writes::

    ice_NNNNN.vtu   one per snapshot: the particles (vertex cells) with point data radius,
                    velocity, angular_velocity, kind, gid and damage (fraction of the element's
                    bonds of snapshot 0 that are broken), and the intact bonds as line cells
    walls.vtu       the job's [[walls]] as triangles (planes as a square patch around their point
                    sized to the ice extent), cell data ``wall`` = index of the [[walls]] entry
    floes_NNNNN.vtu  every floe as a prism at its pose (triangles), cell data ``floe``
    bodies_NNNNN.vtu  every hull at its pose (triangles), cell data ``body``
    moorings_NNNNN.vtu  the mooring lines as polylines, cell data ``line``
    x.pvd           the collection: every block of every snapshot with its time

Blocks are plain functions in two tables, ``SNAPSHOT_BLOCKS`` (one file per snapshot) and
``STATIC_BLOCKS`` (one file per run): a new kind of output is one more entry with a builder
returning a ``meshio.Mesh`` or None when the run has none. The run file is read through
io/run_reader.py.
"""

from __future__ import annotations

import os
import pathlib
import xml.etree.ElementTree as ET

import numpy as np

from .errors import OutputError, RunFileError
from .run_reader import Run, bond_damage, bond_point_indices, open_run


# ------------------------------------------------------------------------------------------------
# Blocks: builders returning a meshio.Mesh (or None when the run has nothing of that kind)


def ice_block(run: Run, key: str):
    import meshio

    g = run.snapshot(key)
    gid = g["gid"][()]
    n = len(gid)
    if n == 0:  # a scene without level ice
        return None
    cells = [meshio.CellBlock("vertex", np.arange(n, dtype=np.int64).reshape(-1, 1)),
             meshio.CellBlock("line", bond_point_indices(gid, g["bonds"][()]))]
    point_data = {"radius": g["radius"][()], "velocity": g["v"][()], "angular_velocity": g["w"][()],
                  "kind": g["kind"][()].astype(np.int32), "gid": gid,
                  **({"crush_depth": g["crush_depth"][()]} if "crush_depth" in g else {}),
                  "damage": bond_damage(gid, g["bonds"][()], *run.initial_bond_counts())}
    return meshio.Mesh(g["x"][()], cells, point_data=point_data)


def walls_block(run: Run):
    import meshio

    tris, owner = run.wall_triangles()
    if not len(tris):
        return None
    return meshio.Mesh(tris.reshape(-1, 3), [("triangle", np.arange(3 * len(tris)).reshape(-1, 3))],
                       cell_data={"wall": [owner.astype(np.int32)]})


def bodies_block(run: Run, key: str):
    """Every hull at its pose of this snapshot (triangles), cell data ``body`` = its [[bodies]] index."""
    import meshio

    from ..platform.hull_buoyancy import transform
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


def floes_block(run: Run, key: str):
    """Every floe as a closed prism at its pose of this snapshot (triangles: top, bottom, sides), cell
    data ``floe`` = its index and point data ``velocity`` [m/s]."""
    import meshio

    from ..kernels.geometry import rotation_matrix

    g, first = run.snapshot(key), run.snapshot(0)
    if "floe_pose" not in g or "floe_polygon" not in first:
        return None
    poly, start, h = first["floe_polygon"][()], first["floe_polygon_start"][()], first["floe_thickness"][()]
    pose, vel = g["floe_pose"][()], g["floe_velocity"][()]
    pts, tris, floe, speed, off = [], [], [], [], 0
    for i in range(len(pose)):
        p2 = poly[start[i]:start[i + 1]]
        k = len(p2)
        local = np.vstack([np.column_stack([p2, np.full(k, z)]) for z in (-0.5 * h[i], 0.5 * h[i])])
        pts.append(local @ rotation_matrix(pose[i, 3:7]).T + pose[i, :3])
        fan = [(0, j + 1, j) for j in range(1, k - 1)] + [(k, k + j, k + j + 1) for j in range(1, k - 1)]
        side = [t for j in range(k) for t in ((j, (j + 1) % k, k + (j + 1) % k), (j, k + (j + 1) % k, k + j))]
        t = np.asarray(fan + side, np.int64)
        tris.append(t + off)
        floe.append(np.full(len(t), i, np.int32))
        speed.append(np.repeat(vel[i:i + 1], 2 * k, axis=0))
        off += 2 * k
    if not pts:
        return None
    return meshio.Mesh(np.vstack(pts), [("triangle", np.vstack(tris))], point_data={"velocity": np.vstack(speed)},
                       cell_data={"floe": [np.concatenate(floe)]})


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
SNAPSHOT_BLOCKS = {"ice": ice_block, "floes": floes_block, "bodies": bodies_block, "moorings": moorings_block}
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
