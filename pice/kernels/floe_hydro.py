"""Water on rigid floes (numba, arrays in and out): gravity, buoyancy of the submerged part of each
floe's polyhedron, heave/roll/pitch damping, and current drag (issue 14; waves are to come).

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


@njit(**JIT)
def floe_water(n, x, v, omega, rot, mass, inertia, area, pts, counts, level, rho_w, g, current, skin, form,
               damping_ratio, force, torque):
    """Add the water's forces [N] and torques about each centre [N m] to the n floes; returns the
    total submerged volume [m^3]. omega (n, 3) [rad/s] and the torques in space; rot (n, 3, 3) each
    floe's attitude (body to space, its principal axes); pts, counts: world polyhedra; area:
    water-plane areas [m^2]; inertia (n, 3) principal moments [kg m^2]; current (2,) [m/s]; skin
    C_w, form C_d [-]."""
    up = np.array([0.0, 0.0, 1.0])
    total = 0.0
    for i in range(n):
        side = np.zeros(counts.shape[1], np.int64)
        sp, sc, _ = clip(pts[i], counts[i], side, up, level, 1)
        vol, cob = volume_centroid(sp, sc)
        force[i, 2] -= mass[i] * g
        if vol <= 0.0:
            continue
        total += vol
        fb = rho_w * g * vol
        force[i, 2] += fb
        arm = cob - x[i]
        torque[i, 0] += arm[1] * fb
        torque[i, 1] -= arm[0] * fb
        # heave, roll and pitch damping
        k_heave = rho_w * g * area[i]
        force[i, 2] -= damping_ratio * 2.0 * math.sqrt(k_heave * mass[i]) * v[i, 2]
        wb = rot[i].T @ omega[i]  # about the principal axes: roll and pitch are the first two
        tb = np.zeros(3)
        for a in range(2):
            k_tilt = k_heave * inertia[i, a] / mass[i]
            tb[a] = -damping_ratio * 2.0 * math.sqrt(k_tilt * inertia[i, a]) * wb[a]
        torque[i] += rot[i] @ tb
        # current drag: skin on the bottom, form on the submerged side
        u0, u1 = current[0] - v[i, 0], current[1] - v[i, 1]
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
