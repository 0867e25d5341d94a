"""DEM mooring line kernels: chains of nodes joined by axial bonds without bending stiffness (000_..., 2.3).

Each node stands for a piece of line of length dl (half pieces at the ends). Per node:
- axial bonds to its neighbours: tension EA (l - l0)/l0 when stretched, nothing in compression
  (a chain or wire goes slack), plus an axial dashpot at a damping ratio of the bond;
- weight in water (wet weight per length x dl) and Morison loads (Eq. 8 of Zhu & Ji 2022, for a
  cylinder piece instead of a sphere): normal drag 1/2 rho C_dn D dl |v_n| v_n, tangential drag
  1/2 rho C_dt pi D dl |v_t| v_t, and added mass C_a rho pi D^2/4 dl on the normal acceleration;
  in waves the drag acts on the current plus the undisturbed particle velocity at the node,
  relative to the node, and the fluid acceleration a adds the inertia load rho V (a + C_a a_n)
  (Froude-Krylov on the whole acceleration, added mass on its part normal to the line; V = pi
  D^2/4 dl), a node being wet below the wave surface over it (docs/waves.md);
- seabed contact below z = seabed: a penalty spring and dashpot, Coulomb friction (regularised).
Node kinds: 0 free, 1 fixed (anchor), 2 prescribed (fairlead, moved with its body).

Arrays: x, v (n, 3); mass (n,) dry mass [kg]; prev (n,) index of the previous node on the line or -1;
seg (n,) index of the element (bond) from prev to this node; props (n_elements,) records of
platform.mooring_lines.LINE_ELEMENT_RECORD: ea [N], l0 [m], diameter D [m], wet_weight [N/m],
drag_normal C_dn, drag_tangential C_dt, added_mass C_a, damping_ratio (of the bond), read by
field name as ``props[s]["ea"]`` (numba compiles it to the loads of a column index; plain Python,
NUMBA_DISABLE_JIT=1, runs it too, which ``props[s].ea`` would not). Scalars as named tuples
(platform.mooring_lines): water LineWater(density [kg/m^3], level [m]); seabed Seabed(z [m],
stiffness [N/m per m of line], damping_ratio, friction, slip_velocity [m/s]); the sea as
platform.sea.SeaComponents (no components: still water, which costs one test per node) with z up
from the water's level, and the ``time`` [s] of the forces.

The waves at the nodes: ``node_waves`` (platform.wave_intervals) gives each node's WAVE_FIELDS (eta
[m] over it, particle velocity [m/s] and acceleration [m/s^2] at it) at two times in one pass over
the sea's components. The platform takes them at the ends of intervals of several platform steps,
at the nodes' places at the interval's start (platform.wave_intervals.WaveIntervals); ``advance_lines``
gets the two ends and where its own start and end lie between them, and every sub-step
interpolates linearly in time (docs/waves.md, Cost); ``node_forces`` reads the result. Still water
passes (0, WAVE_FIELDS) arrays and does none of this.

Every function here is a numba kernel: a pure function of arrays and scalars (no MPI, no I/O),
owned by platform.mooring_lines.MooringLines. A sub-step (``verlet_substep``) is written once; the
time stepping (``advance_lines``) and the static relaxation (``relax_lines``) both take it.
"""

import math

import numpy as np
from numba import njit

from ..kernels import JIT
from .sea import wave_at
from .wave_intervals import WAVE_FIELDS, blend_waves

FREE, FIXED, PRESCRIBED = 0, 1, 2


# columns of ``node_constants``: what each node stands for, from the half of each adjacent element
WEIGHT, DRAG_N, DRAG_T, ADDED, DIAMETER, LENGTH, VOLUME = range(7)


@njit(**JIT)
def node_constants(prev, seg, props):
    """(n, 7) per node, from the half of each adjacent element it stands for: its weight in water [N],
    drag areas x coefficients C_dn D dl and C_dt pi D dl [m^2], added-mass coefficient x volume
    C_a pi D^2/4 dl [m^3], largest diameter [m] (the seabed), line length dl [m] and displaced
    volume pi D^2/4 dl [m^3] (columns WEIGHT..VOLUME). They depend on the lines' elements only:
    platform.mooring_lines.MooringLines takes them once."""
    n = prev.shape[0]
    out = np.zeros((n, 7))
    for i in range(n):
        p = prev[i]
        if p < 0:
            continue
        el = props[seg[i]]
        D, half = el["diameter"], 0.5 * el["l0"]
        for node in (p, i):
            out[node, WEIGHT] += el["wet_weight"] * half
            out[node, DRAG_N] += el["drag_normal"] * D * half
            out[node, DRAG_T] += el["drag_tangential"] * math.pi * D * half
            out[node, ADDED] += el["added_mass"] * 0.25 * math.pi * D * D * half
            out[node, DIAMETER] = max(out[node, DIAMETER], D)
            out[node, LENGTH] += half
            out[node, VOLUME] += 0.25 * math.pi * D * D * half
    return out


@njit(**JIT)
def line_forces(x, v, mass, prev, seg, props, constants, kind, water, current, seabed, sea, time, force, tension,
                added_mass, tangent):
    """``node_forces`` in ``sea`` (SeaComponents) at ``time`` [s], its waves taken at every node
    (``wave_at``, the sums of kernels.waves.sea_point); still water takes none."""
    n = x.shape[0] if sea.amplitude.shape[0] > 0 else 0
    wave = np.empty((n, WAVE_FIELDS))
    for i in range(n):
        w = wave_at(sea, x[i, 0], x[i, 1], x[i, 2] - water.level, time)
        for f in range(WAVE_FIELDS):
            wave[i, f] = w[f]
    node_forces(x, v, mass, prev, seg, props, constants, kind, water, current, seabed, wave, force, tension,
                added_mass, tangent)


@njit(**JIT)
def node_forces(x, v, mass, prev, seg, props, constants, kind, water, current, seabed, wave, force, tension,
                added_mass, tangent):
    """Forces on every node [N]; bond tensions [N] stored at the bond's upper node; added mass [kg];
    the unit tangent at every node, the mean direction of its bonds (0 for a node without bonds).

    constants: ``node_constants``; water: LineWater (density [kg/m^3], level [m]); current: (3,)
    [m/s]; seabed: Seabed (z [m], stiffness [N/m per m of line], damping_ratio, friction,
    slip_velocity [m/s]); wave: (n, WAVE_FIELDS) the waves at each node (eta [m] over it, particle
    velocity [m/s], acceleration [m/s^2]; ``node_waves``), or (0, WAVE_FIELDS) in still water.
    """
    n = x.shape[0]
    rho = water.density
    for i in range(n):
        force[i, 0] = 0.0
        force[i, 1] = 0.0
        force[i, 2] = 0.0
        tension[i] = 0.0
        added_mass[i] = 0.0
        tangent[i, 0] = 0.0
        tangent[i, 1] = 0.0
        tangent[i, 2] = 0.0
    waves = wave.shape[0] > 0
    # axial bonds
    for i in range(n):
        p = prev[i]
        if p < 0:
            continue
        el = props[seg[i]]
        ea, l0, zeta = el["ea"], el["l0"], el["damping_ratio"]
        d0 = x[i, 0] - x[p, 0]
        d1 = x[i, 1] - x[p, 1]
        d2 = x[i, 2] - x[p, 2]
        l = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
        u0, u1, u2 = d0 / l, d1 / l, d2 / l
        k = ea / l0
        t = k * (l - l0) if l > l0 else 0.0
        if zeta > 0.0 and l > l0:
            m_red = mass[i] * mass[p] / (mass[i] + mass[p])
            rate = (v[i, 0] - v[p, 0]) * u0 + (v[i, 1] - v[p, 1]) * u1 + (v[i, 2] - v[p, 2]) * u2
            t += 2.0 * zeta * math.sqrt(k * m_red) * rate
        tension[i] = t
        force[p, 0] += t * u0
        force[p, 1] += t * u1
        force[p, 2] += t * u2
        force[i, 0] -= t * u0
        force[i, 1] -= t * u1
        force[i, 2] -= t * u2
        tangent[p, 0] += u0
        tangent[p, 1] += u1
        tangent[p, 2] += u2
        tangent[i, 0] += u0
        tangent[i, 1] += u1
        tangent[i, 2] += u2
    # weight, Morison loads and seabed per node
    z_bed, k_bed, zeta_bed, mu_bed, v_slip = (seabed.z, seabed.stiffness, seabed.damping_ratio, seabed.friction,
                                              seabed.slip_velocity)
    for i in range(n):
        c = constants[i]
        force[i, 2] -= c[WEIGHT]
        tn = math.sqrt(tangent[i, 0] ** 2 + tangent[i, 1] ** 2 + tangent[i, 2] ** 2)
        if tn > 0:
            for k in range(3):
                tangent[i, k] /= tn
            t0, t1, t2 = tangent[i, 0], tangent[i, 1], tangent[i, 2]
        else:
            t0, t1, t2 = 0.0, 0.0, 1.0
        wet = x[i, 2] <= water.level
        f0, f1, f2 = current[0], current[1], current[2]
        if waves:
            w = wave[i]
            wet = x[i, 2] <= water.level + w[0]
            if wet:
                # Froude-Krylov rho V a and added mass rho C_a V a_n (normal part); the drag's flow
                at = w[4] * t0 + w[5] * t1 + w[6] * t2
                fk, ca = rho * c[VOLUME], rho * c[ADDED]
                force[i, 0] += fk * w[4] + ca * (w[4] - at * t0)
                force[i, 1] += fk * w[5] + ca * (w[5] - at * t1)
                force[i, 2] += fk * w[6] + ca * (w[6] - at * t2)
                f0, f1, f2 = f0 + w[1], f1 + w[2], f2 + w[3]
        if wet:
            r0 = f0 - v[i, 0]
            r1 = f1 - v[i, 1]
            r2 = f2 - v[i, 2]
            rt = r0 * t0 + r1 * t1 + r2 * t2
            n0, n1, n2 = r0 - rt * t0, r1 - rt * t1, r2 - rt * t2
            vn = math.sqrt(n0 * n0 + n1 * n1 + n2 * n2)
            cn = 0.5 * rho * c[DRAG_N] * vn
            ct = 0.5 * rho * c[DRAG_T] * abs(rt)
            force[i, 0] += cn * n0 + ct * rt * t0
            force[i, 1] += cn * n1 + ct * rt * t1
            force[i, 2] += cn * n2 + ct * rt * t2
            added_mass[i] = rho * c[ADDED]
        pen = z_bed - (x[i, 2] - 0.5 * c[DIAMETER])
        if k_bed > 0.0 and pen > 0.0:
            kb = k_bed * c[LENGTH]
            fn = kb * pen - 2.0 * zeta_bed * math.sqrt(kb * mass[i]) * v[i, 2]
            if fn > 0.0:
                force[i, 2] += fn
                sx, sy = v[i, 0], v[i, 1]
                sp = math.sqrt(sx * sx + sy * sy)
                if sp > 0.0:
                    f = mu_bed * fn * min(1.0, sp / v_slip) / sp
                    force[i, 0] -= f * sx
                    force[i, 1] -= f * sy


@njit(**JIT)
def accelerate(v, force, mass, added_mass, tangent_of, kind, half_dt):
    """v += M^-1 F half_dt with the added mass acting on the normal direction only; fixed and
    prescribed nodes are not integrated (their velocities are set by the caller)."""
    n = v.shape[0]
    for i in range(n):
        if kind[i] != FREE:
            continue
        t0, t1, t2 = tangent_of[i, 0], tangent_of[i, 1], tangent_of[i, 2]
        ft = force[i, 0] * t0 + force[i, 1] * t1 + force[i, 2] * t2
        m_n = mass[i] + added_mass[i]
        for k in range(3):
            fk_t = ft * tangent_of[i, k]
            v[i, k] += half_dt * (fk_t / mass[i] + (force[i, k] - fk_t) / m_n)


@njit(**JIT)
def verlet_substep(x, v, mass, prev, seg, props, constants, kind, water, current, seabed, wave0, wave1, wave, wave_a,
                   force, tension, added_mass, tangent, fairleads, x_start, x_end, v_fairlead, a, dt):
    """One velocity-Verlet sub-step of dt [s] ending at the fraction ``a`` of its call's interval:
    half kick, drift of the free nodes, the fairlead nodes placed at (1 - a) x_start + a x_end
    (n_lines, 3) [m] with velocity v_fairlead [m/s], forces in the waves (1 - wave_a) wave0 + wave_a
    wave1 (written to ``wave``; (n, WAVE_FIELDS) each, (0, WAVE_FIELDS) in still water) and tangents
    at the new positions, half kick. Empty ``fairleads`` leave every end where it is."""
    n = x.shape[0]
    accelerate(v, force, mass, added_mass, tangent, kind, 0.5 * dt)
    for i in range(n):
        if kind[i] == FREE:
            for d in range(3):
                x[i, d] += dt * v[i, d]
    for j in range(fairleads.shape[0]):
        f = fairleads[j]
        for d in range(3):
            x[f, d] = (1.0 - a) * x_start[j, d] + a * x_end[j, d]
            v[f, d] = v_fairlead[j, d]
    blend_waves(wave0, wave1, wave_a, wave)
    node_forces(x, v, mass, prev, seg, props, constants, kind, water, current, seabed, wave, force, tension,
                added_mass, tangent)
    accelerate(v, force, mass, added_mass, tangent, kind, 0.5 * dt)


@njit(**JIT)
def advance_lines(x, v, mass, prev, seg, props, constants, kind, water, current, seabed, wave0, wave1, a0, a1, force,
                  tension, added_mass, tangent, fairleads, x_start, x_end, v_fairlead, dt, nsub):
    """nsub velocity-Verlet sub-steps of dt [s]; the fairlead nodes move linearly from x_start to
    x_end (n_lines, 3) [m] with velocity v_fairlead [m/s]; anchors stay fixed. The waves: wave0 and
    wave1 (n, WAVE_FIELDS) are the sea at the nodes at the two ends of an interval (``node_waves``)
    and this call runs from the fraction a0 of it to a1; sub-step k of nsub takes its forces in the
    sea interpolated linearly in time to its end, a0 + (k + 1) / nsub (a1 - a0) (docs/waves.md,
    Cost). Still water: (0, WAVE_FIELDS) arrays."""
    wave = np.empty((wave0.shape[0], WAVE_FIELDS))
    for k in range(nsub):
        a = (k + 1.0) / nsub
        verlet_substep(x, v, mass, prev, seg, props, constants, kind, water, current, seabed, wave0, wave1, wave,
                       a0 + a * (a1 - a0), force, tension, added_mass, tangent, fairleads, x_start, x_end,
                       v_fairlead, a, dt)


@njit(**JIT)
def relax_lines(x, v, mass, prev, seg, props, constants, kind, water, current, seabed, force, tension, added_mass,
                tangent, dt, max_steps, tol):
    """Static equilibrium by kinetic damping (dynamic relaxation): step the lines with fixed ends and
    zero every velocity whenever the kinetic energy has just peaked. Stops when the largest net force
    on a free node is below ``tol`` [N] or after max_steps. Returns the steps taken. In still water
    (a relaxation has no time)."""
    n = x.shape[0]
    no_fairleads = np.zeros(0, np.int64)
    no_points = np.zeros((0, 3))
    no_waves = np.zeros((0, WAVE_FIELDS))
    ke_prev = 0.0
    for step in range(max_steps):
        verlet_substep(x, v, mass, prev, seg, props, constants, kind, water, current, seabed, no_waves, no_waves,
                       no_waves, 1.0, force, tension, added_mass, tangent, no_fairleads, no_points, no_points,
                       no_points, 1.0, dt)
        ke = 0.0
        worst = 0.0
        for i in range(n):
            if kind[i] != FREE:
                continue
            ke += mass[i] * (v[i, 0] ** 2 + v[i, 1] ** 2 + v[i, 2] ** 2)
            f = math.sqrt(force[i, 0] ** 2 + force[i, 1] ** 2 + force[i, 2] ** 2)
            if f > worst:
                worst = f
        if ke < ke_prev:
            for i in range(n):
                v[i, 0] = v[i, 1] = v[i, 2] = 0.0
            ke = 0.0
        ke_prev = ke
        if worst < tol and step > 10:
            return step + 1
    return max_steps


@njit(**JIT)
def line_energies(x, v, mass, prev, seg, props, added_mass, tangent):
    """(kinetic [J], elastic [J]) of the node set.

    Kinetic: 1/2 m |v|^2 of every node plus 1/2 m_a |v_n|^2 of its added mass on the velocity
    normal to its tangent (the inertia ``accelerate`` integrates; added_mass and tangent as the
    last force evaluation left them). Elastic: 1/2 EA/l0 (l - l0)^2 of every taut bond (l > l0);
    a slack bond stores nothing, as it carries no tension in ``line_forces``.
    """
    kinetic = 0.0
    elastic = 0.0
    for i in range(x.shape[0]):
        v0, v1, v2 = v[i, 0], v[i, 1], v[i, 2]
        vt = v0 * tangent[i, 0] + v1 * tangent[i, 1] + v2 * tangent[i, 2]
        n0, n1, n2 = v0 - vt * tangent[i, 0], v1 - vt * tangent[i, 1], v2 - vt * tangent[i, 2]
        kinetic += 0.5 * mass[i] * (v0 * v0 + v1 * v1 + v2 * v2) + 0.5 * added_mass[i] * (n0 * n0 + n1 * n1 + n2 * n2)
        p = prev[i]
        if p < 0:
            continue
        el = props[seg[i]]
        l0 = el["l0"]
        d0 = x[i, 0] - x[p, 0]
        d1 = x[i, 1] - x[p, 1]
        d2 = x[i, 2] - x[p, 2]
        l = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
        if l > l0:
            elastic += 0.5 * el["ea"] / l0 * (l - l0) ** 2
    return kinetic, elastic


@njit(**JIT)
def node_force_norms(force, nodes):
    """(k,) |force[nodes[i]]| [N]: the tension at the fairleads or anchors, each step without numpy's
    per-call overhead (the peaks between series rows are tracked every step)."""
    out = np.empty(len(nodes))
    for k in range(len(nodes)):
        f = force[nodes[k]]
        out[k] = math.sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2])
    return out
