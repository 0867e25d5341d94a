"""Fixed rigid walls from the job: planes, triangles and triangle meshes read with meshio."""

from __future__ import annotations

import pathlib

import numpy as np

from ..errors import JobError
from ..kernels.walls import PLANE, TRIANGLE
from .contact import contact_law, law_records


def build_walls(job, *, default_kn: float, base_dir: pathlib.Path | None = None):
    """Arrays for the wall kernel: (kinds, geometry (n,9), contact-law records (n,), names, owner index
    per wall).

    A mesh wall expands into one triangle per mesh face; ``owner`` maps each triangle back to its
    [[walls]] entry so forces are reported per entry.
    """
    kinds, geometry, params, owner = [], [], [], []
    names = []
    for k, wall in enumerate(job.walls):
        names.append(wall.name or f"wall{k}")
        kn = wall.normal_stiffness if wall.normal_stiffness is not None else default_kn
        row = contact_law(job, kn=kn, friction=wall.friction)
        if wall.type == "plane":
            n = np.asarray(wall.normal, float)
            geometry.append(np.concatenate([wall.point, n / np.linalg.norm(n), np.zeros(3)]))
            kinds.append(PLANE)
            params.append(row)
            owner.append(k)
            continue
        if wall.type == "triangle":
            tris = [np.asarray(wall.vertices, float)]
        else:
            tris = _read_mesh(base_dir or pathlib.Path("."), wall.file, job.source, k)
        for face, tri in enumerate(tris):
            if np.linalg.norm(np.cross(tri[1] - tri[0], tri[2] - tri[0])) == 0.0:
                where = (f"walls[{k}].vertices = {tri.tolist()}" if wall.type == "triangle" else
                         f"walls[{k}].file = {wall.file!r}: face {face} {tri.tolist()}")
                raise JobError(f"{job.source}: {where}: degenerate triangle (zero area): the three vertices [m] "
                               "must not coincide or lie on one line")
            geometry.append(tri.reshape(9))
            kinds.append(TRIANGLE)
            params.append(row)
            owner.append(k)
    if not kinds:
        return (np.zeros(0, np.int64), np.zeros((0, 9)), law_records([]), names, np.zeros(0, np.int64))
    return (np.asarray(kinds, np.int64), np.asarray(geometry, float), law_records(params), names,
            np.asarray(owner, np.int64))


def _read_mesh(base: pathlib.Path, file: str, source: str, k: int) -> list[np.ndarray]:
    import contextlib
    import io
    import warnings

    import meshio

    chatter = io.StringIO()  # meshio prints (and for some formats calls sys.exit) on a bad file
    try:
        with warnings.catch_warnings(), contextlib.redirect_stdout(chatter), contextlib.redirect_stderr(chatter):
            warnings.simplefilter("ignore")
            mesh = meshio.read(base / file)
    except (Exception, SystemExit) as exc:  # meshio raises many types for unreadable files
        text = chatter.getvalue() if isinstance(exc, SystemExit) else str(exc)
        why = "; ".join(" ".join(line.split()) for line in text.splitlines() if line.strip()) or type(exc).__name__
        raise JobError(f"{source}: walls[{k}].file = {file!r}: cannot read the mesh ({why}); "
                       "give an STL, OBJ, VTU or other meshio-readable triangle mesh") from None
    tris = [mesh.points[c][:, :3].astype(float) for block in mesh.cells if block.type == "triangle"
            for c in block.data]
    if not tris:
        raise JobError(f"{source}: walls[{k}].file = {file!r}: no triangles read from it; "
                       "give an STL, OBJ, VTU or other meshio-readable triangle mesh")
    return tris
