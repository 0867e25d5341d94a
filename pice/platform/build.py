"""The platform of a job: [[bodies]] and [[moorings]] -> hull geometry on every rank, the Platform on rank 0.

Every rank needs each hull's triangles and contact grid (it evaluates the contact of its own ice
with the hulls); only rank 0 builds the rigid bodies and the mooring lines and steps them. A body
whose mass is "balance" gets the mass that floats it at its position with its lines attached: the
hull's buoyancy there (platform.hull_buoyancy) plus the lines' vertical pull at their initial
layout, both known before the body is built. Also the set-up checks of the bodies against the ice.
With [waves], the platform floats in the job's sea (physics.waves.sea_from_job): each hull gets
panels for the wave pressure no longer than a tenth of the peak wavelength (WAVE_PANELS_PER_LENGTH;
platform.hull_waves), and the DEM lines feel the waves' particle velocity and acceleration.
"""

from __future__ import annotations

import logging
import pathlib

import numpy as np

from ..errors import JobError
from ..kernels.geometry import rotation_matrix
from ..physics.contact import contact_law, structure_crushing_pressure
from ..physics.waves import sea_from_job
from .catenary import LayoutError, Segment
from .hull_buoyancy import BRACE_RECORD, submerged
from .hull_contact import Hull, build_triangle_grid, hull_forces
from .hull_waves import panel_mesh
from .body_setup import afloat_position, body_profile, mass_and_inertia
from .hulls import box, revolved, semi_submersible, semi_submersible_braces
from .layout import RHO_STEEL, spread_mooring
from .mooring_lines import LineSegment, build_lines
from .platform import Attachment, MooringGroup, Platform, lines_pull
from .quasi_static import QuasiStaticLines
from .rigid_body import RigidBody, heading_quaternion
from .ship import ship_hull

log = logging.getLogger("pice")

WAVE_PANELS_PER_LENGTH = 10  # wave-pressure panels per peak wavelength, at least (hull_waves.panel_mesh)


# -- hulls (every rank) ------------------------------------------------------------------------
def hull_mesh(job, k: int, base_dir=None) -> tuple[np.ndarray, np.ndarray]:
    """(vertices, triangles) of bodies[k]'s hull in its body frame; refuses an inside-out mesh."""
    from ..io.mesh import read_triangle_mesh

    spec = job.bodies[k].hull
    where = f"{job.source}: bodies[{k}].hull"
    if spec.type == "semi_submersible":
        v, t = semi_submersible()
    elif spec.type == "box":
        v, t = box(*spec.size, centre=spec.centre)
    elif spec.type in ("revolved", "buoy"):
        v, t = revolved(body_profile(spec), spec.segments)
    elif spec.type == "ship":
        v, t = ship_hull(spec)[1]
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
    out = []
    for k, body in enumerate(job.bodies):
        v, t = hull_mesh(job, k, base_dir)
        kn = body.normal_stiffness if body.normal_stiffness is not None else default_kn
        # crushing: the width w of ISO 19906's p_G, as given, else the hull's extent across the drift
        # (in y, body frame); a multi-leg hull may rather give one leg's width (docs/crushing.md)
        width = body.crushing_width if body.crushing_width is not None else float(np.ptp(v[:, 1]))
        law = contact_law(job, kn=kn, friction=body.friction,
                          crushing_pressure=structure_crushing_pressure(job, width=width))
        out.append(Hull(body.name, v, t, build_triangle_grid(v, t, reach=reach), law))
    return out


def initial_poses(job) -> np.ndarray:
    """(n_bodies, 13) x, q, v, omega at t = 0 as the job gives them (at rest); a body whose position
    is "afloat" at x = y = 0 and the height where it floats with its lines' pull (body_setup)."""
    poses = np.zeros((len(job.bodies), 13))
    for k, b in enumerate(job.bodies):
        poses[k, 3:7] = heading_quaternion(b.heading)
        if b.position == "afloat":
            v, t = hull_mesh(job, k)
            mass = mass_and_inertia(job, k, v, t)[0]
            # fairleads on the keel move with the body, and their lines' pull with them: iterate the
            # height to 1e-9 m (the pull changes by ~1e-3 of the waterplane's stiffness per metre)
            keel = any(m.body == b.name and m.fairleads is None for m in job.moorings)
            for _ in range(AFLOAT_ITERATIONS if keel else 1):
                z = poses[k, 2]
                poses[k, :3] = afloat_position(job, k, v, t, _braces(b), poses[k, 3:7], mass=mass,
                                               pull_z=_layout_pull_z(job, k, poses[k]))
                if abs(poses[k, 2] - z) < 1e-9:
                    break
            else:
                if keel:
                    raise JobError(f"{job.source}: bodies[{k}].position = \"afloat\": its height with its keel "
                                   f"fairleads did not settle in {AFLOAT_ITERATIONS} iterations; give the "
                                   "fairleads in space (moorings.fairleads)")
        else:
            poses[k, :3] = b.position
    return poses


AFLOAT_ITERATIONS = 50


def _fairleads(job, k: int, pose: np.ndarray) -> np.ndarray:
    """(n_headings, 3) fairleads [m] of moorings[k] in space at t = 0, its body at ``pose``: as given,
    or on the keel (fairlead_inset: the lowest ring of the hull of revolution, that far in from its
    edge, along each heading), carried by the pose."""
    spec = job.moorings[k]
    if spec.fairleads is not None:
        return np.asarray(spec.fairleads, float)
    ib = [b.name for b in job.bodies].index(spec.body)
    prof = body_profile(job.bodies[ib].hull)
    z0, r0 = prof[int(np.argmin(prof[:, 0]))]
    r = r0 - spec.fairlead_inset
    if r < 0.0:  # a narrow keel (a design of a sweep): the fairleads on the axis
        log.warning("moorings[%d].fairlead_inset = %g m is more than the keel's radius, %.4g m: the fairleads are "
                    "on the hull's axis", k, spec.fairlead_inset, r0)
        r = 0.0
    h = np.radians(np.asarray(spec.headings, float))
    body = np.column_stack([r * np.cos(h), r * np.sin(h), np.full(len(h), z0)])
    return pose[:3] + body @ rotation_matrix(pose[3:7]).T


def _braces(spec) -> np.ndarray:
    return semi_submersible_braces() if spec.hull.type == "semi_submersible" else np.zeros(0, BRACE_RECORD)


def refuse_initial_overlap(job, p, hulls: list[Hull], poses: np.ndarray) -> None:
    """A hull that cuts into the ice at t = 0 would fire elements off, and one that holds ice inside
    it would never touch that ice: refuse either with the fix; likewise two hulls that overlap (there
    is no contact between bodies). Called on the whole sheet, before it is distributed."""
    from .hulls import inside

    fix = "move the body (bodies.position) or the sheet (ice.origin) so that they start apart"
    space = []  # points of each hull in the space frame at t = 0
    for k, h in enumerate(hulls):
        f, t = np.zeros((p.n, 3)), np.zeros((p.n, 3))
        elastic = h.law._replace(kt=0.0, zeta=0.0, mu=0.0, crushing_pressure=np.inf)  # elastic normal force only
        pose = poses[k].copy()
        pose[7:] = 0.0
        hull_forces(p.nlocal, p.x, np.zeros_like(p.v), np.zeros_like(p.w), p.radius * 0.99, p.mass, p.cell_area,
                    p.half_height, pose, h.vertices, h.triangles, *h.grid, elastic, np.zeros((p.n, 4)), 0.0, f, t)
        touching = np.abs(f).sum(axis=1) > 0
        R = rotation_matrix(pose[3:7])
        held = inside((p.x[:p.nlocal] - pose[:3]) @ R, h.vertices, h.triangles)  # centres in the body frame
        n_in, n_touch = int(np.count_nonzero(held)), int(np.count_nonzero(touching & ~held))
        if n_in:
            more = f" and overlaps {n_touch} more" if n_touch else ""
            raise JobError(f"{job.source}: bodies[{k}] ({h.name}): its hull contains {n_in} ice element(s) at t = 0 "
                           f"(their centres lie inside it){more}; {fix}")
        if n_touch:
            raise JobError(f"{job.source}: bodies[{k}] ({h.name}): its hull overlaps {n_touch} ice element(s) at "
                           f"t = 0; {fix}")
        # its vertices and face centres, pulled 1e-6 of its size towards its middle (so that hulls
        # sharing a face do not count), in the space frame
        pts = np.vstack([h.vertices, h.vertices[h.triangles].mean(axis=1)])
        middle = h.vertices.mean(axis=0)
        pts = pts + 1e-6 * (middle - pts)
        space.append(pts @ R.T + pose[:3])
    for k, h in enumerate(hulls):
        for j in range(k):
            R, other = rotation_matrix(poses[j, 3:7]), hulls[j]
            n_in = int(np.count_nonzero(inside((space[k] - poses[j, :3]) @ R, other.vertices, other.triangles)))
            R = rotation_matrix(poses[k, 3:7])
            n_in += int(np.count_nonzero(inside((space[j] - poses[k, :3]) @ R, h.vertices, h.triangles)))
            if n_in:
                raise JobError(f"{job.source}: bodies[{k}] ({h.name}): its hull overlaps that of bodies[{j}] "
                               f"({other.name}) at t = 0 ({n_in} vertices and face centres of one inside the "
                               "other; bodies do not touch each other in this model); move one of them "
                               "(bodies.position)")


# -- mooring lines (rank 0) --------------------------------------------------------------------
def _segments(spec, rho_w: float, g: float) -> list[LineSegment]:
    return [LineSegment(length=s.length, ea=s.ea, diameter=s.diameter, wet_weight=s.wet_weight,
                        dry_mass=s.dry_mass if s.dry_mass is not None else s.wet_weight / g / (1.0 - rho_w / RHO_STEEL),
                        drag_normal=s.drag_normal, drag_tangential=s.drag_tangential, added_mass=s.added_mass)
            for s in spec.segments]


def _lines(spec, lines, segs, w, seabed_z: float):
    """The DEM or quasi-static lines of one [[moorings]] entry over the seabed at ``seabed_z`` [m]."""
    if spec.model == "quasi_static":
        cat = [Segment(s.length, s.wet_weight, s.ea) for s in segs]
        return QuasiStaticLines([a for a, _, _ in lines], [f for _, f, _ in lines], [cat] * len(lines),
                                seabed=True, seabed_z=seabed_z)
    lines_obj = build_lines(lines, element_length=spec.element_length, water_density=w.density,
                            water_level=w.level, seabed_z=seabed_z, current=(*w.current, 0.0),
                            bond_damping=spec.bond_damping, seabed_stiffness=spec.seabed_stiffness,
                            seabed_friction=spec.seabed_friction)
    if spec.relax:
        steps = lines_obj.relax(tol=1.0)
        if not lines_obj.settled:
            raise ValueError(f"relax = true: its DEM lines did not settle to 1 N within {steps:,} relaxation steps "
                             f"(the largest net force on a node is still {lines_obj.largest_free_force():.4g} N); "
                             "set relax = false to start from the catenary unsettled, or use longer elements "
                             "(element_length)")
    return lines_obj


def _layout(job, k: int, pose: np.ndarray):
    """(lines as (anchor, fairlead, segments), the layout LineState, the anchor distance [m], the
    LineSegments) of moorings[k], its body at ``pose``, by the layout solve (layout.spread_mooring);
    JobError when it fails."""
    spec, w = job.moorings[k], job.water
    segs = _segments(spec, w.density, job.gravity)
    where = f"{job.source}: moorings[{k}]"
    fairleads = _fairleads(job, k, pose)
    height = spec.anchor_depth
    if height == "seabed":
        above = fairleads[:, 2] - (w.level - w.depth)
        if np.ptp(above) > 1e-9 or above.min() <= 0.0:
            raise JobError(f"{where}.anchor_depth = \"seabed\": needs every fairlead at one depth above the "
                           f"seabed (they lie {above.min():.4g} to {above.max():.4g} m above it); give anchor_depth "
                           "in m")
        height = float(above[0])
    try:
        lines, state, dist = spread_mooring(fairleads_body=fairleads,
                                            bundle_headings_deg=spec.headings, spread_deg=spec.spread,
                                            lines_per_bundle=spec.lines_per_fairlead,
                                            fairlead_to_anchor_height=height,
                                            pretension=spec.pretension, segments=segs, rho_w=w.density,
                                            seabed_z=w.level - w.depth)
    except LayoutError as exc:
        fix = (f"raise the pretension to at least {exc.limit:.4g} N or move the anchors (anchor_depth)"
               if exc.limit is not None else "lower the pretension or check the segments (ea, wet_weight, length)")
        raise JobError(f"{where}.pretension = {spec.pretension:g}: {exc}; {fix}") from None
    except ValueError as exc:  # the catenary solve failed inside the layout solve
        raise JobError(f"{where}.pretension = {spec.pretension:g}: the layout solve failed ({exc}); check the "
                       "segments (ea, wet_weight, length), anchor_depth and the pretension") from None
    return lines, state, dist, segs


def _layout_pull_z(job, ib: int, pose: np.ndarray) -> float:
    """The vertical pull [N] (< 0: down) of every line on bodies[ib] at its layout (the quasi-static
    catenary at the pretension), the body at ``pose``, before any line is built: a body "afloat"
    floats with it."""
    name, out = job.bodies[ib].name, 0.0
    for k, spec in enumerate(job.moorings):
        if spec.body == name:
            lines, _, _, segs = _layout(job, k, pose)
            cat = [Segment(s.length, s.wet_weight, s.ea) for s in segs]
            quasi = QuasiStaticLines([a for a, _, _ in lines], [f for _, f, _ in lines], [cat] * len(lines),
                                     seabed=True, seabed_z=job.water.level - job.water.depth)
            out += float(quasi.pull[:, 2].sum())
    return out


def _mooring_group(job, k: int, poses: np.ndarray) -> MooringGroup:
    """The lines of moorings[k], anchored by the layout solve, attached to their body at its pose
    (poses: (n_bodies, 13) as initial_poses gives them)."""
    spec, w = job.moorings[k], job.water
    ib = [b.name for b in job.bodies].index(spec.body)
    where = f"{job.source}: moorings[{k}]"
    seabed_z = w.level - w.depth
    lines, state, dist, segs = _layout(job, k, poses[ib])
    above = min(a[2] for a, _, _ in lines) - seabed_z
    log.info("moorings[%d] (%s): %d lines, anchors %.1f m out horizontally and %.1f m above the seabed; at the "
             "%.4g N pretension the line %s (horizontal tension %.4g N, vertical pull on the anchor %.4g N, "
             "grounded %.1f m)", k, spec.model, len(lines), dist, above, spec.pretension,
             "touches the seabed" if state.touches_seabed else "hangs free of the seabed",
             state.horizontal_tension, state.anchor_vertical, state.grounded_length)
    x, R = poses[ib, :3], rotation_matrix(poses[ib, 3:7])
    atts = [Attachment(j, ib, R.T @ (fl - x)) for j, (_, fl, _) in enumerate(lines)]
    try:
        lines_obj = _lines(spec, lines, segs, w, seabed_z)
    except ValueError as exc:  # the starting shape's catenary solve, or the settling of the DEM lines
        if str(exc).startswith("relax = "):
            raise JobError(f"{where}.{exc}") from None
        raise JobError(f"{where}: the starting shape of its lines: {exc}; check the segments (ea, wet_weight, "
                       "length), anchor_depth and the pretension") from None
    return MooringGroup(lines_obj, atts)


# -- bodies (rank 0) ---------------------------------------------------------------------------
def _body_mass(job, k: int, mass, hull: Hull, braces: np.ndarray, pose: np.ndarray, line_pull_z: float) -> float:
    """bodies[k]'s ``mass`` [kg] (body_setup.mass_and_inertia); "balance": the mass whose weight equals
    the buoyancy of hull and braces at the body's initial pose plus the lines' vertical pull there,
    rho_w V + F_z / g."""
    spec, w = job.bodies[k], job.water
    if mass != "balance":
        return float(mass)
    vol = submerged(hull.vertices, hull.triangles, braces, position=pose[:3], attitude=pose[3:7], level=w.level)[0]
    mass = w.density * vol + line_pull_z / job.gravity
    if mass <= 0.0:
        raise JobError(f"{job.source}: bodies[{k}].mass = \"balance\": the hull displaces {vol:.4g} m^3 at "
                       f"its position, too little to carry the lines' pull; lower bodies[{k}].position")
    log.info("bodies[%d] (%s): mass %.6g kg floats at its position (displacement %.6g kg, lines' pull "
             "%.4g N)", k, spec.name, mass, w.density * vol, line_pull_z)
    return mass


def build_platform(job, hulls: list[Hull]) -> Platform:
    """Rank 0's bodies and mooring lines at t = 0 (lines settled when their entry asks for it); a
    "balance" mass is resolved first, from the lines at their initial layout, and each body built once."""
    w, g = job.water, job.gravity
    sea = sea_from_job(job)
    if sea is not None and job.ice is not None:
        log.warning("waves: they act on the bodies and their lines; the level-ice elements feel still water")
    panel = None
    if sea is not None and len(sea.amplitude):
        peak = int(np.argmax(sea.amplitude))
        panel = 2.0 * np.pi / float(sea.k[peak]) / WAVE_PANELS_PER_LENGTH  # [m]
    poses = initial_poses(job)
    groups = [_mooring_group(job, k, poses) for k in range(len(job.moorings))]
    pull = lines_pull(groups, len(job.bodies))
    bodies = []
    for k, (spec, hull) in enumerate(zip(job.bodies, hulls)):
        braces = _braces(spec)
        mass, inertia = mass_and_inertia(job, k, hull.vertices, hull.triangles)
        body = RigidBody(spec.name, _body_mass(job, k, mass, hull, braces, poses[k], pull[k, 2]),
                         inertia, hull.vertices, hull.triangles, braces=braces,
                         added_mass=np.asarray(spec.added_mass, float), damping=np.asarray(spec.damping, float),
                         current_drag=np.asarray(spec.current_drag, float),
                         prescribed=np.asarray(spec.velocity, float) if spec.motion == "prescribed" else None,
                         panels=panel_mesh(hull.vertices, hull.triangles, panel) if panel is not None else None)
        if panel is not None:
            log.info("bodies[%d] (%s): %d wave-pressure panels of at most %.3g m", k, spec.name,
                     len(body.panels[1]), panel)
        if spec.mass == "shell" or spec.position == "afloat":
            log.info("bodies[%d] (%s): mass %.6g kg%s, inertia [%.4g, %.4g, %.4g] kg m^2; its centre at z = %.6g m, "
                     "its lowest point %.4g m under the water%s", k, spec.name, body.mass,
                     f" (a {spec.shell_thickness:g} m shell)" if spec.mass == "shell" else "", *body.inertia,
                     poses[k, 2], w.level - poses[k, 2] - hull.vertices[:, 2].min(),
                     f" (afloat with its lines at their layout; settled, they pull {pull[k, 2]:.4g} N)" if spec.position == "afloat" else "")
        body.x = poses[k, :3].copy()
        body.q = poses[k, 3:7].copy()
        bodies.append(body)
    _warn_unbalanced(job, groups, bodies, pull)
    platform = Platform(bodies, rho_w=w.density, g=g, level=w.level, current=w.current, groups=groups, sea=sea)
    platform.loads()  # gravity, buoyancy and the lines' pull at t = 0: the first half kick's loads
    return platform


UNBALANCED_PULL = 0.01  # a free body's lines whose horizontal pull exceeds this fraction of their tension: warned


def _warn_unbalanced(job, groups: list[MooringGroup], bodies: list[RigidBody], pull: np.ndarray) -> None:
    """Warn of a free body whose lines pull it sideways at t = 0 (one chain, an uneven spread): it
    does not start at rest but moves towards its anchors before anything else acts on it."""
    tension = np.zeros(len(bodies))
    for grp in groups:
        reactions = np.linalg.norm(grp.lines.reactions(grp.lines.fairleads), axis=1)
        for a in grp.attachments:
            tension[a.body] += reactions[a.line]
    for k, body in enumerate(bodies):
        sideways = float(np.hypot(pull[k, 0], pull[k, 1]))
        if body.free and sideways > UNBALANCED_PULL * tension[k] > 0.0:
            log.warning("bodies[%d] (%s): its lines pull it %.4g N sideways at t = 0 (%.0f %% of their %.4g N of "
                        "tension), which nothing balances: it moves towards its anchors before any other load "
                        "acts. To start it at rest, spread its lines so that their pulls cancel "
                        "(moorings.headings), as a catenary mooring is laid out", k, job.bodies[k].name, sideways,
                        100.0 * sideways / tension[k], tension[k])
