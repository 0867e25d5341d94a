"""Pack/unpack kernels for the halo exchange and the gid -> local index resolution of bonds."""

import numpy as np
from numba import njit

from . import JIT

GHOST_DOUBLES = 9  # doubles per ghost record sent every step: x, v, w (3 each)


@njit(**JIT)
def _cell(cuts, value, cells):
    """The cell of ``value`` between ``cuts`` (sorted), as clip(searchsorted(cuts, value, "right") - 1,
    0, cells - 1): the number of cuts at or below it, less one; NaN beyond the last."""
    if value != value:
        return cells - 1
    k = 0
    for c in range(len(cuts)):
        if cuts[c] <= value:
            k += 1
    return min(max(k - 1, 0), cells - 1)


@njit(**JIT)
def owner_ranks(x, y, x_cuts, y_cuts):
    """The rank owning each point (x [m], y [m]) of a decomposition into columns between ``x_cuts``
    (px + 1,) and, in column c, rows between ``y_cuts[c]`` (py + 1,): rank = column * py + row."""
    px, py = len(x_cuts) - 1, y_cuts.shape[1] - 1
    out = np.empty(len(x), np.int64)
    for i in range(len(x)):
        col = _cell(x_cuts, x[i], px)
        out[i] = col * py + _cell(y_cuts[col], y[i], py)
    return out


@njit(**JIT)
def pack_kinematics(x, v, w, idx, out):
    """out[GHOST_DOUBLES k : GHOST_DOUBLES (k + 1)] = (x, v, w) of particle idx[k]."""
    for k in range(len(idx)):
        i = idx[k]
        o = GHOST_DOUBLES * k
        for d in range(3):
            out[o + d] = x[i, d]
            out[o + 3 + d] = v[i, d]
            out[o + 6 + d] = w[i, d]


@njit(**JIT)
def unpack_kinematics(buf, x, v, w, start):
    """Write consecutive (x, v, w) records of ``buf`` into rows start, start+1, ..."""
    n = len(buf) // GHOST_DOUBLES
    for k in range(n):
        i = start + k
        o = GHOST_DOUBLES * k
        for d in range(3):
            x[i, d] = buf[o + d]
            v[i, d] = buf[o + 3 + d]
            w[i, d] = buf[o + 6 + d]


@njit(**JIT)
def resolve_bond_partners(gid, nlocal, bond_gid, bond_j):
    """bond_j[i, s] = local index of partner gid bond_gid[i, s] for owned i (searching owned + ghosts).

    A dense map over the span of the local gids (a rank's rows of the lattice: a few times its
    element count) finds each partner in one lookup. Returns (number of partners not found, an
    owned gid with a missing partner or -1, that partner).
    """
    n = gid.shape[0]
    missing = 0
    who = -1
    partner = -1
    if n == 0:
        return missing, who, partner
    lo = gid[0]
    hi = gid[0]
    for i in range(n):
        lo = min(lo, gid[i])
        hi = max(hi, gid[i])
    where = np.full(hi - lo + 1, -1, dtype=np.int64)
    for i in range(n - 1, -1, -1):  # the first row of a gid wins, as a search of the sorted gids found it
        where[gid[i] - lo] = i
    for i in range(nlocal):
        for s in range(bond_gid.shape[1]):
            g = bond_gid[i, s]
            if g < 0:
                bond_j[i, s] = -1
                continue
            k = where[g - lo] if lo <= g <= hi else -1
            bond_j[i, s] = k
            if k < 0:
                missing += 1
                who = gid[i]
                partner = g
    return missing, who, partner


@njit(**JIT)
def max_displacement(x, x_ref, n):
    """Largest |x - x_ref| over the first n rows [m]."""
    worst = 0.0
    for i in range(n):
        d0 = x[i, 0] - x_ref[i, 0]
        d1 = x[i, 1] - x_ref[i, 1]
        d2 = x[i, 2] - x_ref[i, 2]
        d = d0 * d0 + d1 * d1 + d2 * d2
        if d > worst:
            worst = d
    return np.sqrt(worst)


@njit(**JIT)
def motion_bounds(x, x_ref, v, force, ext_force, mass, fix_mask, n):
    """Over the first n rows: (largest |x - x_ref| [m], largest |v| [m/s], largest |a| [m/s^2]).

    a = (F + F_ext) / m on the components that are integrated (a prescribed component keeps its
    velocity, whatever force it carries). Halo.needs_rebuild bounds the motion to the next check with them."""
    moved = 0.0
    speed = 0.0
    accel = 0.0
    for i in range(n):
        d2 = 0.0
        s2 = 0.0
        a2 = 0.0
        for k in range(3):
            d = x[i, k] - x_ref[i, k]
            d2 += d * d
            s2 += v[i, k] * v[i, k]
            if not fix_mask[i, k]:
                a = (force[i, k] + ext_force[i, k]) / mass[i]
                a2 += a * a
        # written so that a NaN is kept (max() with a NaN would drop it): the caller then checks every step
        if not d2 <= moved:
            moved = d2
        if not s2 <= speed:
            speed = s2
        if not a2 <= accel:
            accel = a2
    return np.sqrt(moved), np.sqrt(speed), np.sqrt(accel)


@njit(**JIT)
def longest_bond(x, nlocal, bond_j):
    """Length of the longest intact bond of an owned particle [m] (partners must be resolved)."""
    worst = 0.0
    for i in range(nlocal):
        for s in range(bond_j.shape[1]):
            j = bond_j[i, s]
            if j < 0:
                continue
            d0 = x[j, 0] - x[i, 0]
            d1 = x[j, 1] - x[i, 1]
            d2 = x[j, 2] - x[i, 2]
            d = d0 * d0 + d1 * d1 + d2 * d2
            if d > worst:
                worst = d
    return np.sqrt(worst)
