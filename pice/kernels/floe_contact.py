"""Contact between rigid convex floes (issue 14: seed 003's viscoelastic-plastic law, Eqs. 1-4, on the
overlap of two polyhedra; numba, arrays in and out, no MPI).

For each pair (a, b), a the lower gid, whose bounding spheres and bounding boxes meet, the overlap of
their world polyhedra (kernels/polyhedron_contact.contact_geometry_planes, with the face planes
computed once a step) gives the normal n (from a towards b), the contact area A_c and the depth
delta = V / A_c, at the overlap's centroid. The law is the one of every contact in pice
(kernels/contact_law.py): F_n = k_n (delta - delta_p) - c_n u_n, 0 <= F_n <= sigma_c A_c (the excess
becomes plastic penetration delta_p), and a tangential spring capped at mu F_n. The dashpot is given
as a coefficient c_n [N s/m] (seed 003, Table 3), passed to the law as the damping ratio
c_n / (2 sqrt(m_eff k_n)) of the pair's m_eff = m_a m_b / (m_a + m_b), or as that ratio itself, zr >= 0,
the same for every pair (the keel's rubble; a negative zr takes c_n). b receives F_n n + h at the
overlap's centroid, a the opposite: linear momentum is conserved exactly, and angular
momentum too (both act at one point).

History per pair, kept at the lower-gid floe (the slots of kernels/contacts._find_slot): the
tangential force (3) and delta_p.

The kernels compute the contacts of the floes i = lo, lo + stride, ... below hi (one rank's floes,
dealt round the ranks: physics/floe_system.py) and write each contact as a record, not into force
arrays, in the order of i (a pair's i is the lower of its two indices):

    pair record       (a, b, f (3), torque on a (3), torque on b (3))          PAIR_RECORD = 11 doubles
    structure record  (floe, f on it (3), its torque (3), the structure's load (6))  
``apply_pair_records`` (and kernels/structure_contact.py's ``apply_structure_records``) add them to the floes in record order. Every
rank gathers the records of all ranks and merges them in the order of i (a stable sort), which is the
order one rank computes them in: the floes' forces are then the same bits on any number of ranks.
"""

import math

import numpy as np
from numba import njit

from . import JIT
from .box_contact import box_buffer, box_contact_scalars
from .contact_law import plastic_normal_force, tangential_force
from .contacts import _find_slot, build_cell_list, cell_neighbourhood
from .polyhedra import face_planes, separated_by_planes
from .polyhedron_contact import contact_buffer, contact_scalars

PAIR_RECORD = 11


@njit(**JIT)
def boxes_within(box, held):
    """True when every box (n, 6) lies inside its ``held`` box (the inflated boxes of a pair list)."""
    for i in range(box.shape[0]):
        for e in range(3):
            if box[i, e] < held[i, e] or box[i, 3 + e] > held[i, 3 + e]:
                return False
    return True


@njit(**JIT)
def build_floe_pairs(n, lo, hi, stride, x, bound, box, skin):
    """The candidate pairs of the floes range(lo, hi, stride), a neighbour list with a skin (as
    kernels/pair_list.py for the elements): (start (len(range(lo, hi, stride)) + 1,), partners,
    held (n, 6)). held are the boxes grown by skin / 2 on every side; the k-th owned floe i's
    partners[start[k]:start[k + 1]] are the j > i whose held box meets i's, in increasing j. While
    every floe's box stays inside its held box (``boxes_within``), every pair whose boxes meet is
    listed. The order of the pairs, (i, j) increasing, is a function of the state alone: a restart,
    which builds a fresh list, adds the same forces in the same order."""
    held = np.empty((n, 6))
    owned = len(range(lo, hi, stride))
    start = np.zeros(owned + 1, dtype=np.int64)
    if n == 0:
        return start, np.zeros(0, dtype=np.int64), held
    for i in range(n):
        for e in range(3):
            held[i, e] = box[i, e] - 0.5 * skin
            held[i, 3 + e] = box[i, 3 + e] + 0.5 * skin
    # two held boxes meet only if the centres are within b_i + b_j + skin along every axis
    origin, dims, cstart, order, size = build_cell_list(x, n, 2.0 * bound[:n].max() * 1.0001 + skin)
    near = np.empty(n, dtype=np.int64)
    out = np.empty(16 * max(owned, 1), dtype=np.int64)
    m = 0
    k = 0
    for i in range(lo, hi, stride):
        first = m
        for q in range(cell_neighbourhood(x[i], origin, dims, cstart, order, size, near)):
            j = near[q]
            if j > i and _boxes_meet(held, i, j):
                if m == out.shape[0]:
                    grown = np.empty(2 * m, dtype=np.int64)
                    grown[:m] = out
                    out = grown
                out[m] = j
                m += 1
        out[first:m].sort()
        k += 1
        start[k] = m
    return start, out[:m].copy(), held


@njit(**JIT)
def floe_contacts(n, lo, hi, stride, start, partners, box, gid, x, v, omega, mass, bound, pts, counts, kn, cn, zr,
                  kt, mu, pressure, dt, step, cgid, stamp, hist, records, rot, half):
    """The contacts of every overlapping pair (i, j), i in range(lo, hi, stride) and j > i, of the n
    floes, as pair records (module docstring) in ``records`` (m, PAIR_RECORD), in the order of i then
    j; the candidates are the pair list (start, partners) of ``build_floe_pairs`` for these floes,
    valid for the boxes ``box`` (``floe_boxes``). pts, counts: (n, MAX_FACES, MAX_FACE_VERTS, 3),
    (n, MAX_FACES) world polyhedra; bound: (n,) bounding radius about x [m]. When every floe is a box
    (``half`` (n, 3) its half extents [m], ``rot`` (n, 3, 3) its rotation; else both empty) the overlaps
    are those of kernels/box_contact.py, the same to round-off in fewer operations.
    Returns (records needed (written up to m), contacts in plastic flow, largest overlap volume [m^3])."""
    nrec = 0
    nplastic = 0
    worst = 0.0
    if n == 0 or hi <= lo:
        return nrec, nplastic, worst
    boxes = half.shape[0] == n
    planes = face_planes(pts, counts) if not boxes else np.zeros((1, counts.shape[1], 4))
    buf = contact_buffer(pts[0], planes[0], pts[0], planes[0])  # the overlaps' work array, one for all pairs
    bbuf = box_buffer()
    corner_a, corner_b = np.empty((8, 3)), np.empty((8, 3))
    codes_a, codes_b = np.empty(8, np.int64), np.empty(8, np.int64)
    rel, rel_t = np.empty((3, 3)), np.empty((3, 3))
    k = 0
    for i in range(lo, hi, stride):
        for q in range(start[k], start[k + 1]):
            j = partners[q]
            # the bounding spheres and boxes first; then the pair here, not in a function of two dozen
            # arguments (0.3 us a call: the arrays' reference counts)
            d0, d1, d2 = x[j, 0] - x[i, 0], x[j, 1] - x[i, 1], x[j, 2] - x[i, 2]
            reach = bound[i] + bound[j]
            if d0 * d0 + d1 * d1 + d2 * d2 >= reach * reach or not _boxes_meet(box, i, j):
                continue
            a, b = (i, j) if gid[i] < gid[j] else (j, i)
            if boxes:
                vol, c0, c1, c2, n0, n1, n2, area, depth = box_contact_scalars(
                    x[a], rot[a], half[a], x[b], rot[b], half[b], bbuf, corner_a, corner_b, codes_a, codes_b, rel,
                    rel_t)
                if vol <= 0.0:
                    continue
                s, found = _find_slot(cgid, stamp, a, gid[b], step)
            else:
                s, found = _find_slot(cgid, stamp, a, gid[b], step)
                # a pair in contact at the last step mostly still is: straight to its overlap; the others
                # first try the separating planes (the overlap of separated bodies is empty: the same
                # result, sooner)
                if not found and (_apart_along(d0, d1, d2, pts[i], counts[i], pts[j], counts[j])
                                  or separated_by_planes(planes[i], counts[i], pts[j], counts[j])
                                  or separated_by_planes(planes[j], counts[j], pts[i], counts[i])):
                    continue
                vol, c0, c1, c2, n0, n1, n2, area, depth = contact_scalars(pts[a], counts[a], planes[a], pts[b],
                                                                           counts[b], planes[b], buf)
                if vol <= 0.0:
                    continue
            # the law on the overlap (gid[a] < gid[b]; history slot s, found: in contact at the last step)
            worst = max(worst, vol)
            # lever arms from the centres to the contact point, and the velocity of b's material there
            # relative to a's (in scalars: no temporaries)
            ra0, ra1, ra2 = c0 - x[a, 0], c1 - x[a, 1], c2 - x[a, 2]
            rb0, rb1, rb2 = c0 - x[b, 0], c1 - x[b, 1], c2 - x[b, 2]
            u0 = ((v[b, 0] + (omega[b, 1] * rb2 - omega[b, 2] * rb1))
                  - (v[a, 0] + (omega[a, 1] * ra2 - omega[a, 2] * ra1)))
            u1 = ((v[b, 1] + (omega[b, 2] * rb0 - omega[b, 0] * rb2))
                  - (v[a, 1] + (omega[a, 2] * ra0 - omega[a, 0] * ra2)))
            u2 = ((v[b, 2] + (omega[b, 0] * rb1 - omega[b, 1] * rb0))
                  - (v[a, 2] + (omega[a, 0] * ra1 - omega[a, 1] * ra0)))
            un = u0 * n0 + u1 * n1 + u2 * n2
            h0 = hist[a, s, 0] if found else 0.0
            h1 = hist[a, s, 1] if found else 0.0
            h2 = hist[a, s, 2] if found else 0.0
            dp0 = hist[a, s, 3] if found else 0.0
            m_eff = mass[a] * mass[b] / (mass[a] + mass[b])
            zeta = _ratio(cn, zr, m_eff, kn)
            fn, dp = plastic_normal_force(kn, zeta, m_eff, depth, dp0, un, pressure * area)
            t0, t1, t2, _ = tangential_force(h0, h1, h2, n0, n1, n2, u0, u1, u2, un, kt, dt, mu * fn)
            if dp > dp0:
                nplastic += 1
            if s >= 0:
                cgid[a, s] = gid[b]
                stamp[a, s] = step
                hist[a, s, 0], hist[a, s, 1], hist[a, s, 2], hist[a, s, 3] = t0, t1, t2, dp
            if nrec < records.shape[0]:
                f0, f1, f2 = fn * n0 + t0, fn * n1 + t1, fn * n2 + t2
                records[nrec, 0], records[nrec, 1] = a, b
                records[nrec, 2], records[nrec, 3], records[nrec, 4] = f0, f1, f2
                # the torque on a is -(ra x f), on b rb x f
                records[nrec, 5] = -(ra1 * f2 - ra2 * f1)
                records[nrec, 6] = -(ra2 * f0 - ra0 * f2)
                records[nrec, 7] = -(ra0 * f1 - ra1 * f0)
                records[nrec, 8] = rb1 * f2 - rb2 * f1
                records[nrec, 9] = rb2 * f0 - rb0 * f2
                records[nrec, 10] = rb0 * f1 - rb1 * f0
            nrec += 1
        k += 1
    return nrec, nplastic, worst


@njit(**JIT)
def floe_boxes(n, pts, counts):
    """(n, 6) the axis-aligned bounding boxes (x, y, z lows, then highs) [m] of the first n polyhedra."""
    box = np.empty((n, 6))
    for i in range(n):
        for e in range(3):
            box[i, e], box[i, 3 + e] = math.inf, -math.inf
        for f in range(counts.shape[1]):
            for k in range(counts[i, f]):
                for e in range(3):
                    c = pts[i, f, k, e]
                    box[i, e] = min(box[i, e], c)
                    box[i, 3 + e] = max(box[i, 3 + e], c)
    return box


@njit(**JIT)
def _boxes_meet(box, i, j):
    """True when the bounding boxes of i and j overlap (``floe_boxes``)."""
    return (box[i, 0] <= box[j, 3] and box[j, 0] <= box[i, 3] and box[i, 1] <= box[j, 4] and box[j, 1] <= box[i, 4]
            and box[i, 2] <= box[j, 5] and box[j, 2] <= box[i, 5])


@njit(**JIT)
def _polyhedron_meets_box(box, pts, counts):
    """True when the polyhedron (pts, counts)'s bounding box overlaps ``box`` (6,) (``floe_boxes``)."""
    lo0 = lo1 = lo2 = math.inf
    hi0 = hi1 = hi2 = -math.inf
    for f in range(counts.shape[0]):
        for k in range(counts[f]):
            p0, p1, p2 = pts[f, k, 0], pts[f, k, 1], pts[f, k, 2]
            lo0, lo1, lo2 = min(lo0, p0), min(lo1, p1), min(lo2, p2)
            hi0, hi1, hi2 = max(hi0, p0), max(hi1, p1), max(hi2, p2)
    return (lo0 <= box[3] and box[0] <= hi0 and lo1 <= box[4] and box[1] <= hi1 and lo2 <= box[5]
            and box[2] <= hi2)


@njit(**JIT)
def _ratio(cn, zr, m_eff, kn):
    """The pair's damping ratio: zr when zr >= 0 (a ratio for every pair), else that of the one
    coefficient cn [N s/m] on m_eff [kg] and kn [N/m]."""
    if zr >= 0.0:
        return zr
    return cn / (2.0 * math.sqrt(m_eff * kn)) if kn > 0.0 else 0.0


@njit(**JIT)
def _apart_along(d0, d1, d2, a_pts, a_counts, b_pts, b_counts):
    """True when the line between the centres, d = x_b - x_a, separates the two polyhedra: every point
    of A projects below every point of B. The cheap first test of a pair of neighbouring floes (a
    packed field's neighbours mostly part along it), before the face planes."""
    hi = -math.inf
    for f in range(a_counts.shape[0]):
        for k in range(a_counts[f]):
            hi = max(hi, d0 * a_pts[f, k, 0] + d1 * a_pts[f, k, 1] + d2 * a_pts[f, k, 2])
    for f in range(b_counts.shape[0]):
        for k in range(b_counts[f]):
            if d0 * b_pts[f, k, 0] + d1 * b_pts[f, k, 1] + d2 * b_pts[f, k, 2] <= hi:
                return False
    return True


@njit(**JIT)
def apply_pair_records(records, nrec, force, torque):
    """Add ``nrec`` pair records (module docstring) to the floes' forces [N] and torques [N m], in order:
    b receives f, a the opposite."""
    for k in range(nrec):
        r = records[k]
        a, b = int(r[0]), int(r[1])
        for e in range(3):
            force[b, e] += r[2 + e]
            force[a, e] -= r[2 + e]
            torque[a, e] += r[5 + e]
            torque[b, e] += r[8 + e]
