"""Convex polyhedra: the overlap of two, and the contact it defines (numba; issues 14 and 15's rigid
floes and rubble blocks, both convex: prisms and boxes).

A polyhedron is given by its faces: ``pts`` (F, V, 3) [m] with ``counts`` (F,) vertices each (0 for
an unused face; ``faces_array`` pads to MAX_FACES x MAX_FACE_VERTS, and a clip returns arrays one face
and one point wider than it was given), every face convex and counter-clockwise seen
from outside. The overlap A n B is A clipped by every face plane of B (Sutherland-Hodgman on each
face, and a cap face on the cutting plane from the new points). Each face of the overlap remembers
whether it lies on the surface of A (0) or of B (1).

The contact two polyhedra make (its volume, normal, area and depth) is kernels/polyhedron_contact.py.
"""

import math

import numpy as np
from numba import njit

from . import JIT

MAX_FACES = 48       # faces of one body or overlap (a floe prism of 16 sides has 18)
MAX_FACE_VERTS = 40  # vertices of one face after clipping
EPS = 1e-12          # [m] a point within this of a plane lies on it


@njit(**JIT)
def _clip_face(src, n_src, n0, n1, n2, offset, out):
    """Clip the convex polygon src[:n_src] to n . x <= offset; write it to out; return its size."""
    m = 0
    for i in range(n_src):
        j = i + 1 if i + 1 < n_src else 0
        da = n0 * src[i, 0] + n1 * src[i, 1] + n2 * src[i, 2] - offset
        db = n0 * src[j, 0] + n1 * src[j, 1] + n2 * src[j, 2] - offset
        if da <= EPS:
            out[m, 0], out[m, 1], out[m, 2] = src[i, 0], src[i, 1], src[i, 2]
            m += 1
        if (da < -EPS and db > EPS) or (da > EPS and db < -EPS):
            t = da / (da - db)
            for e in range(3):
                out[m, e] = src[i, e] + t * (src[j, e] - src[i, e])
            m += 1
    return m


@njit(**JIT)
def _cap(pts, count, n0, n1, n2, out, uniq, ang, order):
    """The points on a cutting plane (normal n) as one convex polygon, counter-clockwise seen along +n;
    duplicates (within EPS) dropped. Returns its size. uniq, ang, order: work arrays of >= count rows."""
    k = 0
    for i in range(count):
        dup = False
        for j in range(k):
            d0, d1, d2 = pts[i, 0] - uniq[j, 0], pts[i, 1] - uniq[j, 1], pts[i, 2] - uniq[j, 2]
            if d0 * d0 + d1 * d1 + d2 * d2 <= 1e-18:
                dup = True
                break
        if not dup:
            uniq[k, 0], uniq[k, 1], uniq[k, 2] = pts[i, 0], pts[i, 1], pts[i, 2]
            k += 1
    if k < 3:
        return 0
    c0 = c1 = c2 = 0.0
    for i in range(k):
        c0 += uniq[i, 0]
        c1 += uniq[i, 1]
        c2 += uniq[i, 2]
    c0, c1, c2 = c0 / k, c1 / k, c2 / k
    # a basis (u, v) of the plane with u x v = normal
    r0, r1, r2 = (1.0, 0.0, 0.0) if abs(n0) < 0.9 else (0.0, 1.0, 0.0)
    dot = r0 * n0 + r1 * n1 + r2 * n2
    u0, u1, u2 = r0 - dot * n0, r1 - dot * n1, r2 - dot * n2
    norm = math.sqrt(u0 * u0 + u1 * u1 + u2 * u2)
    u0, u1, u2 = u0 / norm, u1 / norm, u2 / norm
    v0, v1, v2 = n1 * u2 - n2 * u1, n2 * u0 - n0 * u2, n0 * u1 - n1 * u0
    for i in range(k):  # the angles, insertion-sorted (a handful of points: no allocation)
        d0, d1, d2 = uniq[i, 0] - c0, uniq[i, 1] - c1, uniq[i, 2] - c2
        a = math.atan2(d0 * v0 + d1 * v1 + d2 * v2, d0 * u0 + d1 * u1 + d2 * u2)
        j = i
        while j > 0 and ang[j - 1] > a:
            ang[j], order[j] = ang[j - 1], order[j - 1]
            j -= 1
        ang[j], order[j] = a, i
    for i in range(k):
        out[i, 0], out[i, 1], out[i, 2] = uniq[order[i], 0], uniq[order[i], 1], uniq[order[i], 2]
    return k


@njit(**JIT)
def _plane(poly, count):
    """(n0, n1, n2, offset) of a convex face's plane, its unit outward normal in scalars (no array)."""
    s0 = s1 = s2 = 0.0
    p0, p1, p2 = poly[0, 0], poly[0, 1], poly[0, 2]
    for i in range(1, count - 1):
        a0, a1, a2 = poly[i, 0] - p0, poly[i, 1] - p1, poly[i, 2] - p2
        b0, b1, b2 = poly[i + 1, 0] - p0, poly[i + 1, 1] - p1, poly[i + 1, 2] - p2
        s0 += a1 * b2 - a2 * b1
        s1 += a2 * b0 - a0 * b2
        s2 += a0 * b1 - a1 * b0
    norm = math.sqrt(s0 * s0 + s1 * s1 + s2 * s2)
    s0, s1, s2 = s0 / norm, s1 / norm, s2 / norm
    return s0, s1, s2, s0 * p0 + s1 * p1 + s2 * p2


@njit(**JIT)
def face_plane(poly, count):
    """(unit outward normal (3,), offset) of a convex face: normal . x = offset on it."""
    n0, n1, n2, offset = _plane(poly, count)
    s = np.empty(3)
    s[0], s[1], s[2] = n0, n1, n2
    return s, offset


@njit(**JIT)
def _clip_into(pts, counts, side, n0, n1, n2, offset, tag, out, ocounts, oside, tmp, cut, uniq, ang, order):
    """The convex polyhedron (pts, counts, side) cut to n . x <= offset, written to (out, ocounts,
    oside) with the cap on the plane tagged ``tag``; returns its face count, 0 when nothing is kept,
    or -1 when nothing lies beyond the plane (out untouched: the polyhedron is unchanged). out holds
    one face more than pts and one point more per face (and as many as its faces); tmp, cut, uniq,
    ang, order: work arrays (``clip`` sizes them)."""
    n_faces = counts.shape[0]
    outside = False
    for f in range(n_faces):
        for i in range(counts[f]):
            if n0 * pts[f, i, 0] + n1 * pts[f, i, 1] + n2 * pts[f, i, 2] - offset > EPS:
                outside = True
                break
        if outside:
            break
    if not outside:
        return -1
    ocounts[:] = 0
    nfaces = 0
    ncut = 0
    for f in range(n_faces):
        if counts[f] < 3:
            continue
        m = _clip_face(pts[f], counts[f], n0, n1, n2, offset, tmp)
        for i in range(m):  # points on the cutting plane close the cap
            d = n0 * tmp[i, 0] + n1 * tmp[i, 1] + n2 * tmp[i, 2] - offset
            if abs(d) <= 1e-9 and ncut < cut.shape[0]:
                cut[ncut] = tmp[i]
                ncut += 1
        if m >= 3:
            out[nfaces, :m] = tmp[:m]
            ocounts[nfaces] = m
            oside[nfaces] = side[f]
            nfaces += 1
    if nfaces == 0:
        return 0
    k = _cap(cut, ncut, n0, n1, n2, tmp, uniq, ang, order)
    if k >= 3:
        out[nfaces, :k] = tmp[:k]
        ocounts[nfaces] = k
        oside[nfaces] = tag
        nfaces += 1
    return nfaces


@njit(**JIT)
def clip(pts, counts, side, normal, offset, tag):
    """The convex polyhedron (pts, counts, side) cut to normal . x <= offset: (pts, counts, side) of the
    part kept, the cap on the plane tagged ``tag`` (module docstring). Unchanged when nothing lies
    beyond the plane (a face may lie in it); every count 0 when nothing is kept."""
    n_faces = pts.shape[0]
    # room for one more face (the cap) and one more point per face (a cut adds at most one), and for a
    # cap through every face: the arrays grow with each cut, so tightly sized inputs are safe
    width = max(pts.shape[1] + 1, n_faces + 1)
    nxt = np.empty((n_faces + 1, width, 3))  # only the first counts[f] points of a face are ever read
    ncounts = np.zeros(n_faces + 1, np.int64)
    nside = np.zeros(n_faces + 1, np.int64)
    tmp = np.empty((width, 3))
    cut = np.empty((2 * n_faces, 3))
    uniq = np.empty((2 * n_faces, 3))
    ang = np.empty(2 * n_faces)
    order = np.empty(2 * n_faces, np.int64)
    if _clip_into(pts, counts, side, normal[0], normal[1], normal[2], offset, tag, nxt, ncounts, nside, tmp, cut,
                  uniq, ang, order) < 0:
        return pts, counts, side
    return nxt, ncounts, nside


@njit(**JIT)
def overlap(a_pts, a_counts, b_pts, b_counts):
    """A n B of two convex polyhedra (module docstring): (pts, counts, side) of its faces, side 0 on A's
    surface and 1 on B's. Empty (every count 0) when they do not overlap. The clips by B's faces go
    back and forth between two buffers sized once for the largest result (each adds at most one face,
    and one point to a face)."""
    nfa, nfb = a_counts.shape[0], b_counts.shape[0]
    faces = nfa + nfb
    width = max(a_pts.shape[1] + nfb, faces) + 1
    buf = np.empty((2, faces, width, 3))
    cnt = np.zeros((2, faces), np.int64)
    sd = np.zeros((2, faces), np.int64)
    buf[0, :nfa, :a_pts.shape[1]] = a_pts
    cnt[0, :nfa] = a_counts
    tmp = np.empty((width, 3))
    cut = np.empty((2 * faces, 3))
    uniq = np.empty((2 * faces, 3))
    ang = np.empty(2 * faces)
    order = np.empty(2 * faces, np.int64)
    cur = 0
    for fb in range(nfb):
        if b_counts[fb] < 3:
            continue
        n0, n1, n2, offset = _plane(b_pts[fb], b_counts[fb])
        kept = _clip_into(buf[cur], cnt[cur], sd[cur], n0, n1, n2, offset, 1, buf[1 - cur], cnt[1 - cur],
                          sd[1 - cur], tmp, cut, uniq, ang, order)
        if kept < 0:
            continue
        cur = 1 - cur
        if kept == 0:
            break
    return buf[cur], cnt[cur], sd[cur]


@njit(**JIT)
def fan_sums(p, m, r0, r1, r2):
    """The convex polygon p[:m] fanned from p[0] into triangles, each the base of a tetrahedron with
    apex (r0, r1, r2): (sum of 6 x their signed volumes [m^3], sum of 6 V x (the tetrahedra's four
    vertices' sum less 4 apex) (3) [m^4], the polygon's vector area (3) [m^2]). Over a closed outward
    surface the first is 6 V, the next give the centroid (/ 4 / 6 V + apex), the area sums to zero.
    Scalars only: no temporaries."""
    vol = c0 = c1 = c2 = s0 = s1 = s2 = 0.0
    a0, a1, a2 = p[0, 0] - r0, p[0, 1] - r1, p[0, 2] - r2
    for i in range(1, m - 1):
        b0, b1, b2 = p[i, 0] - r0, p[i, 1] - r1, p[i, 2] - r2
        d0, d1, d2 = p[i + 1, 0] - r0, p[i + 1, 1] - r1, p[i + 1, 2] - r2
        v6 = a0 * (b1 * d2 - b2 * d1) - a1 * (b0 * d2 - b2 * d0) + a2 * (b0 * d1 - b1 * d0)
        vol += v6
        c0 += v6 * (a0 + b0 + d0)
        c1 += v6 * (a1 + b1 + d1)
        c2 += v6 * (a2 + b2 + d2)
        f0, f1, f2 = b0 - a0, b1 - a1, b2 - a2
        g0, g1, g2 = d0 - a0, d1 - a1, d2 - a2
        s0 += 0.5 * (f1 * g2 - f2 * g1)
        s1 += 0.5 * (f2 * g0 - f0 * g2)
        s2 += 0.5 * (f0 * g1 - f1 * g0)
    return vol, c0, c1, c2, s0, s1, s2


@njit(**JIT)
def volume_centroid(pts, counts):
    """(volume [m^3], centroid (3,) [m]) of a closed polyhedron given by its faces (0, NaN if empty)."""
    ref = np.zeros(3)
    found = False
    for f in range(counts.shape[0]):
        if counts[f] >= 3:
            ref = pts[f, 0].copy()
            found = True
            break
    c = np.zeros(3)
    if not found:
        return 0.0, np.full(3, np.nan)
    vol = c0 = c1 = c2 = 0.0
    r0, r1, r2 = ref[0], ref[1], ref[2]
    for f in range(counts.shape[0]):
        v6, m0, m1, m2, _, _, _ = fan_sums(pts[f], counts[f], r0, r1, r2)
        vol, c0, c1, c2 = vol + v6, c0 + m0, c1 + m1, c2 + m2
    c[0], c[1], c[2] = c0 / (4.0 * vol) + r0, c1 / (4.0 * vol) + r1, c2 / (4.0 * vol) + r2
    if vol <= 0.0:
        return 0.0, np.full(3, np.nan)
    return vol / 6.0, c


@njit(**JIT)
def _beyond(normal, offset, pts, counts):
    """True when every vertex of (pts, counts) lies beyond the plane normal . x = offset (by EPS)."""
    for f in range(counts.shape[0]):
        for i in range(counts[f]):
            if normal[0] * pts[f, i, 0] + normal[1] * pts[f, i, 1] + normal[2] * pts[f, i, 2] - offset <= EPS:
                return False
    return True


@njit(**JIT)
def separated(a_pts, a_counts, b_pts, b_counts):
    """True when a face plane of A or of B has the other body wholly outside it: the two cannot overlap.
    (False does not prove an overlap: ``overlap`` decides; this is the cheap test first.)"""
    for f in range(a_counts.shape[0]):
        if a_counts[f] >= 3:
            normal, offset = face_plane(a_pts[f], a_counts[f])
            if _beyond(normal, offset, b_pts, b_counts):
                return True
    for f in range(b_counts.shape[0]):
        if b_counts[f] >= 3:
            normal, offset = face_plane(b_pts[f], b_counts[f])
            if _beyond(normal, offset, a_pts, a_counts):
                return True
    return False


@njit(**JIT)
def face_planes(pts, counts):
    """(n, F, 4) the face planes (unit outward normal, offset) of n polyhedra; unused faces zero."""
    out = np.zeros((pts.shape[0], pts.shape[1], 4))
    for k in range(pts.shape[0]):
        for f in range(pts.shape[1]):
            m = counts[k, f]
            if m < 3:
                continue
            out[k, f, 0], out[k, f, 1], out[k, f, 2], out[k, f, 3] = _plane(pts[k, f], m)
    return out


@njit(**JIT)
def separated_by_planes(planes, counts, pts, other_counts):
    """True when one of the face planes (F, 4) of a polyhedron with face counts ``counts`` has the
    other polyhedron (pts, other_counts) wholly outside: ``separated`` with the planes computed once."""
    for f in range(planes.shape[0]):
        if counts[f] >= 3 and _beyond(planes[f, :3], planes[f, 3], pts, other_counts):
            return True
    return False


def faces_array(faces) -> tuple[np.ndarray, np.ndarray]:
    """(pts, counts) of ``faces``, a list of (k, 3) arrays (convex, counter-clockwise from outside)."""
    if len(faces) > MAX_FACES:
        raise ValueError(f"{len(faces)} faces: at most {MAX_FACES}")
    pts = np.zeros((MAX_FACES, MAX_FACE_VERTS, 3))
    counts = np.zeros(MAX_FACES, np.int64)
    for f, face in enumerate(faces):
        face = np.asarray(face, float)
        pts[f, :len(face)] = face
        counts[f] = len(face)
    return pts, counts


def prism(polygon, z0: float, z1: float) -> tuple[np.ndarray, np.ndarray]:
    """(pts, counts) of the right prism over a convex polygon (k, 2) [m] (counter-clockwise in x-y)
    from z0 to z1 [m]: a floe, or with a rectangle a box."""
    p = np.asarray(polygon, float)
    bottom = np.column_stack([p[::-1], np.full(len(p), z0)])
    top = np.column_stack([p, np.full(len(p), z1)])
    sides = [np.array([[*p[i], z0], [*p[(i + 1) % len(p)], z0], [*p[(i + 1) % len(p)], z1], [*p[i], z1]])
             for i in range(len(p))]
    return faces_array([bottom, top] + sides)
