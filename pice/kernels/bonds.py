"""Parallel-bond forces and breakage (Zhu & Ji 2022, Eqs. 1-5), canonical per bond.

Every bond is evaluated in its canonical orientation (a = lower gid, b = higher gid), so any rank
holding either end computes the same numbers to the last bit and breaks the bond at the same step.
A bond whose both ends are owned is evaluated once (from the lower-gid end) and both copies of its
history are written; a bond to a ghost is evaluated by each rank for its own end.

params (float64 array, see physics.bond.BondParams.as_array):
    0 kn [N/m]  1 ks [N/m]  2 kt [N m/rad]  3 kb [N m/rad]  4 A [m^2]  5 I [m^4]  6 J [m^4]
    7 R [m]  8 normal strength [Pa]  9 shear strength [Pa]  10 mu  11-14 dashpots cn, cs, ct, cb
"""

import math

import numpy as np
from numba import njit

from . import JIT


@njit(**JIT)
def _project_keep_magnitude(vec, n):
    """Remove the component of ``vec`` along unit ``n`` and restore its length (rotates history)."""
    mag2 = vec[0] * vec[0] + vec[1] * vec[1] + vec[2] * vec[2]
    if mag2 == 0.0:
        return
    d = vec[0] * n[0] + vec[1] * n[1] + vec[2] * n[2]
    vec[0] -= d * n[0]
    vec[1] -= d * n[1]
    vec[2] -= d * n[2]
    new2 = vec[0] * vec[0] + vec[1] * vec[1] + vec[2] * vec[2]
    if new2 > 0.0:
        s = math.sqrt(mag2 / new2)
        vec[0] *= s
        vec[1] *= s
        vec[2] *= s


@njit(**JIT)
def bond_update(a, b, x, v, w, radius, L0, hist, params, dt, out_force, out_moment_a, out_moment_b):
    """Advance one bond's history by one step and return its failure state.

    Args:
        a, b: local indices of the lower-gid and higher-gid ends.
        hist: (8,) history in the canonical orientation, updated in place.
        out_force: (3,) force on end a [N] (end b receives the opposite), written.
        out_moment_a, out_moment_b: (3,) moments on each end [N m], written.

    Returns:
        0 intact, 1 broken in tension/bending (Eq. 3), 2 broken in shear/twist (Eqs. 4-5).
    """
    kn, ks, kt, kb = params[0], params[1], params[2], params[3]
    A, I, J, R = params[4], params[5], params[6], params[7]
    dx0 = x[b, 0] - x[a, 0]
    dx1 = x[b, 1] - x[a, 1]
    dx2 = x[b, 2] - x[a, 2]
    L = math.sqrt(dx0 * dx0 + dx1 * dx1 + dx2 * dx2)
    n = np.empty(3)
    n[0] = dx0 / L
    n[1] = dx1 / L
    n[2] = dx2 / L
    ca = radius[a] + 0.5 * (L - radius[a] - radius[b])  # centre of a -> contact point [m]
    cb = L - ca
    # velocity of the contact point carried by b minus that carried by a
    vr = np.empty(3)
    vr[0] = (v[b, 0] - cb * (w[b, 1] * n[2] - w[b, 2] * n[1])) - (v[a, 0] + ca * (w[a, 1] * n[2] - w[a, 2] * n[1]))
    vr[1] = (v[b, 1] - cb * (w[b, 2] * n[0] - w[b, 0] * n[2])) - (v[a, 1] + ca * (w[a, 2] * n[0] - w[a, 0] * n[2]))
    vr[2] = (v[b, 2] - cb * (w[b, 0] * n[1] - w[b, 1] * n[0])) - (v[a, 2] + ca * (w[a, 0] * n[1] - w[a, 1] * n[0]))
    vn = vr[0] * n[0] + vr[1] * n[1] + vr[2] * n[2]
    wr0 = w[b, 0] - w[a, 0]
    wr1 = w[b, 1] - w[a, 1]
    wr2 = w[b, 2] - w[a, 2]
    wn = wr0 * n[0] + wr1 * n[1] + wr2 * n[2]
    vs = np.empty(3)
    ws = np.empty(3)
    for k in range(3):
        vs[k] = vr[k] - vn * n[k]
    ws[0] = wr0 - wn * n[0]
    ws[1] = wr1 - wn * n[1]
    ws[2] = wr2 - wn * n[2]
    fs = hist[0:3]
    mb = hist[4:7]
    _project_keep_magnitude(fs, n)
    _project_keep_magnitude(mb, n)
    # Eqs. 1-2: incremental shear force, twisting and bending moments on a
    for k in range(3):
        fs[k] += ks * vs[k] * dt
        mb[k] += kb * ws[k] * dt
    hist[3] += kt * wn * dt
    tension = kn * (L - L0)  # normal force, the integral of Eq. 1 [N]
    hist[7] = tension
    mt = hist[3]
    fs_mag = math.sqrt(fs[0] * fs[0] + fs[1] * fs[1] + fs[2] * fs[2])
    mb_mag = math.sqrt(mb[0] * mb[0] + mb[1] * mb[1] + mb[2] * mb[2])
    sigma = tension / A + mb_mag * R / I          # Eq. 3, tension positive [Pa]
    tau = fs_mag / A + abs(mt) * R / J            # Eq. 4 [Pa]
    if sigma >= params[8]:
        return 1
    if tau >= params[10] * sigma + params[9]:     # Eq. 5
        return 2
    cn, cs, ct, cbd = params[11], params[12], params[13], params[14]
    for k in range(3):
        out_force[k] = (tension + cn * vn) * n[k] + fs[k] + cs * vs[k]
    # moment of the force about each centre, plus the bond's own moments
    fa0, fa1, fa2 = out_force[0], out_force[1], out_force[2]
    ax, ay, az = ca * n[0], ca * n[1], ca * n[2]
    bx, by, bz = cb * n[0], cb * n[1], cb * n[2]
    for k in range(3):
        own = (mt + ct * wn) * n[k] + mb[k] + cbd * ws[k]
        out_moment_a[k] = own
        out_moment_b[k] = -own
    out_moment_a[0] += ay * fa2 - az * fa1
    out_moment_a[1] += az * fa0 - ax * fa2
    out_moment_a[2] += ax * fa1 - ay * fa0
    out_moment_b[0] += by * fa2 - bz * fa1
    out_moment_b[1] += bz * fa0 - bx * fa2
    out_moment_b[2] += bx * fa1 - by * fa0
    return 0


@njit(**JIT)
def bond_forces(nlocal, gid, x, v, w, radius, bond_j, bond_mate, bond_gid, bond_L0, bond_hist,
                params, dt, force, torque, events, max_events):
    """Add the forces of every intact bond touching an owned particle; break failed bonds.

    Args:
        events: (max_events, 4) int64 log of bonds broken this call: (gid_a, gid_b, mode, 0).

    Returns:
        Number of bonds broken in this call (counted once per bond on this rank).
    """
    nslots = bond_j.shape[1]
    f = np.zeros(3)
    ma = np.zeros(3)
    mb = np.zeros(3)
    nbroken = 0
    for i in range(nlocal):
        for s in range(nslots):
            j = bond_j[i, s]
            if j < 0:
                continue
            j_owned = j < nlocal
            if j_owned and gid[j] < gid[i]:
                continue  # evaluated from j's side
            i_is_a = gid[i] < gid[j]
            a = i if i_is_a else j
            b = j if i_is_a else i
            h = bond_hist[i, s]
            mode = bond_update(a, b, x, v, w, radius, bond_L0[i, s], h, params, dt, f, ma, mb)
            if mode != 0:
                bond_j[i, s] = -1
                bond_gid[i, s] = -1
                if j_owned:
                    m = bond_mate[i, s]
                    bond_j[j, m] = -1
                    bond_gid[j, m] = -1
                if i_is_a:  # the rank owning the lower-gid end counts and logs the break
                    if nbroken < max_events:
                        events[nbroken, 0] = gid[a]
                        events[nbroken, 1] = gid[b]
                        events[nbroken, 2] = mode
                        events[nbroken, 3] = 0
                    nbroken += 1
                continue
            sign = 1.0 if i_is_a else -1.0
            mi = ma if i_is_a else mb
            mj = mb if i_is_a else ma
            for k in range(3):
                force[i, k] += sign * f[k]
                torque[i, k] += mi[k]
            if j_owned:
                bond_hist[j, bond_mate[i, s]][:] = h
                for k in range(3):
                    force[j, k] -= sign * f[k]
                    torque[j, k] += mj[k]
    return nbroken


@njit(**JIT)
def bond_energy(nlocal, gid, bond_gid, bond_hist, params):
    """Elastic energy [J] stored in intact bonds with an owned lower-gid end (each bond counted once)."""
    kn, ks, kt, kb = params[0], params[1], params[2], params[3]
    e = 0.0
    for i in range(nlocal):
        for s in range(bond_gid.shape[1]):
            if bond_gid[i, s] < 0 or bond_gid[i, s] < gid[i]:
                continue
            h = bond_hist[i, s]
            e += 0.5 * h[7] * h[7] / kn
            if ks > 0:
                e += 0.5 * (h[0] * h[0] + h[1] * h[1] + h[2] * h[2]) / ks
            if kt > 0:
                e += 0.5 * h[3] * h[3] / kt
            if kb > 0:
                e += 0.5 * (h[4] * h[4] + h[5] * h[5] + h[6] * h[6]) / kb
    return e
