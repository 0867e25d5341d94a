"""Contact between rigid convex floes (issue 14: seed 003's viscoelastic-plastic law, Eqs. 1-4, on the
overlap of two polyhedra; numba, arrays in and out, no MPI).

For each pair (a, b), a the lower gid, whose bounding spheres meet, the overlap of their world
polyhedra (kernels/polyhedra.contact_geometry) gives the normal n (from a towards b), the contact
area A_c and the depth delta = V / A_c, at the overlap's centroid. The law is the one of every
contact in pice (kernels/contact_law.py): F_n = k_n (delta - delta_p) - c_n u_n, 0 <= F_n <= sigma_c A_c
(the excess becomes plastic penetration delta_p), and a tangential spring capped at mu F_n. The
dashpot is given as a coefficient c_n [N s/m] (seed 003, Table 3), passed to the law as the damping
ratio c_n / (2 sqrt(m_eff k_n)) of the pair's m_eff = m_a m_b / (m_a + m_b). b receives F_n n + h
at the overlap's centroid, a the opposite: linear momentum is conserved exactly, and angular
momentum too (both act at one point).

History per pair, kept at the lower-gid floe (the slots of kernels/contacts._find_slot): the
tangential force (3) and delta_p.
"""

import math

import numpy as np
from numba import njit

from . import JIT
from .contact_law import plastic_normal_force, tangential_force
from .contacts import _find_slot, build_cell_list, cell_neighbourhood
from .polyhedra import contact_geometry, face_planes, separated_by_planes


@njit(**JIT)
def floe_contacts(n, gid, x, v, omega, mass, bound, pts, counts, kn, cn, kt, mu, pressure, dt, step,
                  cgid, stamp, hist, force, torque):
    """Add the contact forces [N] and torques about each centroid [N m] of every overlapping pair of
    the n floes, the candidates from a cell list of their centres (cells of the largest bounding
    diameter). pts, counts: (n, MAX_FACES, MAX_FACE_VERTS, 3), (n, MAX_FACES) world polyhedra; bound:
    (n,) bounding radius about x [m]. Returns (contacts, contacts in plastic flow, largest overlap
    volume [m^3])."""
    ncontact = 0
    nplastic = 0
    worst = 0.0
    if n == 0:
        return ncontact, nplastic, worst
    planes = face_planes(pts, counts)
    size = 2.0 * bound[:n].max() * 1.0001
    origin, dims, start, order, size = build_cell_list(x, n, size)
    near = np.empty(n, dtype=np.int64)
    for i in range(n):
        for q in range(cell_neighbourhood(x[i], origin, dims, start, order, size, near)):
            j = near[q]
            if j > i:
                ncontact, nplastic, worst = _pair(i, j, gid, x, v, omega, mass, bound, pts, counts, planes, kn, cn,
                                                  kt, mu, pressure, dt, step, cgid, stamp, hist, force, torque,
                                                  ncontact, nplastic, worst)
    return ncontact, nplastic, worst


@njit(**JIT)
def _pair(i, j, gid, x, v, omega, mass, bound, pts, counts, planes, kn, cn, kt, mu, pressure, dt, step, cgid,
          stamp, hist, force, torque, ncontact, nplastic, worst):
    """The contact of floes i and j, if they overlap (``floe_contacts``); returns the updated counts."""
    d = x[j] - x[i]
    reach = bound[i] + bound[j]
    if d[0] * d[0] + d[1] * d[1] + d[2] * d[2] >= reach * reach:
        return ncontact, nplastic, worst
    if (separated_by_planes(planes[i], counts[i], pts[j], counts[j])
            or separated_by_planes(planes[j], counts[j], pts[i], counts[i])):
        return ncontact, nplastic, worst
    a, b = (i, j) if gid[i] < gid[j] else (j, i)
    vol, c, nrm, area, depth = contact_geometry(pts[a], counts[a], pts[b], counts[b])
    if vol <= 0.0:
        return ncontact, nplastic, worst
    ncontact += 1
    worst = max(worst, vol)
    ra, rb = c - x[a], c - x[b]
    # velocity of b's material at the contact point relative to a's
    u = (v[b] + np.cross(omega[b], rb)) - (v[a] + np.cross(omega[a], ra))
    un = u[0] * nrm[0] + u[1] * nrm[1] + u[2] * nrm[2]
    s, found = _find_slot(cgid, stamp, a, gid[b], step)
    h0 = hist[a, s, 0] if found else 0.0
    h1 = hist[a, s, 1] if found else 0.0
    h2 = hist[a, s, 2] if found else 0.0
    dp0 = hist[a, s, 3] if found else 0.0
    m_eff = mass[a] * mass[b] / (mass[a] + mass[b])
    zeta = cn / (2.0 * math.sqrt(m_eff * kn)) if kn > 0.0 else 0.0
    fn, dp = plastic_normal_force(kn, zeta, m_eff, depth, dp0, un, pressure * area)
    t0, t1, t2, _ = tangential_force(h0, h1, h2, nrm[0], nrm[1], nrm[2], u[0], u[1], u[2], un, kt, dt, mu * fn)
    if dp > dp0:
        nplastic += 1
    if s >= 0:
        cgid[a, s] = gid[b]
        stamp[a, s] = step
        hist[a, s, 0], hist[a, s, 1], hist[a, s, 2], hist[a, s, 3] = t0, t1, t2, dp
    f = fn * nrm + np.array([t0, t1, t2])
    force[b] += f
    force[a] -= f
    torque[b] += np.cross(rb, f)
    torque[a] -= np.cross(ra, f)
    return ncontact, nplastic, worst


@njit(**JIT)
def structure_contacts(n, x, v, omega, mass, bound, pts, counts, s_pts, s_counts, s_centre, s_bound, s_v, s_w,
                       kn, cn, kt, mu, pressure, dt, step, slot_gid, cgid, stamp, hist, force, torque):
    """Add the contact of every floe with a convex structure (s_pts, s_counts: its faces in space;
    s_centre [m]: its reference point, the centre of its bounding sphere of radius s_bound and of
    its motion: velocity s_v [m/s] and angular velocity s_w [rad/s] there; zero for a fixed one):
    the law of ``floe_contacts`` with the floe's own mass as m_eff. The history is kept in the
    floe's slot keyed by ``slot_gid`` (a negative key, distinct from every floe's gid). Returns
    (load on the structure (6,): force [N] and moment about s_centre [N m], contacts, contacts in
    plastic flow)."""
    load = np.zeros(6)
    ncontact = 0
    nplastic = 0
    for i in range(n):
        d = x[i] - s_centre
        reach = bound[i] + s_bound
        if d[0] * d[0] + d[1] * d[1] + d[2] * d[2] >= reach * reach:
            continue
        vol, c, nrm, area, depth = contact_geometry(pts[i], counts[i], s_pts, s_counts)
        if vol <= 0.0:
            continue
        ncontact += 1
        r = c - x[i]
        # the floe's material at the contact point relative to the structure's (the law's "element" is
        # the floe, its normal from the structure towards the floe)
        n0, n1, n2 = -nrm[0], -nrm[1], -nrm[2]
        u = v[i] + np.cross(omega[i], r) - (s_v + np.cross(s_w, c - s_centre))
        un = u[0] * n0 + u[1] * n1 + u[2] * n2
        s, found = _find_slot(cgid, stamp, i, slot_gid, step)
        h0 = hist[i, s, 0] if found else 0.0
        h1 = hist[i, s, 1] if found else 0.0
        h2 = hist[i, s, 2] if found else 0.0
        dp0 = hist[i, s, 3] if found else 0.0
        zeta = cn / (2.0 * math.sqrt(mass[i] * kn)) if kn > 0.0 else 0.0
        fn, dp = plastic_normal_force(kn, zeta, mass[i], depth, dp0, un, pressure * area)
        t0, t1, t2, _ = tangential_force(h0, h1, h2, n0, n1, n2, u[0], u[1], u[2], un, kt, dt, mu * fn)
        if dp > dp0:
            nplastic += 1
        if s >= 0:
            cgid[i, s] = slot_gid
            stamp[i, s] = step
            hist[i, s, 0], hist[i, s, 1], hist[i, s, 2], hist[i, s, 3] = t0, t1, t2, dp
        f = np.array([fn * n0 + t0, fn * n1 + t1, fn * n2 + t2])  # on the floe
        force[i] += f
        torque[i] += np.cross(r, f)
        arm = c - s_centre
        load[:3] -= f
        load[3:] -= np.cross(arm, f)
    return load, ncontact, nplastic
