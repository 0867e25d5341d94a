"""Water on rigid floes (numba, arrays in and out): gravity, buoyancy of the submerged part of each
floe's polyhedron, heave/roll/pitch damping, current drag, and the waves' Froude-Krylov pressure
and particle velocity (issue 14; no added mass or diffraction yet).

With waves, a floe's buoyancy is that of its part below the surface at its centre, level + eta_c,
and the dynamic pressure less rho g eta_c acts on its wetted faces. A uniform pressure on the
wetted faces pushes up by itself times the water-plane area, so the two together are the linear
hydrostatic and Froude-Krylov loads for small motions, while a floe that rides a wave higher than
its freeboard keeps floating (cut at the still level, a 2 m wave would sink a 2.6 m floe of 0.27 m
freeboard in its troughs).

Per floe of mass m, centre x, velocity v, angular velocity w, water-plane area A_wp [m^2]:

- gravity -m g at x; buoyancy rho_w g V up at the centre of buoyancy, where V is the part of the
  polyhedron below the water level (kernels/polyhedra.clip);
- linear damping of heave, roll and pitch at ``damping_ratio`` of critical for the hydrostatic
  stiffnesses, rho_w g A_wp in heave and rho_w g A_wp r^2 in roll and pitch with r^2 = I / m
  (standing for the radiation damping the seed takes from WAMIT; an assumption, like the level
  ice's heave damping ratio);
- skin drag of the current on the bottom, rho_w C_w A_wp |u| u, and form drag on the submerged
  side, 1/2 rho_w C_d draft b |u| u, b the floe's width across u, with u the current relative to
  the floe's horizontal velocity (seed 003 Eq. 12 for the form drag; the skin drag as the level ice).
"""

import math

import numpy as np
from numba import njit

from . import JIT
from .polyhedra import clip, volume_centroid
from .waves import sea_elevation, sea_kinematics


@njit(**JIT)
def wave_pressure_load(sp, sc, side, x, amp, omega, k, direction, phase, depth, g, rho_w, t, p0):
    """(force (3,) [N], moment about x (3,) [N m]) of the undisturbed waves' dynamic pressure less p0
    [Pa] on the wetted faces (side 0) of a floe's submerged part: -(p - p0) A n at each face's
    centroid (Froude-Krylov; a floe is small against the waves, seed 003 Eq. 11)."""
    f = np.zeros(3)
    m = np.zeros(3)
    pt = np.empty((1, 3))
    for face in range(sc.shape[0]):
        if sc[face] < 3 or side[face] != 0:
            continue
        c = np.zeros(3)
        s = np.zeros(3)
        for i in range(sc[face]):
            c += sp[face, i]
        c /= sc[face]
        for i in range(1, sc[face] - 1):
            a = sp[face, i] - sp[face, 0]
            b = sp[face, i + 1] - sp[face, 0]
            s += 0.5 * np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])
        pt[0] = c
        _, _, p = sea_kinematics(amp, omega, k, direction, phase, depth, g, rho_w, pt, t)
        df = -(p[0] - p0) * s
        f += df
        r = c - x
        m += np.array([r[1] * df[2] - r[2] * df[1], r[2] * df[0] - r[0] * df[2], r[0] * df[1] - r[1] * df[0]])
    return f, m


@njit(**JIT)
def floe_water(lo, hi, x, v, omega, rot, mass, inertia, area, pts, counts, level, rho_w, g, current, skin, form,
               damping_ratio, sea_amp, sea_omega, sea_k, sea_direction, sea_phase, sea_depth, t, added, force, torque):
    """Add the water's forces [N] and torques about each centre [N m] to the floes lo..hi-1; returns the
    total submerged volume [m^3]. omega (n, 3) [rad/s] and the torques in space; rot (n, 3, 3) each
    floe's attitude (body to space, its principal axes); pts, counts: world polyhedra; area:
    water-plane areas [m^2]; inertia (n, 3) principal moments [kg m^2]; current (2,) [m/s]; skin
    C_w, form C_d [-]; sea_*: the waves' components (physics/waves.Sea; none: still water) at time
    t [s], whose dynamic pressure acts on the wetted faces and whose particle velocity at the
    floe's centre adds to the current in the drag. With waves, ``added`` (n, 3) [kg]: each floe's
    added mass along x, y, z, times the waves' acceleration at its centre of buoyancy (seed 003 Eq. 11's
    diffraction force on a small body).
    """
    up = np.array([0.0, 0.0, 1.0])
    total = 0.0
    for i in range(lo, hi):
        side = np.zeros(counts.shape[1], np.int64)
        # with waves the floe floats on the surface where it is: its buoyancy is cut at level + eta there,
        # and the dynamic pressure less rho g eta acts on its wetted faces (module docstring)
        eta = 0.0
        if sea_amp.shape[0] > 0:
            eta = sea_elevation(sea_amp, sea_omega, sea_k, sea_direction, sea_phase, x[i, 0:1], x[i, 1:2], t)[0]
        sp, sc, sides = clip(pts[i], counts[i], side, up, level + eta, 1)
        vol, cob = volume_centroid(sp, sc)
        force[i, 2] -= mass[i] * g
        if vol <= 0.0:
            continue
        total += vol
        fb = rho_w * g * vol
        force[i, 2] += fb
        torque[i, 0] += (cob[1] - x[i, 1]) * fb
        torque[i, 1] -= (cob[0] - x[i, 0]) * fb
        # heave, roll and pitch damping
        k_heave = rho_w * g * area[i]
        force[i, 2] -= damping_ratio * 2.0 * math.sqrt(k_heave * mass[i]) * v[i, 2]
        R = rot[i]
        for a in range(2):  # about the principal axes: roll and pitch are the first two (scalars: no BLAS)
            wb = R[0, a] * omega[i, 0] + R[1, a] * omega[i, 1] + R[2, a] * omega[i, 2]
            k_tilt = k_heave * inertia[i, a] / mass[i]
            tb = -damping_ratio * 2.0 * math.sqrt(k_tilt * inertia[i, a]) * wb
            for e in range(3):
                torque[i, e] += R[e, a] * tb
        flow0, flow1 = current[0], current[1]
        if sea_amp.shape[0] > 0:
            fw, mw = wave_pressure_load(sp, sc, sides, x[i], sea_amp, sea_omega, sea_k, sea_direction, sea_phase,
                                        sea_depth, g, rho_w, t, rho_w * g * eta)
            force[i] += fw
            torque[i] += mw
            centre = np.empty((1, 3))
            centre[0] = cob
            uw, aw, _ = sea_kinematics(sea_amp, sea_omega, sea_k, sea_direction, sea_phase, sea_depth, g, rho_w,
                                       centre, t)
            flow0 += uw[0, 0]
            flow1 += uw[0, 1]
            for e in range(3):  # the diffraction term of seed 003 Eq. 11: added mass times the waves' acceleration
                force[i, e] += added[i, e] * aw[0, e]
        # drag of the current (and the waves' particle velocity): skin on the bottom, form on the side
        u0, u1 = flow0 - v[i, 0], flow1 - v[i, 1]
        speed = math.sqrt(u0 * u0 + u1 * u1)
        if speed == 0.0:
            continue
        lo, hi, zmin = math.inf, -math.inf, math.inf
        e0, e1 = -u1 / speed, u0 / speed  # across the flow
        for f in range(sc.shape[0]):
            for k in range(sc[f]):
                s = sp[f, k, 0] * e0 + sp[f, k, 1] * e1
                lo, hi = min(lo, s), max(hi, s)
                zmin = min(zmin, sp[f, k, 2])
        drag = rho_w * (skin * area[i] + 0.5 * form * (level - zmin) * (hi - lo)) * speed
        force[i, 0] += drag * u0
        force[i, 1] += drag * u1
    return total
