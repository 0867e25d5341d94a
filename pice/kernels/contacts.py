"""Contact between unbonded spheres: the cell list, and the shared contact law (contact_law.py) on the
candidates of the neighbour list (pair_list.py).

The effective mass of a pair is m_a m_b / (m_a + m_b). The tangential history of a contact is kept
per particle in slots keyed by the partner's gid and, like bonds, computed in canonical orientation
(lower gid first) so both ends agree.
"""

import math

import numpy as np
from numba import njit

from . import JIT
from .contact_law import contact_energy, contact_height, crushing_cap, plastic_normal_force, tangential_force


@njit(**JIT)
def _cell_index(q, dim):
    """Cell index of the scaled coordinate q along one axis, clamped to [0, dim - 1] (0 for NaN)."""
    if q >= dim - 1:
        return dim - 1
    if q > 0.0:
        return int(q)
    return 0


@njit(**JIT)
def build_cell_list(x, n, cell_size):
    """Bin the first ``n`` positions into cubic cells of edge ``cell_size`` [m] (counting sort, O(n)).

    Returns (origin, dims, cell_start, order): particles of cell c are order[cell_start[c]:cell_start[c+1]].
    The grid is coarsened if the bounding box would need more than 8 n + 64 cells.
    """
    lo = np.empty(3)
    hi = np.empty(3)
    for k in range(3):
        lo[k] = np.inf
        hi[k] = -np.inf
    for i in range(n):
        for k in range(3):
            if x[i, k] < lo[k]:
                lo[k] = x[i, k]
            if x[i, k] > hi[k]:
                hi[k] = x[i, k]
    if n == 0:
        for k in range(3):
            lo[k] = 0.0
            hi[k] = 0.0
    size = cell_size
    dims = np.empty(3, dtype=np.int64)
    while True:
        total = 1.0  # float: a runaway extent must not overflow the cell count before the health check
        for k in range(3):
            span = (hi[k] - lo[k]) / size
            dims[k] = int(span) + 1 if 0.0 < span < 1e15 else 1  # one cell along k if non-finite or absurd
            total *= dims[k]
        if total <= 8 * n + 64:
            break
        size *= 1.5
    ncell = dims[0] * dims[1] * dims[2]
    count = np.zeros(ncell + 1, dtype=np.int64)
    cell_of = np.empty(n, dtype=np.int64)
    for i in range(n):
        cx = _cell_index((x[i, 0] - lo[0]) / size, dims[0])
        cy = _cell_index((x[i, 1] - lo[1]) / size, dims[1])
        cz = _cell_index((x[i, 2] - lo[2]) / size, dims[2])
        c = (cz * dims[1] + cy) * dims[0] + cx
        cell_of[i] = c
        count[c + 1] += 1
    for c in range(ncell):
        count[c + 1] += count[c]
    fill = count[:-1].copy()
    order = np.empty(n, dtype=np.int64)
    for i in range(n):
        c = cell_of[i]
        order[fill[c]] = i
        fill[c] += 1
    origin = lo
    return origin, dims, count, order, size


@njit(**JIT)
def cell_neighbourhood(point, origin, dims, start, order, size, out):
    """Write into ``out`` the indices of every point binned (``build_cell_list``) in the 3 x 3 x 3 cells
    around ``point`` (3,) [m], cell by cell; return how many. ``out`` holds at least all the points."""
    cx = _cell_index((point[0] - origin[0]) / size, dims[0])
    cy = _cell_index((point[1] - origin[1]) / size, dims[1])
    cz = _cell_index((point[2] - origin[2]) / size, dims[2])
    m = 0
    for z in range(max(cz - 1, 0), min(cz + 2, dims[2])):
        for y in range(max(cy - 1, 0), min(cy + 2, dims[1])):
            for xx in range(max(cx - 1, 0), min(cx + 2, dims[0])):
                c = (z * dims[1] + y) * dims[0] + xx
                for p in range(start[c], start[c + 1]):
                    out[m] = order[p]
                    m += 1
    return m


@njit(**JIT)
def _find_slot(cgid, stamp, i, partner, step):
    """Slot of particle i holding a live contact with ``partner``, or a free slot (history reset), or -1."""
    free = -1
    for s in range(cgid.shape[1]):
        if cgid[i, s] == partner and stamp[i, s] >= step - 1:
            return s, True
        if free < 0 and stamp[i, s] < step - 1:
            free = s
    return free, False


@njit(**JIT)
def _bonded(bond_j, i, j):
    for s in range(bond_j.shape[1]):
        if bond_j[i, s] == j:
            return True
    return False


@njit(**JIT)
def contact_forces(nlocal, gid, x, v, w, radius, mass, cell_area, half_height, pair_start, partners, cgid, stamp,
                   chist, law, dt, step, force, torque):
    """Add contact forces between unbonded overlapping spheres, among the candidates of the pair list
    (pair_list.py: owned i's are partners[pair_start[i]:pair_start[i+1]], unbonded, in gid order).

    law: the contact law's parameters (physics.contact.ContactLaw: kn, kt, zeta, mu, crushing_pressure).
    chist: (n, slots, 4) per contact: tangential force on the lower-gid end [N] and plastic penetration [m].
    Returns (contacts, elastic energy [J], contacts in plastic flow (crushing)).
    """
    ncontacts = 0
    ncrushing = 0
    energy = 0.0
    n = np.empty(3)
    for i in range(nlocal):
        for q in range(pair_start[i], pair_start[i + 1]):
            j = partners[q]
            d0 = x[j, 0] - x[i, 0]
            d1 = x[j, 1] - x[i, 1]
            d2 = x[j, 2] - x[i, 2]
            dist2 = d0 * d0 + d1 * d1 + d2 * d2
            rsum = radius[i] + radius[j]
            if dist2 >= rsum * rsum or dist2 == 0.0:
                continue
            j_owned = j < nlocal
            i_is_a = gid[i] < gid[j]
            a = i if i_is_a else j
            b = j if i_is_a else i
            ncontacts += 1
            e, yielding = _pair(a, b, i, j, i_is_a, j_owned, x, v, w, radius, mass, cell_area,
                                half_height, gid, cgid, stamp, chist, law, dt, step, n, force, torque)
            energy += e
            ncrushing += yielding
    return ncontacts, energy, ncrushing


@njit(**JIT)
def _pair(a, b, i, j, i_is_a, j_owned, x, v, w, radius, mass, cell_area, half_height, gid, cgid, stamp, chist,
          law, dt, step, n, force, torque):
    """The contact law (contact_law.py) on the pair (a, b) = (lower gid, higher gid), seen from a.
    Returns (elastic energy [J] counted on this rank, 1 if the contact is in plastic flow else 0)."""
    d0 = x[b, 0] - x[a, 0]
    d1 = x[b, 1] - x[a, 1]
    d2 = x[b, 2] - x[a, 2]
    L = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
    n[0] = d0 / L  # from a towards b
    n[1] = d1 / L
    n[2] = d2 / L
    delta = radius[a] + radius[b] - L
    ca = radius[a] - 0.5 * delta
    cb = radius[b] - 0.5 * delta
    # velocity of b's contact point relative to a's
    vr0 = (v[b, 0] - cb * (w[b, 1] * n[2] - w[b, 2] * n[1])) - (v[a, 0] + ca * (w[a, 1] * n[2] - w[a, 2] * n[1]))
    vr1 = (v[b, 1] - cb * (w[b, 2] * n[0] - w[b, 0] * n[2])) - (v[a, 1] + ca * (w[a, 2] * n[0] - w[a, 0] * n[2]))
    vr2 = (v[b, 2] - cb * (w[b, 0] * n[1] - w[b, 1] * n[0])) - (v[a, 2] + ca * (w[a, 0] * n[1] - w[a, 1] * n[0]))
    vn = vr0 * n[0] + vr1 * n[1] + vr2 * n[2]
    # tangential history and plastic penetration from i's slot
    si, found = _find_slot(cgid, stamp, i, gid[j], step)
    h0 = chist[i, si, 0] if found else 0.0
    h1 = chist[i, si, 1] if found else 0.0
    h2 = chist[i, si, 2] if found else 0.0
    dp0 = chist[i, si, 3] if found else 0.0
    # the overlap's half chord in plan (lens of two circles) and the lower contact face [m]
    xa = 0.5 * (L * L + radius[a] * radius[a] - radius[b] * radius[b]) / L
    height = min(contact_height(radius[a], cell_area[a], half_height[a]),
                 contact_height(radius[b], cell_area[b], half_height[b]))
    cap = crushing_cap(law.crushing_pressure, radius[a] * radius[a] - xa * xa, height)
    fn, dp = plastic_normal_force(law.kn, law.zeta, mass[a] * mass[b] / (mass[a] + mass[b]), delta, dp0, vn, cap)
    # in the law's terms, a is the element: normal -n (from b to a), velocity -vr (a relative to b)
    f0, f1, f2, ftm = tangential_force(h0, h1, h2, -n[0], -n[1], -n[2], -vr0, -vr1, -vr2, vn, law.kt, dt,
                                       law.mu * fn)
    if si >= 0:
        cgid[i, si] = gid[j]
        stamp[i, si] = step
        chist[i, si, 0], chist[i, si, 1], chist[i, si, 2], chist[i, si, 3] = f0, f1, f2, dp
    if j_owned:
        sj, _ = _find_slot(cgid, stamp, j, gid[i], step)
        if sj >= 0:
            cgid[j, sj] = gid[i]
            stamp[j, sj] = step
            chist[j, sj, 0], chist[j, sj, 1], chist[j, sj, 2], chist[j, sj, 3] = f0, f1, f2, dp
    # force on a: repulsion along -n plus the tangential spring
    fa0 = -fn * n[0] + f0
    fa1 = -fn * n[1] + f1
    fa2 = -fn * n[2] + f2
    ma0 = ca * (n[1] * fa2 - n[2] * fa1)
    ma1 = ca * (n[2] * fa0 - n[0] * fa2)
    ma2 = ca * (n[0] * fa1 - n[1] * fa0)
    mb0 = cb * (n[1] * fa2 - n[2] * fa1)
    mb1 = cb * (n[2] * fa0 - n[0] * fa2)
    mb2 = cb * (n[0] * fa1 - n[1] * fa0)
    sign = 1.0 if i_is_a else -1.0
    force[i, 0] += sign * fa0
    force[i, 1] += sign * fa1
    force[i, 2] += sign * fa2
    if i_is_a:
        torque[i, 0] += ma0
        torque[i, 1] += ma1
        torque[i, 2] += ma2
    else:
        torque[i, 0] += mb0
        torque[i, 1] += mb1
        torque[i, 2] += mb2
    if j_owned:
        force[j, 0] -= sign * fa0
        force[j, 1] -= sign * fa1
        force[j, 2] -= sign * fa2
        if i_is_a:
            torque[j, 0] += mb0
            torque[j, 1] += mb1
            torque[j, 2] += mb2
        else:
            torque[j, 0] += ma0
            torque[j, 1] += ma1
            torque[j, 2] += ma2
    mine = i_is_a or j_owned
    return (contact_energy(law.kn, law.kt, delta - dp, ftm) if mine else 0.0), (1 if (mine and dp > dp0) else 0)
