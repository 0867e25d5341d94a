"""The contact of two convex polyhedra, and the part of one in a half-space (numba; issues 14 and
15's rigid floes and rubble blocks).

The contact of an overlap of volume V (a body's ice crushing or pressing into another's):

    S_A = sum over the overlap's faces on A's surface of their vector areas   [m^2]
    n = S_A / |S_A|   (from A towards B)   A_c = |S_A|   delta = V / A_c

S_A is minus the gradient of V with respect to a translation of B: moving B by dx changes the
overlap by -S_A . dx (tests/unit/test_polyhedra.py checks it). A normal force along n is then the
direction in which the overlap grows fastest (the "energy-conserving" direction of Feng's contact
theory for polyhedra), and A_c, the overlap's area seen along n, is where the plastic limit
sigma_c A_c of the contact law acts. For two boxes pressed face to face this is the face normal,
the overlap of the faces and the depth.

Computed from the faces of each body clipped by the other's planes (``contact_geometry_planes``):
the overlap's surface is the part of A's surface inside B with the part of B's inside A, so no cap
face is built. ``contact_geometry_clipped`` computes the same from the overlap polyhedron itself
(kernels/polyhedra.overlap): the reference of tests/unit/test_polyhedra.py.
"""

import math

import numpy as np
from numba import njit

from . import JIT
from .polyhedra import EPS, _clip_face, face_planes, fan_sums, overlap, separated, volume_centroid


@njit(**JIT)
def _inside_part(poly, count, planes, pcounts, buf):
    """The part of the convex polygon poly[:count] on the inner side (n . x <= offset + EPS) of every
    face plane (planes (F, 4): unit normal, offset; pcounts (F,): those with >= 3 vertices are faces):
    (index of buf (2, W, 3) holding it, its size; < 3 when nothing of it is inside)."""
    for k in range(count):
        buf[0, k, 0], buf[0, k, 1], buf[0, k, 2] = poly[k, 0], poly[k, 1], poly[k, 2]
    cur, n = 0, count
    for f in range(planes.shape[0]):
        if pcounts[f] < 3:
            continue
        n0, n1, n2, off = planes[f, 0], planes[f, 1], planes[f, 2], planes[f, 3]
        out = False
        inside = False
        for k in range(n):
            d = n0 * buf[cur, k, 0] + n1 * buf[cur, k, 1] + n2 * buf[cur, k, 2] - off
            if d > EPS:
                out = True
            else:
                inside = True
        if not out:
            continue
        if not inside:
            return cur, 0
        n = _clip_face(buf[cur], n, n0, n1, n2, off, buf[1 - cur])
        cur = 1 - cur
        if n < 3:
            return cur, 0
    return cur, n


@njit(**JIT)
def _coplanar(plane, planes, pcounts):
    """True when ``plane`` (4,) is one of ``planes`` (same outward normal and offset, within EPS)."""
    for f in range(planes.shape[0]):
        if (pcounts[f] >= 3 and abs(planes[f, 3] - plane[3]) <= EPS
                and planes[f, 0] * plane[0] + planes[f, 1] * plane[1] + planes[f, 2] * plane[2] >= 1.0 - 1e-12):
            return True
    return False


@njit(**JIT)
def contact_geometry_planes(a_pts, a_counts, a_planes, b_pts, b_counts, b_planes):
    """``contact_geometry`` with the face planes of A and B given (face_planes, one body each).

    The overlap's surface is the part of A's surface inside B with the part of B's surface inside A:
    each face of one clipped by the other's face planes (Sutherland-Hodgman), no cap faces to build.
    A face of B in the plane of a face of A, facing the same way, is A's (as ``overlap`` keeps it). The
    volume and centroid are sums of tetrahedra over those faces (``volume_centroid``), S_A the sum of
    the vector areas of A's parts."""
    vol, c0, c1, c2, n0, n1, n2, area, depth = contact_scalars(a_pts, a_counts, a_planes, b_pts, b_counts, b_planes,
                                                                contact_buffer(a_pts, a_planes, b_pts, b_planes))
    centre = np.full(3, np.nan)
    normal = np.zeros(3)
    if vol <= 0.0:
        return 0.0, centre, normal, 0.0, 0.0
    centre[0], centre[1], centre[2] = c0, c1, c2
    normal[0], normal[1], normal[2] = n0, n1, n2
    return vol, centre, normal, area, depth


@njit(**JIT)
def contact_buffer(a_pts, a_planes, b_pts, b_planes):
    """The work array ``contact_scalars`` needs for polyhedra of these shapes (one per kernel call)."""
    width = max(a_pts.shape[1], b_pts.shape[1]) + a_planes.shape[0] + b_planes.shape[0] + 1
    return np.empty((2, width, 3))


@njit(**JIT)
def contact_scalars(a_pts, a_counts, a_planes, b_pts, b_counts, b_planes, buf):
    """``contact_geometry_planes`` in scalars, with its work array ``buf`` (``contact_buffer``) given,
    so that a kernel's loop over pairs allocates nothing: (volume [m^3], centroid (3 scalars) [m],
    unit normal from A towards B (3 scalars), contact area [m^2], depth [m]); volume 0 when apart
    (the rest then meaningless)."""
    vol = c0 = c1 = c2 = s0 = s1 = s2 = 0.0
    r0 = r1 = r2 = 0.0
    have_ref = False
    for side in range(2):
        pts, counts = (a_pts, a_counts) if side == 0 else (b_pts, b_counts)
        planes, pcounts = (b_planes, b_counts) if side == 0 else (a_planes, a_counts)
        for f in range(counts.shape[0]):
            if counts[f] < 3:
                continue
            if side == 1 and _coplanar(b_planes[f], a_planes, a_counts):
                continue
            cur, m = _inside_part(pts[f], counts[f], planes, pcounts, buf)
            if m < 3:
                continue
            p = buf[cur]
            if not have_ref:
                r0, r1, r2 = p[0, 0], p[0, 1], p[0, 2]
                have_ref = True
            v6, m0, m1, m2, a0, a1, a2 = fan_sums(p, m, r0, r1, r2)
            vol, c0, c1, c2 = vol + v6, c0 + m0, c1 + m1, c2 + m2
            if side == 0:  # S_A: the vector areas of A's parts
                s0, s1, s2 = s0 + a0, s1 + a1, s2 + a2
    return overlap_scalars(vol, c0, c1, c2, s0, s1, s2, r0, r1, r2)


@njit(**JIT)
def overlap_scalars(vol6, c0, c1, c2, s0, s1, s2, r0, r1, r2):
    """The contact from the overlap's sums over its faces (``fan_sums`` from the apex r): 6 V, the
    moments c, S_A; (volume [m^3], centroid (3 scalars) [m], unit normal S_A / |S_A| (3 scalars), contact
    area |S_A| [m^2], depth V / |S_A| [m]), all zero when vol6 <= 0 (apart)."""
    if vol6 <= 0.0:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    k0, k1, k2 = c0 / (4.0 * vol6) + r0, c1 / (4.0 * vol6) + r1, c2 / (4.0 * vol6) + r2
    vol = vol6 / 6.0
    area = math.sqrt(s0 * s0 + s1 * s1 + s2 * s2)
    if area <= 0.0:
        return vol, k0, k1, k2, 0.0, 0.0, 0.0, 0.0, 0.0
    return vol, k0, k1, k2, s0 / area, s1 / area, s2 / area, area, vol / area


@njit(**JIT)
def part_inside(pts, counts, n0, n1, n2, offset, buf, e0=0.0, e1=0.0):
    """(volume [m^3], centroid (3,) [m], area of the cut [m^2], lo, hi [m], zmin [m]) of the part of a
    convex polyhedron with n . x <= offset (n a unit vector): its faces clipped to the half-space, and no
    cap face built. With the tetrahedra's apex on the plane (at offset n) the cap adds no volume nor
    moment, and its area is |the sum of the clipped faces' vector areas| (a closed surface's vector
    areas sum to zero). lo, hi: the extent of the part's vertices along the horizontal (e0, e1), zmin
    their lowest z (a floe's submerged part across the flow: kernels/floe_hydro.py). buf: work array
    (2, W, 3), W >= the faces' vertices + 1. Volume 0 when nothing is inside."""
    r0, r1, r2 = offset * n0, offset * n1, offset * n2
    vol = c0 = c1 = c2 = s0 = s1 = s2 = 0.0
    lo, hi, zmin = math.inf, -math.inf, math.inf
    for f in range(counts.shape[0]):
        if counts[f] < 3:
            continue
        m = _clip_face(pts[f], counts[f], n0, n1, n2, offset, buf[0])
        if m < 3:
            continue
        p = buf[0]
        for i in range(m):
            across = p[i, 0] * e0 + p[i, 1] * e1
            lo, hi, zmin = min(lo, across), max(hi, across), min(zmin, p[i, 2])
        v6, m0, m1, m2, a0, a1, a2 = fan_sums(p, m, r0, r1, r2)
        vol, c0, c1, c2, s0, s1, s2 = vol + v6, c0 + m0, c1 + m1, c2 + m2, s0 + a0, s1 + a1, s2 + a2
    centre = np.full(3, np.nan)
    if vol <= 0.0:
        return 0.0, centre, 0.0, lo, hi, zmin
    centre[0], centre[1], centre[2] = c0 / (4.0 * vol) + r0, c1 / (4.0 * vol) + r1, c2 / (4.0 * vol) + r2
    return vol / 6.0, centre, math.sqrt(s0 * s0 + s1 * s1 + s2 * s2), lo, hi, zmin


@njit(**JIT)
def contact_geometry(a_pts, a_counts, b_pts, b_counts):
    """(overlap volume [m^3], its centroid (3,) [m], unit normal from A towards B, contact area A_c
    [m^2], depth delta = V / A_c [m]) of two convex polyhedra (module docstring); volume 0 when apart.
    Computed from the faces of each clipped by the other (``contact_geometry_planes``); ``overlap``,
    the clipped polyhedron itself, gives the same to round-off (tests/unit/test_polyhedra.py)."""
    pa = face_planes(a_pts.reshape((1,) + a_pts.shape), a_counts.reshape((1,) + a_counts.shape))[0]
    pb = face_planes(b_pts.reshape((1,) + b_pts.shape), b_counts.reshape((1,) + b_counts.shape))[0]
    return contact_geometry_planes(a_pts, a_counts, pa, b_pts, b_counts, pb)


@njit(**JIT)
def contact_geometry_clipped(a_pts, a_counts, b_pts, b_counts):
    """``contact_geometry`` from the overlap polyhedron itself (``overlap``: A clipped by B's planes,
    with cap faces): the reference the face-clipping computation is tested against."""
    if separated(a_pts, a_counts, b_pts, b_counts):
        return 0.0, np.full(3, np.nan), np.zeros(3), 0.0, 0.0
    pts, counts, side = overlap(a_pts, a_counts, b_pts, b_counts)
    vol, centre = volume_centroid(pts, counts)
    normal = np.zeros(3)
    if vol <= 0.0:
        return 0.0, centre, normal, 0.0, 0.0
    s = np.zeros(3)
    for f in range(counts.shape[0]):
        if counts[f] < 3 or side[f] != 0:
            continue
        for i in range(1, counts[f] - 1):
            a = pts[f, i] - pts[f, 0]
            b = pts[f, i + 1] - pts[f, 0]
            s[0] += 0.5 * (a[1] * b[2] - a[2] * b[1])
            s[1] += 0.5 * (a[2] * b[0] - a[0] * b[2])
            s[2] += 0.5 * (a[0] * b[1] - a[1] * b[0])
    area = math.sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2])
    if area <= 0.0:
        return vol, centre, normal, 0.0, 0.0
    return vol, centre, s / area, area, vol / area
