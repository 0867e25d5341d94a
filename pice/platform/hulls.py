"""Hull meshes: closed, outward-oriented triangle meshes in the body frame (origin at the CG).

Built from parameters (boxes, the semi-submersible of Zhu & Ji 2022) here, or read with meshio
(platform.build.hull_mesh). Parts of a hull are separate closed meshes that touch without
overlapping, so the submerged volumes of the parts add up (platform.hull_buoyancy) and the contact
sees their outer faces. Braces are not triangles but cylinders, records (p0, p1, radius) of
hull_buoyancy.BRACE_RECORD, whose buoyancy follows Eqs. 13-14 (semi_submersible_braces,
RigidBody.braces); ``cylinder`` meshes one for drawing or checking.
"""

from __future__ import annotations

import math

import numpy as np

from .hull_buoyancy import BRACE_RECORD


def box(lx: float, ly: float, lz: float, centre=(0.0, 0.0, 0.0)) -> tuple[np.ndarray, np.ndarray]:
    """A closed box mesh (8 vertices, 12 outward triangles)."""
    c = np.asarray(centre, float)
    v = np.array([[sx * lx / 2, sy * ly / 2, sz * lz / 2] for sz in (-1, 1) for sy in (-1, 1) for sx in (-1, 1)]) + c
    # vertex k = ix + 2 iy + 4 iz
    faces = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    tris = []
    for a, b, cc, d in faces:
        tris += [(a, b, cc), (a, cc, d)]
    return v, np.asarray(tris, np.int64)


def sloped_block(lx_bottom: float, lx_top: float, ly: float, z0: float, z1: float,
                 centre_xy=(0.0, 0.0)) -> tuple[np.ndarray, np.ndarray]:
    """A block whose +x and -x faces lean outwards from z0 (length lx_bottom) to z1 (length lx_top):
    an ice-resistant slope at bow and stern. y faces are vertical."""
    cx, cy = centre_xy
    v = []
    for z, lx in ((z0, lx_bottom), (z1, lx_top)):
        for sy in (-1, 1):
            for sx in (-1, 1):
                v.append([cx + sx * lx / 2, cy + sy * ly / 2, z])
    v = np.asarray(v, float)
    faces = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    tris = []
    for a, b, c, d in faces:
        tris += [(a, b, c), (a, c, d)]
    return v, np.asarray(tris, np.int64)


def merge(parts) -> tuple[np.ndarray, np.ndarray]:
    """One vertex/triangle set from several closed parts."""
    verts, tris, off = [], [], 0
    for v, t in parts:
        verts.append(v)
        tris.append(t + off)
        off += len(v)
    return np.vstack(verts), np.vstack(tris)


def semi_submersible(*, length: float = 86.2, width: float = 64.6, draft: float = 14.0,
                     pontoon_width: float = 14.0, pontoon_height: float = 8.0, column: float = 16.68,
                     freeboard: float = 12.0, slope_deg: float = 10.0, cg_above_keel: float = 8.9):
    """The moored semi-submersible of Zhu & Ji (2022), Table 3, as far as the paper describes it:
    the hull (pontoons and columns) as a closed triangle mesh. Its braces are cylinders, not
    triangles: ``semi_submersible_braces`` with the same size parameters.

    Assumptions where the paper gives no drawing (docs/semi_submersible.md): a ring pontoon of
    ``pontoon_width`` x ``pontoon_height`` around the 86.2 m x 64.6 m footprint, four square corner
    columns of side ``column`` from the pontoon to ``freeboard`` above the still waterline, whose
    bow (+x) and stern (-x) faces lean out at ``slope_deg`` from the vertical (the 10-degree
    ice-resistant slope of Table 3). With the default braces, the default sizes displace the
    35,000.5 t of Table 3 at the 14 m draft within 0.1 % (rho_w = 1025 kg/m^3) with the centre of
    buoyancy 5.37 m above the keel (Table 3: 5.4 m); the braces displace 815 m^3 of it. Body
    frame: origin at the CG, ``cg_above_keel`` above the keel.
    """
    zk = -cg_above_keel                     # keel
    zp = zk + pontoon_height                # pontoon top
    zt = zk + draft + freeboard             # column top
    parts = []
    # ring pontoon: two long sides, two short ends in between (touching, not overlapping)
    for sy in (-1, 1):
        parts.append(box(length, pontoon_width, pontoon_height,
                         (0.0, sy * (width - pontoon_width) / 2, zk + pontoon_height / 2)))
    inner_y = width - 2 * pontoon_width
    for sx in (-1, 1):
        parts.append(box(pontoon_width, inner_y, pontoon_height,
                         (sx * (length - pontoon_width) / 2, 0.0, zk + pontoon_height / 2)))
    # columns: x faces lean out by tan(slope) per metre of height
    lean = math.tan(math.radians(slope_deg)) * (zt - zp)
    for sx in (-1, 1):
        for sy in (-1, 1):
            cx = sx * (length - column) / 2 - sx * lean / 2
            cy = sy * (width - column) / 2
            parts.append(sloped_block(column - lean, column + lean, column, zp, zt, (cx, cy)))
    return merge(parts)


def semi_submersible_braces(*, length: float = 86.2, width: float = 64.6, draft: float = 14.0,
                            pontoon_width: float = 14.0, pontoon_height: float = 8.0, column: float = 16.68,
                            freeboard: float = 12.0, slope_deg: float = 10.0, cg_above_keel: float = 8.9,
                            brace_diameter: float = 2.5, brace_height: float | None = None) -> np.ndarray:
    """The braces of ``semi_submersible`` (same size parameters) as cylinders: (4,) records of
    hull_buoyancy.BRACE_RECORD (p0 (3,), p1 (3,), radius) in the body frame [m], for
    ``RigidBody(braces=...)``, whose buoyancy follows Eqs. 13-14 (hull_buoyancy.brace_submerged).

    Assumption (the paper gives no drawing; docs/semi_submersible.md): four horizontal braces of
    diameter ``brace_diameter`` join neighbouring columns along their centre lines, their axes
    ``brace_height`` above the keel (default: half-way between the pontoon top and the still
    waterline, 11 m; the brace tops are then 1.75 m below the water, under a 1 m ice sheet's
    0.9 m draft). Each brace ends where its axis meets the column face, so no volume is counted
    twice: on a vertical face the flat end is the face; on a 10-degree bow/stern face the flat end
    enters the column above the axis by exactly the wedge it leaves open below it
    (2 R^3 tan(slope) / 3 each), so the volume is that of the brace cut to fit the face.
    pontoon_width does not enter (the braces sit above the pontoons); it is accepted so that both
    functions take the same keywords.
    """
    del pontoon_width
    R = brace_diameter / 2
    zk = -cg_above_keel
    zp = zk + pontoon_height
    zt = zk + draft + freeboard
    zb = zk + (brace_height if brace_height is not None else pontoon_height + (draft - pontoon_height) / 2)
    if not (zp + R <= zb <= zt - R):
        raise ValueError(f"brace_height = {zb - zk:g} m above the keel: the braces (radius {R:g} m) must lie "
                         f"between the pontoon top ({pontoon_height:g} m) and the column top "
                         f"({draft + freeboard:g} m)")
    lean = math.tan(math.radians(slope_deg)) * (zt - zp)
    f = (zb - zp) / (zt - zp)
    x_face = length / 2 - column - lean * f   # inner (sloped) x face of the columns at the brace height
    y_face = width / 2 - column               # inner (vertical) y face
    cx = (length - column - lean) / 2         # column centre lines
    cy = (width - column) / 2
    if x_face <= 0.0 or y_face <= 0.0 or R > column / 2 - lean / 2:
        raise ValueError(f"column = {column:g} m, brace_diameter = {brace_diameter:g} m: the columns overlap "
                         "or the braces are wider than the columns")
    rows = [((-x_face, sy * cy, zb), (x_face, sy * cy, zb), R) for sy in (-1, 1)]   # along x (port, starboard)
    rows += [((sx * cx, -y_face, zb), (sx * cx, y_face, zb), R) for sx in (-1, 1)]  # along y (stern, bow)
    return np.array(rows, BRACE_RECORD)


def revolved(profile, segments: int = 48) -> tuple[np.ndarray, np.ndarray]:
    """A closed, outward mesh of revolution about the z axis: ``profile`` (k, 2) of (z, r) [m] from the
    bottom ring to the top ring (z increasing, every r > 0), each ring a regular ``segments``-gon
    with its vertices on the circle, closed by a flat cap at each end (a conical hull, a buoy's
    double cone, a cone structure)."""
    prof = np.asarray(profile, float).reshape(-1, 2)
    if len(prof) < 2 or np.any(np.diff(prof[:, 0]) <= 0.0) or np.any(prof[:, 1] <= 0.0):
        raise ValueError(f"profile {prof.tolist()}: give at least two (z, r) rings, z increasing, every r > 0 m")
    if int(segments) < 3:
        raise ValueError(f"segments = {segments}: at least 3")
    m, rings = int(segments), len(prof)
    phi = 2.0 * math.pi * np.arange(m) / m
    verts = [np.column_stack([r * np.cos(phi), r * np.sin(phi), np.full(m, z)]) for z, r in prof]
    verts.append(np.array([[0.0, 0.0, prof[0, 0]], [0.0, 0.0, prof[-1, 0]]]))  # the caps' centres
    bottom, top = rings * m, rings * m + 1
    tris = []
    for k in range(m):
        j = (k + 1) % m
        for ring in range(rings - 1):  # counter-clockwise seen from outside
            a, b = ring * m + k, ring * m + j
            tris += [(a, b, b + m), (a, b + m, a + m)]
        tris += [(bottom, j, k), (top, (rings - 1) * m + k, (rings - 1) * m + j)]
    return np.vstack(verts), np.asarray(tris, np.int64)


def buoy_design_profile(*, d_max: float, alpha_deg: float, height: float = 3.0, keel: float | None = None,
                        widest: float | None = None) -> np.ndarray:
    """(z, r) rings [m], keel at z = 0, of one moored buoy of Cai (2018, seed 004) as its Table 6-1/6-2
    designs are built: a keel cylinder ``keel`` m high (default H/6, Eq. 4-16), the lower cone at the
    downward-sloping hull angle ``alpha_deg`` (from the horizontal) up to the widest section, diameter
    ``d_max``, at ``widest`` m (default 5H/6, Eq. 4-22), and the upper cone back to the minimum
    diameter at the top, ``height``: D_min = D_max - 2 (widest - keel) / tan(alpha), and the
    upward-sloping angle theta = atan((height - widest) / (r_max - r_min)). Table 4-2's buoy is
    d_max 9 m at 45 deg (D_min 5 m, theta 14.04 deg). Raises ValueError when D_min would not be > 0."""
    keel = height / 6.0 if keel is None else keel
    widest = 5.0 * height / 6.0 if widest is None else widest
    if not 0.0 <= keel < widest < height:
        raise ValueError(f"keel = {keel:g} m, widest = {widest:g} m, height = {height:g} m: need 0 <= keel < "
                         "widest < height")
    drop = (widest - keel) / math.tan(math.radians(alpha_deg))  # r_max - r_min [m]
    r_max = 0.5 * d_max
    if r_max - drop <= 0.0:
        raise ValueError(f"D_max = {d_max:g} m at {alpha_deg:g} deg: the cone closes before the keel (D_min "
                         f"{d_max - 2 * drop:.3g} m); widen the buoy (D_max > {2 * drop:.4g} m) or steepen the hull "
                         f"angle (> {math.degrees(math.atan2(widest - keel, r_max)):.4g} deg)")
    rings = [(0.0, r_max - drop)] + ([(keel, r_max - drop)] if keel > 0.0 else [])
    return np.array(rings + [(widest, r_max), (height, r_max - drop)])


def cylinder(p0, p1, radius: float, n: int = 64) -> tuple[np.ndarray, np.ndarray]:
    """A closed n-sided prism around the segment p0 -> p1 (outward triangles): a brace as a mesh,
    for drawing it or checking Eqs. 13-14 against the clipped-mesh volume of Eq. 12."""
    p0, p1 = np.asarray(p0, float), np.asarray(p1, float)
    a = (p1 - p0) / np.linalg.norm(p1 - p0)
    u = np.cross(a, [1.0, 0.0, 0.0] if abs(a[0]) < 0.9 else [0.0, 1.0, 0.0])
    u /= np.linalg.norm(u)
    w = np.cross(a, u)
    phi = 2 * np.pi * np.arange(n) / n
    ring = radius * (np.cos(phi)[:, None] * u + np.sin(phi)[:, None] * w)
    v = np.vstack([p0 + ring, p1 + ring, p0, p1])      # 0..n-1 at p0, n..2n-1 at p1, caps' centres
    c0, c1 = 2 * n, 2 * n + 1
    tris = []
    for i in range(n):
        j = (i + 1) % n
        tris += [(i, j, n + j), (i, n + j, n + i), (c0, j, i), (c1, n + i, n + j)]
    return v, np.asarray(tris, np.int64)


def inside(points, vertices: np.ndarray, triangles: np.ndarray, chunk: int = 2_000_000) -> np.ndarray:
    """(m,) bool: which of the (m, 3) ``points`` [m] lie inside the closed triangle mesh (same frame).

    The generalised winding number (the solid angle of every triangle seen from the point, van
    Oosterom & Strackee 1983, summed over 4 pi): 1 inside a closed mesh, 0 outside, whichever way its
    triangles face; the parts of a merged hull add up. Only points in the mesh's bounding box are
    tested, ``chunk`` point-triangle pairs at a time (memory ~ 200 bytes a pair).
    """
    points = np.asarray(points, float).reshape(-1, 3)
    out = np.zeros(len(points), bool)
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    cand = np.nonzero(np.all((points >= lo) & (points <= hi), axis=1))[0]
    a0, b0, c0 = (vertices[triangles[:, k]] for k in range(3))
    step = max(1, chunk // max(len(triangles), 1))
    for start in range(0, len(cand), step):
        idx = cand[start:start + step]
        p = points[idx][:, None, :]
        a, b, c = a0[None] - p, b0[None] - p, c0[None] - p
        la, lb, lc = (np.linalg.norm(e, axis=2) for e in (a, b, c))
        det = np.einsum("ijk,ijk->ij", a, np.cross(b, c))
        den = (la * lb * lc + np.einsum("ijk,ijk->ij", a, b) * lc + np.einsum("ijk,ijk->ij", a, c) * lb
               + np.einsum("ijk,ijk->ij", b, c) * la)
        winding = np.arctan2(det, den).sum(axis=1) / (2.0 * math.pi)
        out[idx] = np.abs(winding) > 0.5
    return out
