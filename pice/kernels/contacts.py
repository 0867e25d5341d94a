"""Contact between unbonded spheres: cell list, linear spring-dashpot with Coulomb friction.

Normal force F_n = k_n delta + c_n v_approach (never tensile), c_n = 2 zeta sqrt(m_eff k_n) with zeta
from the restitution coefficient. Tangential: incremental spring k_t with history, capped at
mu F_n (Coulomb). The history of a contact is kept per particle in slots keyed by the partner's gid
and, like bonds, computed in canonical orientation (lower gid first) so both ends agree.

params: 0 kn [N/m]  1 kt [N/m]  2 zeta  3 mu
"""

import math

import numpy as np
from numba import njit

from . import JIT


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
def contact_forces(nlocal, ntotal, gid, x, v, w, radius, mass, bond_j, cgid, stamp, chist, params,
                   dt, step, cell_size, force, torque):
    """Add contact forces between unbonded overlapping spheres. Returns (contacts, elastic energy [J])."""
    kn, kt, zeta, mu = params[0], params[1], params[2], params[3]
    origin, dims, start, order, size = build_cell_list(x, ntotal, cell_size)
    ncontacts = 0
    energy = 0.0
    n = np.empty(3)
    ft = np.empty(3)
    for i in range(nlocal):
        cx = _cell_index((x[i, 0] - origin[0]) / size, dims[0])
        cy = _cell_index((x[i, 1] - origin[1]) / size, dims[1])
        cz = _cell_index((x[i, 2] - origin[2]) / size, dims[2])
        for dz in range(-1, 2):
            z = cz + dz
            if z < 0 or z >= dims[2]:
                continue
            for dy in range(-1, 2):
                y = cy + dy
                if y < 0 or y >= dims[1]:
                    continue
                for dxc in range(-1, 2):
                    xx = cx + dxc
                    if xx < 0 or xx >= dims[0]:
                        continue
                    c = (z * dims[1] + y) * dims[0] + xx
                    for p in range(start[c], start[c + 1]):
                        j = order[p]
                        if j == i:
                            continue
                        j_owned = j < nlocal
                        if j_owned and gid[j] < gid[i]:
                            continue  # handled from j
                        d0 = x[j, 0] - x[i, 0]
                        d1 = x[j, 1] - x[i, 1]
                        d2 = x[j, 2] - x[i, 2]
                        dist2 = d0 * d0 + d1 * d1 + d2 * d2
                        rsum = radius[i] + radius[j]
                        if dist2 >= rsum * rsum or dist2 == 0.0:
                            continue
                        if _bonded(bond_j, i, j):
                            continue
                        i_is_a = gid[i] < gid[j]
                        a = i if i_is_a else j
                        b = j if i_is_a else i
                        ncontacts += 1
                        energy += _pair(a, b, i, j, i_is_a, j_owned, x, v, w, radius, mass, gid, cgid, stamp,
                                        chist, kn, kt, zeta, mu, dt, step, n, ft, force, torque)
    return ncontacts, energy


@njit(**JIT)
def _pair(a, b, i, j, i_is_a, j_owned, x, v, w, radius, mass, gid, cgid, stamp, chist,
          kn, kt, zeta, mu, dt, step, n, ft, force, torque):
    d0 = x[b, 0] - x[a, 0]
    d1 = x[b, 1] - x[a, 1]
    d2 = x[b, 2] - x[a, 2]
    L = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
    n[0] = d0 / L
    n[1] = d1 / L
    n[2] = d2 / L
    delta = radius[a] + radius[b] - L
    ca = radius[a] - 0.5 * delta
    cb = radius[b] - 0.5 * delta
    vr0 = (v[b, 0] - cb * (w[b, 1] * n[2] - w[b, 2] * n[1])) - (v[a, 0] + ca * (w[a, 1] * n[2] - w[a, 2] * n[1]))
    vr1 = (v[b, 1] - cb * (w[b, 2] * n[0] - w[b, 0] * n[2])) - (v[a, 1] + ca * (w[a, 2] * n[0] - w[a, 0] * n[2]))
    vr2 = (v[b, 2] - cb * (w[b, 0] * n[1] - w[b, 1] * n[0])) - (v[a, 2] + ca * (w[a, 0] * n[1] - w[a, 1] * n[0]))
    vn = vr0 * n[0] + vr1 * n[1] + vr2 * n[2]
    m_eff = mass[a] * mass[b] / (mass[a] + mass[b])
    cn = 2.0 * zeta * math.sqrt(m_eff * kn)
    fn = kn * delta - cn * vn  # repulsive magnitude; vn < 0 when approaching
    if fn < 0.0:
        fn = 0.0
    # tangential history from i's slot
    si, found = _find_slot(cgid, stamp, i, gid[j], step)
    if found:
        for k in range(3):
            ft[k] = chist[i, si, k]
    else:
        for k in range(3):
            ft[k] = 0.0
    dn = ft[0] * n[0] + ft[1] * n[1] + ft[2] * n[2]
    for k in range(3):
        ft[k] -= dn * n[k]
    ft[0] += kt * (vr0 - vn * n[0]) * dt
    ft[1] += kt * (vr1 - vn * n[1]) * dt
    ft[2] += kt * (vr2 - vn * n[2]) * dt
    ftm = math.sqrt(ft[0] * ft[0] + ft[1] * ft[1] + ft[2] * ft[2])
    cap = mu * fn
    if ftm > cap:
        s = cap / ftm if ftm > 0.0 else 0.0
        for k in range(3):
            ft[k] *= s
        ftm = cap
    if si >= 0:
        cgid[i, si] = gid[j]
        stamp[i, si] = step
        for k in range(3):
            chist[i, si, k] = ft[k]
    if j_owned:
        sj, _ = _find_slot(cgid, stamp, j, gid[i], step)
        if sj >= 0:
            cgid[j, sj] = gid[i]
            stamp[j, sj] = step
            for k in range(3):
                chist[j, sj, k] = ft[k]
    # force on a: repulsion along -n plus the tangential spring
    fa0 = -fn * n[0] + ft[0]
    fa1 = -fn * n[1] + ft[1]
    fa2 = -fn * n[2] + ft[2]
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
    e = 0.5 * kn * delta * delta
    if kt > 0.0:
        e += 0.5 * ftm * ftm / kt
    return e if (i_is_a or j_owned) else 0.0
