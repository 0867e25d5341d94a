"""The contact of two boxes (rectangular cuboids: the keel's rubble blocks, issue 15), the same contact as
kernels/polyhedron_contact.contact_scalars computes for any two convex polyhedra, in fewer operations
(numba, scalars in and out).

A box is its centre c [m], its rotation R (3, 3) (body to space) and its half extents h (3,) [m] along
its body axes. The overlap's faces are each box's faces clipped by the other box (as in the general
kernel), computed in A's body frame, where A is the axis-aligned box |x_e| <= h_e:

- The line between the centres separates most neighbours that do not touch (three projections a box),
  and the 15 axes of oriented boxes (``_separated``) most of the rest.
- B's corners in A's frame, A's corners in B's frame (16 rotations), and each corner's outcode: a bit for
  each of the other box's six face planes it is outside of (more than EPS beyond, as the general clip).
- A face whose four corners are all outside one plane (their codes share a bit) has no part inside the
  other box and is skipped; the others are clipped only by the planes some corner is outside of (a
  convex polygon whose corners are inside a plane lies inside it). Two boxes are apart when all eight corners of one share a bit (a face axis separates
  them): no face survives.
- A's faces are clipped in B's frame and the pieces turned into A's frame; the tetrahedra fanned from
  one apex then give the volume and centroid, and A's pieces the vector area S_A, as in
  polyhedron_contact.contact_scalars; the centroid and normal are turned into space last.

Measured (benchmarks/keel_contacts.py, the narrow keel's 4,788 blocks, 15,076 overlapping pairs, one
rank): the overlap geometry 1.13 against 1.47 us a pair, and with the pair's work moved into the loop of
floe_contacts (no call of two dozen arguments) the block-block contacts 19.7 against 32.0 ms a step and
the step 23.4 against 36.6 ms (docs/ridge_keel.md, "The box kernel").

The two kernels agree to round-off on exact boxes (tests/unit/test_box_contact.py). The keel's blocks
as built (a rectangle turned into its principal axes) have their corners within 2e-10 m of +-h, which
this kernel takes as exact; so on the narrow keel (the 29,790 pairs whose boxes meet) both kernels find
the same 15,070 overlaps, and the overlaps' depths differ by about that 2e-10 m: their volumes by up to
1e-4 relative at 1-10 um deep, 1e-5 at 10-100 um (most contacts), 6e-7 beyond; a normal force of
k_n 2e-10 m = 2 mN at seed 002's k_n.
"""

import numpy as np
from numba import njit

from . import JIT
from .polyhedra import EPS, _clip_face, fan_sums
from .polyhedron_contact import overlap_scalars


def _face_table() -> np.ndarray:
    """(6, 4) the corners of each face of a box, counter-clockwise seen from outside. Corner k has
    body coordinates s_e h_e with s_e = +1 where bit e of k is set, else -1; face 2 e + 0 is the face
    x_e = +h_e, face 2 e + 1 the face x_e = -h_e."""
    table = np.empty((6, 4), np.int64)
    for e in range(3):
        u, v = (e + 1) % 3, (e + 2) % 3
        ring = [(-1, -1), (1, -1), (1, 1), (-1, 1)]  # in (u, v): counter-clockwise about +e
        for side, sign in ((0, 1), (1, -1)):
            seq = ring if sign > 0 else ring[::-1]
            for k, (su, sv) in enumerate(seq):
                corner = (1 << e if sign > 0 else 0) | (1 << u if su > 0 else 0) | (1 << v if sv > 0 else 0)
                table[2 * e + side, k] = corner
    return table


FACES = _face_table()


@njit(**JIT)
def box_buffer():
    """The work array of ``box_contact_scalars`` (one per kernel call): room for a face clipped by six
    planes, twice."""
    return np.empty((2, 12, 3))


@njit(inline="always", **JIT)
def _corners(t0, t1, t2, R, h, out, codes, g):
    """The eight corners t + R (s * h) into out (8, 3), and their outcodes against the box |x_e| <= g_e
    into codes (8,) (bit 2 e: x_e > g_e + EPS; bit 2 e + 1: x_e < -g_e - EPS). Returns the AND of the
    codes (nonzero: one plane has every corner outside)."""
    both = 63
    for k in range(8):
        s0 = h[0] if k & 1 else -h[0]
        s1 = h[1] if k & 2 else -h[1]
        s2 = h[2] if k & 4 else -h[2]
        c = 0
        for e in range(3):
            p = t0 if e == 0 else (t1 if e == 1 else t2)
            p += R[e, 0] * s0 + R[e, 1] * s1 + R[e, 2] * s2
            out[k, e] = p
            if p > g[e] + EPS:
                c |= 1 << (2 * e)
            elif p < -g[e] - EPS:
                c |= 1 << (2 * e + 1)
        codes[k] = c
        both &= c
    return both


@njit(inline="always", **JIT)
def _separated(t0, t1, t2, R, ha, hb):
    """True when one of the 15 separating axes of two boxes (A's three face normals, B's three, and the
    nine products of an edge of each) parts them by more than EPS; B at t in A's frame, turned by R
    (the test of oriented bounding boxes: Gottschalk, Lin & Manocha 1996). An axis along two parallel
    edges has length ~0 and separates nothing here, so it needs no special case."""
    t = (t0, t1, t2)
    for i in range(3):  # A's face normals
        if abs(t[i]) > ha[i] + hb[0] * abs(R[i, 0]) + hb[1] * abs(R[i, 1]) + hb[2] * abs(R[i, 2]) + EPS:
            return True
    for j in range(3):  # B's
        if (abs(t0 * R[0, j] + t1 * R[1, j] + t2 * R[2, j])
                > hb[j] + ha[0] * abs(R[0, j]) + ha[1] * abs(R[1, j]) + ha[2] * abs(R[2, j]) + EPS):
            return True
    for i in range(3):  # the edges' products A_i x B_j
        i1, i2 = (i + 1) % 3, (i + 2) % 3
        for j in range(3):
            j1, j2 = (j + 1) % 3, (j + 2) % 3
            ra = ha[i1] * abs(R[i2, j]) + ha[i2] * abs(R[i1, j])
            rb = hb[j1] * abs(R[i, j2]) + hb[j2] * abs(R[i, j1])
            if abs(t[i2] * R[i1, j] - t[i1] * R[i2, j]) > ra + rb + EPS:
                return True
    return False


@njit(inline="always", **JIT)
def _face_inside(corner, codes, f, g, buf):
    """Face f of a box, its corners given in the other box's frame (corner (8, 3), codes (8,)), clipped to
    that box |x_e| <= g_e: (index of buf holding it, its size; < 3 when nothing of it is inside)."""
    k0, k1, k2, k3 = FACES[f, 0], FACES[f, 1], FACES[f, 2], FACES[f, 3]
    c0, c1, c2, c3 = codes[k0], codes[k1], codes[k2], codes[k3]
    if c0 & c1 & c2 & c3:
        return 0, 0
    for q, k in enumerate((k0, k1, k2, k3)):
        buf[0, q, 0], buf[0, q, 1], buf[0, q, 2] = corner[k, 0], corner[k, 1], corner[k, 2]
    out = c0 | c1 | c2 | c3
    cur, n = 0, 4
    for b in range(6):
        if out & (1 << b):
            e, sign = b >> 1, 1.0 if b & 1 == 0 else -1.0  # the plane sign * x_e = g_e
            n = _clip_face(buf[cur], n, sign if e == 0 else 0.0, sign if e == 1 else 0.0, sign if e == 2 else 0.0,
                           g[e], buf[1 - cur])
            cur = 1 - cur
            if n < 3:
                return cur, 0
    return cur, n


@njit(**JIT)
def box_contact_scalars(ca, Ra, ha, cb, Rb, hb, buf, corner_a, corner_b, codes_a, codes_b, R, Rt):
    """The contact of boxes A (centre ca (3,) [m], rotation Ra (3, 3), half extents ha (3,) [m]) and B,
    as polyhedron_contact.contact_scalars gives it for their polyhedra: (volume [m^3], centroid (3
    scalars) [m], unit normal from A towards B (3 scalars), contact area [m^2], depth [m]); volume 0
    when apart (the rest then meaningless). buf: ``box_buffer``; corner_a, corner_b (8, 3), codes_a,
    codes_b (8,) int64, R, Rt (3, 3): work arrays (a kernel's loop over pairs allocates nothing)."""
    d0, d1, d2 = cb[0] - ca[0], cb[1] - ca[1], cb[2] - ca[2]
    # the line between the centres first (a packed pile's neighbours mostly part along it): each box's
    # half-width along d is sum_e h_e |d . R e_e|, and they are apart when the two leave |d|^2 between
    reach = 0.0
    for e in range(3):
        reach += ha[e] * abs(d0 * Ra[0, e] + d1 * Ra[1, e] + d2 * Ra[2, e])
        reach += hb[e] * abs(d0 * Rb[0, e] + d1 * Rb[1, e] + d2 * Rb[2, e])
    if d0 * d0 + d1 * d1 + d2 * d2 > reach:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    # B's pose in A's frame: t = Ra^T (cb - ca), R = Ra^T Rb
    t0 = Ra[0, 0] * d0 + Ra[1, 0] * d1 + Ra[2, 0] * d2
    t1 = Ra[0, 1] * d0 + Ra[1, 1] * d1 + Ra[2, 1] * d2
    t2 = Ra[0, 2] * d0 + Ra[1, 2] * d1 + Ra[2, 2] * d2
    for r in range(3):
        for c in range(3):
            R[r, c] = Ra[0, r] * Rb[0, c] + Ra[1, r] * Rb[1, c] + Ra[2, r] * Rb[2, c]
    if _separated(t0, t1, t2, R, ha, hb):
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    # B's corners in A's frame against A
    if _corners(t0, t1, t2, R, hb, corner_b, codes_b, ha):
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    # A's corners in B's frame against B: A's centre there is -R^T t, its rotation R^T
    for r in range(3):
        for c in range(3):
            Rt[r, c] = R[c, r]
    u0 = -(R[0, 0] * t0 + R[1, 0] * t1 + R[2, 0] * t2)
    u1 = -(R[0, 1] * t0 + R[1, 1] * t1 + R[2, 1] * t2)
    u2 = -(R[0, 2] * t0 + R[1, 2] * t1 + R[2, 2] * t2)
    if _corners(u0, u1, u2, Rt, ha, corner_a, codes_a, hb):
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    vol = c0 = c1 = c2 = s0 = s1 = s2 = 0.0
    r0 = r1 = r2 = 0.0
    have_ref = False
    for side in range(2):
        for f in range(6):
            if side == 0:  # A's face f, clipped in B's frame, turned into A's
                cur, m = _face_inside(corner_a, codes_a, f, hb, buf)
                if m < 3:
                    continue
                p = buf[cur]
                for k in range(m):
                    q0, q1, q2 = p[k, 0], p[k, 1], p[k, 2]
                    p[k, 0] = t0 + R[0, 0] * q0 + R[0, 1] * q1 + R[0, 2] * q2
                    p[k, 1] = t1 + R[1, 0] * q0 + R[1, 1] * q1 + R[1, 2] * q2
                    p[k, 2] = t2 + R[2, 0] * q0 + R[2, 1] * q1 + R[2, 2] * q2
            else:  # B's face f, clipped in A's frame; one in the plane of a face of A, facing the same way, is A's
                e, sign = f >> 1, 1.0 if f & 1 == 0 else -1.0
                cur, m = _face_inside(corner_b, codes_b, f, ha, buf)
                if m < 3 or _coplanar_face(R, e, sign, corner_b[FACES[f, 0]], ha):
                    continue
                p = buf[cur]
            if not have_ref:
                r0, r1, r2 = p[0, 0], p[0, 1], p[0, 2]
                have_ref = True
            v6, m0, m1, m2, a0, a1, a2 = fan_sums(p, m, r0, r1, r2)
            vol, c0, c1, c2 = vol + v6, c0 + m0, c1 + m1, c2 + m2
            if side == 0:
                s0, s1, s2 = s0 + a0, s1 + a1, s2 + a2
    vol, k0, k1, k2, n0, n1, n2, area, depth = overlap_scalars(vol, c0, c1, c2, s0, s1, s2, r0, r1, r2)
    if vol <= 0.0:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    # into space: the centroid ca + Ra k, the normal Ra n
    w0 = ca[0] + Ra[0, 0] * k0 + Ra[0, 1] * k1 + Ra[0, 2] * k2
    w1 = ca[1] + Ra[1, 0] * k0 + Ra[1, 1] * k1 + Ra[1, 2] * k2
    w2 = ca[2] + Ra[2, 0] * k0 + Ra[2, 1] * k1 + Ra[2, 2] * k2
    m0 = Ra[0, 0] * n0 + Ra[0, 1] * n1 + Ra[0, 2] * n2
    m1 = Ra[1, 0] * n0 + Ra[1, 1] * n1 + Ra[1, 2] * n2
    m2 = Ra[2, 0] * n0 + Ra[2, 1] * n1 + Ra[2, 2] * n2
    return vol, w0, w1, w2, m0, m1, m2, area, depth


@njit(inline="always", **JIT)
def _coplanar_face(R, e, sign, point, ha):
    """True when B's face along its axis e, side sign (outward normal sign R[:, e] in A's frame, through
    ``point``), lies in the plane of a face of A facing the same way (normals within 1e-12, offsets
    within EPS, as polyhedron_contact._coplanar)."""
    for a in range(3):
        dot = sign * R[a, e]
        if dot >= 1.0 - 1e-12 and abs(point[a] - ha[a]) <= EPS:
            return True
        if -dot >= 1.0 - 1e-12 and abs(-point[a] - ha[a]) <= EPS:
            return True
    return False


@njit(**JIT)
def box_half_extents(body_pts, counts, rel=1e-9):
    """(n, 3) half extents [m] of n body-frame polyhedra (n, F, V, 3) when every one is a box centred on
    its origin with its faces across its body axes (6 faces of 4 corners, each corner at +-h_e within
    rel h_e), else an empty (0, 3) array: the box kernel then does not apply."""
    n = body_pts.shape[0]
    none = np.empty((0, 3))
    if counts.shape[1] < 6:
        return none
    h = np.zeros((n, 3))
    for i in range(n):
        faces = 0
        for f in range(counts.shape[1]):
            if counts[i, f] == 0:
                continue
            if counts[i, f] != 4:
                return none
            faces += 1
            for k in range(4):
                for e in range(3):
                    h[i, e] = max(h[i, e], abs(body_pts[i, f, k, e]))
        if faces != 6:
            return none
        for f in range(counts.shape[1]):
            for k in range(counts[i, f]):
                for e in range(3):
                    if abs(abs(body_pts[i, f, k, e]) - h[i, e]) > rel * h[i, e]:
                        return none
    return h
