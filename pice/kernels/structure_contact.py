"""Contact between rigid floes and structures: a body's hull (its convex pieces) and plane walls
(issues 14 and 15; numba, arrays in and out, no MPI). The law and the records are those of
kernels/floe_contact.py: each contact is a structure record

    (floe, f on it (3), its torque (3), the structure's load: force (3), moment about its reference (3))

in the order of the floes, added by ``apply_structure_records``. A hull of several convex pieces
meets each floe as one contact (``hull_contacts``), a single convex structure as one
(``structure_contacts``), a wall's half-space as one (``plane_contacts``).
"""

import math

import numpy as np
from numba import njit

from . import JIT
from .contact_law import plastic_normal_force, tangential_force
from .contacts import _find_slot
from .floe_contact import _polyhedron_meets_box, _ratio, floe_boxes
from .polyhedra import face_planes, separated_by_planes
from .polyhedron_contact import contact_geometry_planes, part_inside

STRUCTURE_RECORD = 13


@njit(**JIT)
def apply_structure_records(records, nrec, force, torque, load):
    """Add ``nrec`` structure records to the floes' forces and torques and to the structure's load (6,)
    (force [N], moment about its reference point [N m]), in order."""
    for k in range(nrec):
        r = records[k]
        i = int(r[0])
        for e in range(3):
            force[i, e] += r[1 + e]
            torque[i, e] += r[4 + e]
        for e in range(6):
            load[e] += r[7 + e]


@njit(**JIT)
def structure_contacts(lo, hi, stride, x, v, omega, mass, bound, pts, counts, s_pts, s_counts, s_centre, s_bound,
                       s_v, s_w, kn, cn, zr, kt, mu, pressure, dt, step, slot_gid, cgid, stamp, hist, records):
    """The contact of every floe in range(lo, hi, stride) with a convex structure (s_pts, s_counts: its
    faces in space; s_centre [m]: its reference point, the centre of its bounding sphere of radius s_bound and
    of its motion: velocity s_v [m/s] and angular velocity s_w [rad/s] there; zero for a fixed one):
    the law of ``floe_contacts`` with the floe's own mass as m_eff, as structure records in
    ``records`` (m, STRUCTURE_RECORD). The history is kept in the floe's slot keyed by ``slot_gid`` (a
    negative key, distinct from every floe's gid). A floe is tested against the structure's bounding
    sphere, its bounding box and its face planes before their overlap is clipped (a hull's pieces have
    their sphere about the body's origin: a ship's bow piece reaches every block of a keel).
    Returns (records needed, contacts in plastic flow)."""
    nrec = 0
    nplastic = 0
    s_box = floe_boxes(1, s_pts.reshape((1,) + s_pts.shape), s_counts.reshape((1,) + s_counts.shape))
    s_planes = face_planes(s_pts.reshape((1,) + s_pts.shape), s_counts.reshape((1,) + s_counts.shape))[0]
    for i in range(lo, hi, stride):
        d0, d1, d2 = x[i, 0] - s_centre[0], x[i, 1] - s_centre[1], x[i, 2] - s_centre[2]
        reach = bound[i] + s_bound
        if d0 * d0 + d1 * d1 + d2 * d2 >= reach * reach:
            continue
        if not _polyhedron_meets_box(s_box[0], pts[i], counts[i]):
            continue
        if separated_by_planes(s_planes, s_counts, pts[i], counts[i]):
            continue
        planes = face_planes(pts[i:i + 1], counts[i:i + 1])[0]
        vol, c, nrm, area, depth = contact_geometry_planes(pts[i], counts[i], planes, s_pts, s_counts, s_planes)
        if vol <= 0.0:
            continue
        # the structure's normal points from the floe towards it; the law's normal from it to the floe
        nrec, nplastic = _on_structure(i, c, -nrm[0], -nrm[1], -nrm[2], area, depth, x, v, omega, mass, s_centre,
                                       s_v, s_w, kn, cn, zr, kt, mu, pressure, dt, step, slot_gid, cgid, stamp, hist,
                                       records, nrec, nplastic)
    return nrec, nplastic


@njit(**JIT)
def hull_contacts(lo, hi, stride, x, v, omega, mass, bound, pts, counts, p_pts, p_counts, p_bound, s_centre, s_v,
                  s_w, kn, cn, zr, kt, mu, pressure, dt, step, slot_gid, cgid, stamp, hist, records, nrec):
    """The contact of every floe in range(lo, hi, stride) with a hull of P convex pieces (p_pts, p_counts:
    (P, F, V, 3), (P, F) their faces in space, padded with faces of count 0; p_bound (P,): each piece's
    bounding radius about s_centre [m], the hull's reference point, where its velocity s_v [m/s] and
    angular velocity s_w [rad/s] are given): ONE contact per floe and hull, as the hull's union meets
    the floe. The pieces' overlaps with the floe add up: V = sum V_p, the centroid the V-weighted mean,
    and S_A = sum S_A,p, since the floe's surface inside the union is the sum of its parts inside each
    piece (so a seam between two pieces, a face each shares inside the hull, adds nothing); for a convex
    union this is the union's own contact (kernels/polyhedron_contact.py) to round-off. The law then
    acts once (a floe straddling a seam is not pushed by each piece: the law's k_n delta does not scale
    with the area), with the history in the slot ``slot_gid``. The force is shared among the pieces in
    proportion to their V_p, a record per piece in ``records[p]`` (P, m, STRUCTURE_RECORD), counted in
    ``nrec[p]`` (P,), so that each piece's load is its share (a ship's bow and midbody: Malmberg's two
    terms). Returns the contacts in plastic flow."""
    npieces = p_pts.shape[0]
    nplastic = 0
    for p in range(npieces):
        nrec[p] = 0
    vols = np.zeros(npieces)
    one = np.empty((1, records.shape[2]))
    boxes = np.empty((npieces, 6))
    planes = np.empty((npieces, p_counts.shape[1], 4))
    for p in range(npieces):
        boxes[p] = floe_boxes(1, p_pts[p:p + 1], p_counts[p:p + 1])[0]
        planes[p] = face_planes(p_pts[p:p + 1], p_counts[p:p + 1])[0]
    for i in range(lo, hi, stride):
        d0, d1, d2 = x[i, 0] - s_centre[0], x[i, 1] - s_centre[1], x[i, 2] - s_centre[2]
        far = True
        for p in range(npieces):
            reach = bound[i] + p_bound[p]
            if d0 * d0 + d1 * d1 + d2 * d2 < reach * reach:
                far = False
        if far:
            continue
        vol = c0 = c1 = c2 = s0 = s1 = s2 = 0.0
        fplanes = np.empty((0, 4))  # the floe's face planes, computed once a piece's tests pass
        for p in range(npieces):
            vols[p] = 0.0
            reach = bound[i] + p_bound[p]
            if (d0 * d0 + d1 * d1 + d2 * d2 >= reach * reach or not _polyhedron_meets_box(boxes[p], pts[i], counts[i])
                    or separated_by_planes(planes[p], p_counts[p], pts[i], counts[i])):
                continue
            if fplanes.shape[0] == 0:
                fplanes = face_planes(pts[i:i + 1], counts[i:i + 1])[0]
            vp, c, nrm, area, _ = contact_geometry_planes(pts[i], counts[i], fplanes, p_pts[p], p_counts[p], planes[p])
            if vp <= 0.0:
                continue
            vols[p] = vp
            vol += vp
            c0, c1, c2 = c0 + vp * c[0], c1 + vp * c[1], c2 + vp * c[2]
            s0, s1, s2 = s0 + area * nrm[0], s1 + area * nrm[1], s2 + area * nrm[2]
        area = math.sqrt(s0 * s0 + s1 * s1 + s2 * s2)
        if vol <= 0.0 or area <= 0.0:
            continue
        c = np.array([c0 / vol, c1 / vol, c2 / vol])
        # the structure's normal points from the floe towards it; the law's normal from it to the floe
        _, nplastic = _on_structure(i, c, -s0 / area, -s1 / area, -s2 / area, area, vol / area, x, v, omega, mass,
                                    s_centre, s_v, s_w, kn, cn, zr, kt, mu, pressure, dt, step, slot_gid, cgid,
                                    stamp, hist, one, 0, nplastic)
        for p in range(npieces):
            if vols[p] > 0.0:
                if nrec[p] < records.shape[1]:
                    share = vols[p] / vol
                    records[p, nrec[p], 0] = i
                    for e in range(1, records.shape[2]):
                        records[p, nrec[p], e] = share * one[0, e]
                nrec[p] += 1
    return nplastic


@njit(**JIT)
def _on_structure(i, c, n0, n1, n2, area, depth, x, v, omega, mass, s_centre, s_v, s_w, kn, cn, zr, kt, mu, pressure,
                  dt, step, slot_gid, cgid, stamp, hist, records, nrec, nplastic):
    """The law on floe i against a structure at contact point c [m], normal (n0, n1, n2) from the
    structure towards the floe, contact area [m^2] and depth [m]; one structure record."""
    r = c - x[i]
    # the floe's material at the contact point relative to the structure's
    u = v[i] + np.cross(omega[i], r) - (s_v + np.cross(s_w, c - s_centre))
    un = u[0] * n0 + u[1] * n1 + u[2] * n2
    s, found = _find_slot(cgid, stamp, i, slot_gid, step)
    h0 = hist[i, s, 0] if found else 0.0
    h1 = hist[i, s, 1] if found else 0.0
    h2 = hist[i, s, 2] if found else 0.0
    dp0 = hist[i, s, 3] if found else 0.0
    zeta = _ratio(cn, zr, mass[i], kn)
    fn, dp = plastic_normal_force(kn, zeta, mass[i], depth, dp0, un, pressure * area)
    t0, t1, t2, _ = tangential_force(h0, h1, h2, n0, n1, n2, u[0], u[1], u[2], un, kt, dt, mu * fn)
    if dp > dp0:
        nplastic += 1
    if s >= 0:
        cgid[i, s] = slot_gid
        stamp[i, s] = step
        hist[i, s, 0], hist[i, s, 1], hist[i, s, 2], hist[i, s, 3] = t0, t1, t2, dp
    if nrec < records.shape[0]:
        f = np.array([fn * n0 + t0, fn * n1 + t1, fn * n2 + t2])  # on the floe
        tq = np.cross(r, f)
        m = np.cross(c - s_centre, f)
        rec = records[nrec]
        rec[0] = i
        for e in range(3):
            rec[1 + e] = f[e]
            rec[4 + e] = tq[e]
            rec[7 + e] = -f[e]
            rec[10 + e] = -m[e]
    return nrec + 1, nplastic


@njit(**JIT)
def plane_contacts(lo, hi, stride, x, v, omega, mass, bound, pts, counts, normal, offset, kn, cn, zr, kt, mu, pressure,
                   dt, step, slot_gid, cgid, stamp, hist, records):
    """The contact of every floe in range(lo, hi, stride) with a fixed wall filling the half-space
    normal . x >= offset (normal (3,) a unit vector into the wall): the floe's part inside the wall is the overlap
    (kernels/polyhedron_contact.part_inside); its area on the wall's plane is A_c, its volume over A_c
    the depth. A floe whose bounding sphere (radius ``bound`` [m] about x) stays out of the wall is
    skipped. Structure records as ``structure_contacts`` (the load's moment about the origin).
    Returns (records needed, plastic)."""
    nrec = 0
    nplastic = 0
    into = -normal
    zero = np.zeros(3)
    buf = np.empty((2, pts.shape[2] + 2, 3))
    for i in range(lo, hi, stride):
        if normal[0] * x[i, 0] + normal[1] * x[i, 1] + normal[2] * x[i, 2] + bound[i] <= offset:
            continue
        beyond = False
        for f in range(counts.shape[1]):
            for k in range(counts[i, f]):
                p = pts[i, f, k]
                if normal[0] * p[0] + normal[1] * p[1] + normal[2] * p[2] > offset:
                    beyond = True
                    break
            if beyond:
                break
        if not beyond:
            continue
        vol, c, area, _, _, _ = part_inside(pts[i], counts[i], into[0], into[1], into[2], -offset, buf)
        if vol <= 0.0 or area <= 0.0:
            continue
        nrec, nplastic = _on_structure(i, c, into[0], into[1], into[2], area, vol / area, x, v, omega, mass, zero,
                                       zero, zero, kn, cn, zr, kt, mu, pressure, dt, step, slot_gid, cgid, stamp, hist,
                                       records, nrec, nplastic)
    return nrec, nplastic
