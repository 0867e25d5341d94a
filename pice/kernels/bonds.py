"""Parallel-bond forces and breakage (Zhu & Ji 2022, Eqs. 1-5), canonical per bond.

Every bond is evaluated in its canonical orientation (a = lower gid, b = higher gid), so any rank
holding either end computes the same numbers to the last bit and breaks the bond at the same step.
A bond whose both ends are owned is evaluated once, from the lower-gid end, whose copy of the history
is then the current one; ``sync_mate_history`` brings the other copy up to date before it can be
read (before particles migrate, and before output). A bond to a ghost is evaluated by each rank for
its own end, each on its own copy.

law: the bond's parameters by name (physics.bond.BondLaw): springs kn, ks [N/m], kt, kb [N m/rad];
the section of the bond: area, inertia, polar [m^2, m^4, m^4] and the fibre distances bend_fiber,
twist_fiber [m] (a disk: both its radius R); normal_strength, shear_strength, compressive_strength
[Pa], friction (mu), shear_law; dashpots cn, cs [N s/m], ct, cb [N m s/rad].

Failure modes are the named constants below; ``failure_mode`` states the criteria and
``failure_mode_squared``, which the kernel calls, decides by the same criteria on squared magnitudes
(tests/unit/test_bond_kernel.py checks that the two agree). The stresses on the bond's section
(Eqs. 3-4 of Zhu & Ji 2022, tension positive):

    sigma_n = T / A,   sigma_b = |M_b| c_b / I,   tau = |F_s| / A + |M_t| c_t / J

It breaks in tension and bending when sigma_n + sigma_b reaches the normal strength; in compression
(an optional cap) when sigma_b - sigma_n reaches the compressive strength; in shear and twist when
tau reaches the shear strength tau_c. With shear_law MOHR_COULOMB (the default), tau_c = sigma_s -
mu sigma_n: compression raises it, as in Potyondy & Cundall (2004) and Itasca's parallel bond; with
ZHU_JI_EQ5, tau_c = mu (sigma_n + sigma_b) + sigma_s, Eq. 5 of the paper as printed.
"""

import math

from numba import njit

from . import JIT, JIT_FMA

INTACT = 0
TENSION_BENDING = 1  # Eq. 3: tension plus bending reaches the normal strength
SHEAR_TWIST = 2      # Eqs. 4-5: shear plus twist reaches the shear strength
COMPRESSION = 3      # compression plus bending reaches the bond's compressive strength (optional cap)
CRUSHED = 4          # one of its elements was crushed through at a structure (physics/crushing.py)
FAILURE_MODES = {TENSION_BENDING: "tension + bending", SHEAR_TWIST: "shear + twist",
                 COMPRESSION: "compression + bending", CRUSHED: "element crushed"}

MOHR_COULOMB = 0     # tau_c = sigma_s - mu sigma_n: compression raises the shear strength
ZHU_JI_EQ5 = 1       # tau_c = mu sigma_max + sigma_s: Eq. 5 of Zhu & Ji (2022) as printed


@njit(**JIT, inline="always")
def failure_mode(sigma_n, sigma_b, tau, law):
    """The bond's failure mode from its normal stress sigma_n = T/A (tension > 0), bending stress
    sigma_b = |M_b| c_b / I >= 0 and shear stress tau [Pa]: INTACT, TENSION_BENDING, COMPRESSION or
    SHEAR_TWIST (the module docstring gives the criteria)."""
    sigma_max = sigma_n + sigma_b
    if sigma_max >= law.normal_strength:
        return TENSION_BENDING
    if sigma_b - sigma_n >= law.compressive_strength:
        return COMPRESSION
    if law.shear_law == MOHR_COULOMB:
        tau_c = law.shear_strength - law.friction * sigma_n
    else:
        tau_c = law.friction * sigma_max + law.shear_strength
    if tau >= tau_c:
        return SHEAR_TWIST
    return INTACT


@njit(**JIT, inline="always")
def failure_mode_squared(sigma_n, mb2, fs2, mt_abs, law):
    """``failure_mode`` from the squared magnitudes of the bending moment mb2 [N^2 m^2] and the shear
    force fs2 [N^2], and |M_t| [N m]: the same criteria compared without the two square roots where
    the shear law allows (Mohr-Coulomb), for the bonds that stay intact (nearly all of them)."""
    bend = law.bend_fiber / law.inertia          # sigma_b = |M_b| bend [Pa]
    reserve = law.normal_strength - sigma_n     # tension + bending: sigma_b >= reserve
    if reserve <= 0.0 or mb2 * bend * bend >= reserve * reserve:
        return TENSION_BENDING
    reserve = law.compressive_strength + sigma_n  # compression + bending: sigma_b >= reserve
    if reserve <= 0.0 or mb2 * bend * bend >= reserve * reserve:
        return COMPRESSION
    twist = mt_abs * (law.twist_fiber / law.polar)  # the factor is the same for every bond: hoisted
    if law.shear_law == MOHR_COULOMB:
        tau_c = law.shear_strength - law.friction * sigma_n
    else:
        tau_c = law.friction * (sigma_n + math.sqrt(mb2) * bend) + law.shear_strength
    reserve = (tau_c - twist) * law.area          # shear + twist: |F_s| >= reserve
    if reserve <= 0.0 or fs2 >= reserve * reserve:
        return SHEAR_TWIST
    return INTACT


@njit(**JIT, inline="always")
def _turned(a0, a1, a2, n0, n1, n2):
    """a less its component along unit n, rescaled to its former length: a history vector turned
    with the bond into the plane normal to n. The scale is 1 / sqrt(1 - x), x = (a.n)^2 / |a|^2; a
    bond turns little in a step, and for x < 1e-6 its series 1 + x/2 + 3x^2/8 is exact to round-off
    (the next term, 5x^3/16, is below 1e-18) and saves a division and a square root."""
    mag2 = a0 * a0 + a1 * a1 + a2 * a2
    d = a0 * n0 + a1 * n1 + a2 * n2
    a0 -= d * n0
    a1 -= d * n1
    a2 -= d * n2
    dd = d * d
    if dd < 1e-6 * mag2:  # the bond turned little: 1/sqrt(1 - x) to third order in x = d^2/|a|^2
        x = dd / mag2
        sc = 1.0 + x * (0.5 + 0.375 * x)
    else:
        new2 = a0 * a0 + a1 * a1 + a2 * a2
        sc = math.sqrt(mag2 / new2) if new2 > 0.0 else 0.0
    return a0 * sc, a1 * sc, a2 * sc


@njit(**JIT, inline="always")
def _bond_core(a, b, x, v, w, radius, L0, H, i, s, law, dt):
    """Advance the history H[i, s, :] (8,: shear force (3), twisting moment, bending moment (3), tension,
    canonical orientation) of the bond between a (the lower-gid end) and b by one step; return
    (mode, force on a (3), moment on a (3), moment on b (3)) as plain floats: the failure mode
    (INTACT, or a failure mode with all loads zero) and the loads [N], [N m] (b receives the opposite
    force). The history is read once and written once."""
    dx0 = x[b, 0] - x[a, 0]
    dx1 = x[b, 1] - x[a, 1]
    dx2 = x[b, 2] - x[a, 2]
    L = math.sqrt(dx0 * dx0 + dx1 * dx1 + dx2 * dx2)
    inv_L = 1.0 / L
    n0, n1, n2 = dx0 * inv_L, dx1 * inv_L, dx2 * inv_L
    ca = radius[a] + 0.5 * (L - radius[a] - radius[b])  # centre of a -> contact point [m]
    cb = L - ca
    wa0, wa1, wa2 = w[a, 0], w[a, 1], w[a, 2]
    wb0, wb1, wb2 = w[b, 0], w[b, 1], w[b, 2]
    # velocity of the contact point carried by b minus that carried by a
    vr0 = (v[b, 0] - cb * (wb1 * n2 - wb2 * n1)) - (v[a, 0] + ca * (wa1 * n2 - wa2 * n1))
    vr1 = (v[b, 1] - cb * (wb2 * n0 - wb0 * n2)) - (v[a, 1] + ca * (wa2 * n0 - wa0 * n2))
    vr2 = (v[b, 2] - cb * (wb0 * n1 - wb1 * n0)) - (v[a, 2] + ca * (wa0 * n1 - wa1 * n0))
    vn = vr0 * n0 + vr1 * n1 + vr2 * n2
    vs0, vs1, vs2 = vr0 - vn * n0, vr1 - vn * n1, vr2 - vn * n2
    wr0, wr1, wr2 = wb0 - wa0, wb1 - wa1, wb2 - wa2
    wn = wr0 * n0 + wr1 * n1 + wr2 * n2
    ws0, ws1, ws2 = wr0 - wn * n0, wr1 - wn * n1, wr2 - wn * n2
    h0, h1, h2 = _turned(H[i, s, 0], H[i, s, 1], H[i, s, 2], n0, n1, n2)
    h4, h5, h6 = _turned(H[i, s, 4], H[i, s, 5], H[i, s, 6], n0, n1, n2)
    # Eqs. 1-2: incremental shear force, twisting and bending moments on a
    ksdt, kbdt = law.ks * dt, law.kb * dt
    fs0 = h0 + ksdt * vs0
    fs1 = h1 + ksdt * vs1
    fs2 = h2 + ksdt * vs2
    mt = H[i, s, 3] + law.kt * dt * wn
    mb0 = h4 + kbdt * ws0
    mb1 = h5 + kbdt * ws1
    mb2 = h6 + kbdt * ws2
    tension = law.kn * (L - L0)  # normal force, the integral of Eq. 1 [N]
    H[i, s, 0], H[i, s, 1], H[i, s, 2], H[i, s, 3] = fs0, fs1, fs2, mt
    H[i, s, 4], H[i, s, 5], H[i, s, 6], H[i, s, 7] = mb0, mb1, mb2, tension
    mode = failure_mode_squared(tension * (1.0 / law.area), mb0 * mb0 + mb1 * mb1 + mb2 * mb2,
                                fs0 * fs0 + fs1 * fs1 + fs2 * fs2, abs(mt), law)  # Eqs. 3-5
    if mode != INTACT:
        return (mode, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    fn = tension + law.cn * vn
    cs = law.cs
    fa0 = fn * n0 + fs0 + cs * vs0
    fa1 = fn * n1 + fs1 + cs * vs1
    fa2 = fn * n2 + fs2 + cs * vs2
    # the bond's own moments on a, plus the moment of the force about each centre
    mtot = mt + law.ct * wn
    cbd = law.cb
    own0 = mtot * n0 + mb0 + cbd * ws0
    own1 = mtot * n1 + mb1 + cbd * ws1
    own2 = mtot * n2 + mb2 + cbd * ws2
    c0 = n1 * fa2 - n2 * fa1
    c1 = n2 * fa0 - n0 * fa2
    c2 = n0 * fa1 - n1 * fa0
    return (0, fa0, fa1, fa2, own0 + ca * c0, own1 + ca * c1, own2 + ca * c2,
            -own0 + cb * c0, -own1 + cb * c1, -own2 + cb * c2)


@njit(**JIT_FMA)
def bond_forces(nlocal, gid, x, v, w, radius, bond_j, bond_mate, bond_gid, bond_L0, bond_hist,
                law, dt, force, torque, events, removed):
    """Add the forces of every intact bond touching an owned particle; break failed bonds.

    Args:
        events: (max_events, 3) int64 log of bonds broken this call: (gid_a, gid_b, mode); the
            breaks beyond its length are counted but not logged.
        removed: (max_removed, 2) int64 log of the bonds this rank removed from its rows, as local
            (i, j) with i owned (the lower-gid end when both are owned: the contact pair list's
            convention, kernels/pair_list.insert_pairs); those beyond its length are counted only.

    Returns:
        (broken, removed): the bonds broken in this call, counted once over the ranks (by the rank that
        owns the lower-gid end), and the bonds this rank removed from its rows (a bond to a ghost breaks
        on both ranks holding it).
    """
    nslots = bond_j.shape[1]
    max_events = events.shape[0]
    nbroken = 0
    nremoved = 0
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
            r = _bond_core(a, b, x, v, w, radius, bond_L0[i, s], bond_hist, i, s, law, dt)
            if r[0] != INTACT:
                if nremoved < removed.shape[0]:
                    removed[nremoved, 0] = i
                    removed[nremoved, 1] = j
                nremoved += 1
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
                        events[nbroken, 2] = r[0]
                    nbroken += 1
                continue
            sign = 1.0 if i_is_a else -1.0
            f0, f1, f2 = sign * r[1], sign * r[2], sign * r[3]
            force[i, 0] += f0
            force[i, 1] += f1
            force[i, 2] += f2
            if i_is_a:
                torque[i, 0] += r[4]
                torque[i, 1] += r[5]
                torque[i, 2] += r[6]
            else:
                torque[i, 0] += r[7]
                torque[i, 1] += r[8]
                torque[i, 2] += r[9]
            if j_owned:  # i is a: b's force (b's copy of the history is synced by sync_mate_history)
                force[j, 0] -= f0
                force[j, 1] -= f1
                force[j, 2] -= f2
                torque[j, 0] += r[7]
                torque[j, 1] += r[8]
                torque[j, 2] += r[9]
    return nbroken, nremoved


@njit(**JIT)
def bond_energy(nlocal, gid, bond_gid, bond_hist, law):
    """Elastic energy [J] stored in intact bonds with an owned lower-gid end (each bond counted once)."""
    kn, ks, kt, kb = law.kn, law.ks, law.kt, law.kb
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


@njit(**JIT)
def sync_mate_history(nlocal, gid, bond_j, bond_mate, bond_hist):
    """Copy the history of every bond between two owned particles from its lower-gid end to the other.

    Only the lower-gid end's copy is advanced when both ends are owned (half the memory traffic);
    call this before either copy may be read from the higher-gid side: before migration and output.
    """
    for i in range(nlocal):
        for s in range(bond_j.shape[1]):
            j = bond_j[i, s]
            if j < 0 or j >= nlocal or gid[j] < gid[i]:
                continue
            m = bond_mate[i, s]
            for k in range(bond_hist.shape[2]):
                bond_hist[j, m, k] = bond_hist[i, s, k]


@njit(**JIT)
def sync_leaving_history(leaving, nlocal, gid, bond_j, bond_mate, bond_hist):
    """``sync_mate_history`` for the bonds of the owned rows ``leaving`` (indices < nlocal) only:
    each bond between a leaving row and another owned row gets its lower-gid end's history at both
    ends. Before a migration this is all that must agree: a bond whose ends both stay owned is read
    from its lower-gid end alone, here as before; a bond that the migration cuts is then advanced
    at each end by its own rank, from its own copy (both the lower end's, bit for bit)."""
    for i in leaving:
        for s in range(bond_j.shape[1]):
            j = bond_j[i, s]
            if j < 0 or j >= nlocal:
                continue
            m = bond_mate[i, s]
            if gid[i] < gid[j]:
                for k in range(bond_hist.shape[2]):
                    bond_hist[j, m, k] = bond_hist[i, s, k]
            else:
                for k in range(bond_hist.shape[2]):
                    bond_hist[i, s, k] = bond_hist[j, m, k]
