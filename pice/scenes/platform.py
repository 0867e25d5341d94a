"""The [[bodies]] and [[moorings]] of a job: hull geometry on every rank, the Platform on rank 0.

Every rank needs each hull's triangles and contact grid (it evaluates the contact of its own ice
with the hulls); only rank 0 builds the rigid bodies and the mooring lines and steps them.
"""

from __future__ import annotations

import logging
import pathlib
from dataclasses import dataclass

import numpy as np

from ..errors import JobError
from ..job_platform import heading_quaternion
from ..kernels.hull_contact import build_triangle_grid
from ..kernels.geometry import rotation_matrix
from ..physics.body import RigidBody
from ..physics.catenary import Segment
from ..physics.contact import damping_ratio_from_restitution
from ..physics.mooring import LineSegment, build_lines
from ..physics.platform import Attachment, MooringGroup, Platform
from ..physics.quasi_static import QuasiStaticLines
from .hulls import box, semi_submersible, semi_submersible_braces
from .moorings import RHO_STEEL, spread_mooring

log = logging.getLogger("pice")


@dataclass
class Hull:
    """One body's surface for the ice-hull contact kernel (body frame) and its contact law."""

    name: str
    vertices: np.ndarray      # (nv, 3) [m]
    triangles: np.ndarray     # (nt, 3)
    grid: tuple               # kernels.hull_contact.build_triangle_grid
    params: np.ndarray        # (4,) kn [N/m], kt [N/m], zeta, mu


def hull_mesh(job, k: int, base_dir=None) -> tuple[np.ndarray, np.ndarray]:
    """(vertices, triangles) of bodies[k]'s hull in its body frame; refuses an inside-out mesh."""
    from ..io.mesh import read_triangle_mesh

    spec = job.bodies[k].hull
    where = f"{job.source}: bodies[{k}].hull"
    if spec.type == "semi_submersible":
        v, t = semi_submersible()
    elif spec.type == "box":
        v, t = box(*spec.size, centre=spec.centre)
    else:
        try:
            v, t = read_triangle_mesh(pathlib.Path(base_dir or ".") / spec.file)
        except ValueError as exc:
            raise JobError(f"{where}.file = {spec.file!r}: cannot read the mesh ({exc}); give an STL, OBJ, VTU "
                           "or other meshio-readable closed triangle mesh") from None
    a, b, c = v[t[:, 0]], v[t[:, 1]], v[t[:, 2]]
    volume = float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum()) / 6.0
    if volume <= 0.0:
        raise JobError(f"{where}: the mesh encloses a volume of {volume:.4g} m^3: its triangles must face "
                       "outwards (counter-clockwise seen from outside) and close the hull")
    return v, t


def hulls_from_job(job, *, default_kn: float, reach: float, base_dir=None) -> list[Hull]:
    """Contact geometry of every body; ``reach`` [m] is the largest ice radius."""
    zeta = damping_ratio_from_restitution(job.contact.restitution)
    out = []
    for k, body in enumerate(job.bodies):
        v, t = hull_mesh(job, k, base_dir)
        kn = body.normal_stiffness if body.normal_stiffness is not None else default_kn
        params = np.array([kn, job.contact.stiffness_ratio * kn, zeta, body.friction])
        out.append(Hull(body.name, v, t, build_triangle_grid(v, t, reach=reach), params))
    return out


def _segments(spec, rho_w: float, g: float) -> list[LineSegment]:
    return [LineSegment(length=s.length, ea=s.ea, diameter=s.diameter, wet_weight=s.wet_weight,
                        dry_mass=s.dry_mass if s.dry_mass is not None else s.wet_weight / g / (1.0 - rho_w / RHO_STEEL),
                        drag_normal=s.drag_normal, drag_tangential=s.drag_tangential, added_mass=s.added_mass)
            for s in spec.segments]


def _mooring_group(job, k: int, bodies: list[RigidBody]) -> MooringGroup:
    spec, w = job.moorings[k], job.water
    names = [b.name for b in job.bodies]
    ib = names.index(spec.body)
    body = bodies[ib]
    segs = _segments(spec, w.density, job.gravity)
    try:
        lines, state, dist = spread_mooring(fairleads_body=np.asarray(spec.fairleads, float),
                                            bundle_headings_deg=spec.headings, spread_deg=spec.spread,
                                            lines_per_bundle=spec.lines_per_fairlead,
                                            fairlead_to_anchor_height=spec.anchor_depth,
                                            pretension=spec.pretension, segments=segs, rho_w=w.density)
    except ValueError as exc:
        raise JobError(f"{job.source}: moorings[{k}].pretension = {spec.pretension:g}: {exc}; raise the "
                       "pretension or move the anchors (anchor_depth)") from None
    log.info("moorings[%d] (%s): %d lines, anchors %.1f m out horizontally; at the %.4g N pretension the line "
             "%s (horizontal tension %.4g N, anchor uplift %.4g N, grounded %.1f m)", k, spec.model, len(lines),
             dist, spec.pretension, "touches the seabed" if state.touches_seabed else "hangs free of the seabed",
             state.horizontal_tension, state.anchor_vertical, state.grounded_length)
    R = rotation_matrix(body.q)
    atts = [Attachment(j, ib, R.T @ (fl - body.x)) for j, (_, fl, _) in enumerate(lines)]
    seabed_z = w.level - w.depth
    if spec.model == "quasi_static":
        cat = [Segment(s.length, s.wet_weight, s.ea) for s in segs]
        lines_obj = QuasiStaticLines([a for a, _, _ in lines], [f for _, f, _ in lines], [cat] * len(lines),
                                     seabed=True)
    else:
        lines_obj = build_lines(lines, element_length=spec.element_length, water_density=w.density,
                                water_level=w.level, seabed_z=seabed_z, current=(*w.current, 0.0),
                                bond_damping=spec.bond_damping, seabed_stiffness=spec.seabed_stiffness,
                                seabed_friction=spec.seabed_friction)
        if spec.relax:
            lines_obj.relax(tol=1.0)
    return MooringGroup(lines_obj, atts)


def build_platform(job, hulls: list[Hull]) -> Platform:
    """Rank 0's bodies and mooring lines at t = 0 (lines settled when their entry asks for it)."""
    w, g = job.water, job.gravity
    bodies = []
    for spec, hull in zip(job.bodies, hulls):
        braces = semi_submersible_braces() if spec.hull.type == "semi_submersible" else np.zeros((0, 7))
        body = RigidBody(spec.name, 1.0, np.asarray(spec.inertia, float), hull.vertices, hull.triangles,
                         braces=braces, added_mass=np.asarray(spec.added_mass, float), damping=np.asarray(spec.damping, float),
                         current_drag=np.asarray(spec.current_drag, float),
                         prescribed=np.asarray(spec.velocity, float) if spec.motion == "prescribed" else None)
        body.x = np.asarray(spec.position, float)
        body.q = np.asarray(heading_quaternion(spec.heading), float)
        bodies.append(body)
    groups = [_mooring_group(job, k, bodies) for k in range(len(job.moorings))]
    platform = Platform(bodies, rho_w=w.density, g=g, level=w.level, current=w.current, groups=groups)
    platform.loads()  # the lines' pull at t = 0, for "balance"
    for k, (spec, body) in enumerate(zip(job.bodies, bodies)):
        if spec.mass == "balance":
            vol = body.submerged(w.level)[0]  # hull mesh and braces
            body.mass = w.density * vol + platform.mooring_force[k, 2] / g
            if body.mass <= 0.0:
                raise JobError(f"{job.source}: bodies[{k}].mass = \"balance\": the hull displaces {vol:.4g} m^3 at "
                               f"its position, too little to carry the lines' pull; lower bodies[{k}].position")
            log.info("bodies[%d] (%s): mass %.6g kg floats at its position (displacement %.6g kg, lines' pull "
                     "%.4g N)", k, spec.name, body.mass, w.density * vol, platform.mooring_force[k, 2])
        else:
            body.mass = float(spec.mass)
    platform.loads()
    return platform
