"""Fixed rigid walls from the job: planes, triangles and triangle meshes (read by io/mesh.py)."""

from __future__ import annotations

import pathlib

import numpy as np

from ..errors import JobError
from ..kernels.walls import PLANE, TRIANGLE, wall_forces
from .contact import contact_law, law_records, structure_crushing_pressure


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
        row = contact_law(job, kn=kn, friction=wall.friction,
                          crushing_pressure=structure_crushing_pressure(job, width=wall.crushing_width))
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
            tris = read_wall_mesh(base_dir or pathlib.Path("."), wall.file, job.source, k)
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


def read_wall_mesh(base: pathlib.Path, file: str, source: str, k: int) -> list[np.ndarray]:
    """The triangles ((3,3) each, [m]) of walls[k].file, read by io/mesh.py (the one mesh reader);
    a file that cannot be read or holds no triangles is a JobError naming the key."""
    from ..io.mesh import NoTrianglesError, read_triangle_mesh

    fix = "give an STL, OBJ, VTU or other meshio-readable triangle mesh"
    try:
        vertices, triangles = read_triangle_mesh(base / file)
    except NoTrianglesError:
        raise JobError(f"{source}: walls[{k}].file = {file!r}: no triangles read from it; {fix}") from None
    except ValueError as exc:
        raise JobError(f"{source}: walls[{k}].file = {file!r}: cannot read the mesh ({exc}); {fix}") from None
    return list(vertices[triangles])


class WallTerm:
    """Contact of the ice with the fixed [[walls]] (kernels/walls.py), with the reaction on each wall.

    After each step ``force`` and ``moment`` hold, per wall triangle or plane, this rank's ice load
    [N] and its moment about the origin [N m]; ``c.wall_energy`` the elastic energy in wall contacts [J];
    ``crushing`` the contacts in plastic flow.
    """

    crushing = 0

    name = "walls"

    def __init__(self, job, *, default_kn: float, base_dir: pathlib.Path | None = None):
        self.kinds, self.geometry, self.params, self.names, self.owner = build_walls(
            job, default_kn=default_kn, base_dir=base_dir)
        self.n_entries = len(job.walls)
        self.force = np.zeros((len(self.kinds), 3))
        self.moment = np.zeros((len(self.kinds), 3))

    def add_forces(self, p, c, dt):
        self.force[:] = 0.0
        self.moment[:] = 0.0
        c.wall_energy, self.crushing = wall_forces(
            p.nlocal, p.x, p.v, p.w, p.radius, p.mass, p.cell_area, p.half_height, self.kinds, self.geometry,
            self.params, p.wall_hist, dt, p.force, p.torque, self.force, self.moment)

    def local_loads(self) -> np.ndarray:
        """(n_wall_entries, 6): force [N] of this rank's ice on each [[walls]] entry, and its moment
        about the origin [N m] (each contact force acts at the sphere's contact point)."""
        out = np.zeros((self.n_entries, 6))
        if len(self.owner):
            np.add.at(out[:, :3], self.owner, self.force)
            np.add.at(out[:, 3:], self.owner, self.moment)
        return out

    def refuse_initial_overlap(self, job, p) -> None:
        """A wall that cuts into the ice at t = 0 would fire elements off: refuse it with the fix."""
        f, t, wf = np.zeros((p.n, 3)), np.zeros((p.n, 3)), np.zeros((len(self.kinds), 3))
        params = self.params.copy()
        params["kt"], params["zeta"], params["mu"] = 0.0, 0.0, 0.0  # elastic normal force only
        params["crushing_pressure"] = np.inf
        wall_forces(p.nlocal, p.x, np.zeros_like(p.v), np.zeros_like(p.w), p.radius * 0.99, p.mass, p.cell_area,
                    p.half_height, self.kinds, self.geometry, params, np.zeros_like(p.wall_hist), 0.0, f, t, wf,
                    np.zeros_like(wf))
        hit = np.nonzero(np.abs(wf).sum(axis=1) > 0)[0]
        if len(hit):
            k = int(self.owner[hit[0]])
            n_el = int(np.count_nonzero(np.abs(f).sum(axis=1) > 0))
            raise JobError(f"{job.source}: walls[{k}] ({self.names[k]}): overlaps {n_el} ice "
                           "element(s) at t = 0; move the wall clear of the sheet (or the sheet's origin)")
