"""Contact of spheres with fixed rigid walls: infinite planes and triangles, with friction.

geometry (n_walls, 9): plane = (point, unit normal, -); triangle = (v0, v1, v2)
kinds (n_walls,): PLANE or TRIANGLE.  params (n_walls,): records of the contact law
(physics.contact.CONTACT_LAW_RECORD: kn [N/m], kt [N/m], zeta, mu), one per wall.
A plane pushes along its normal on the side the normal points to (a half-space wall); a triangle
pushes away from its closest point, on both sides.
"""

import math

import numpy as np
from numba import njit

from . import JIT
from .contact_law import contact_energy, contact_height, crushing_cap, plastic_normal_force, tangential_force
from .geometry import closest_point_on_triangle

PLANE = 0     # an infinite plane: geometry = (point, unit normal, -)
TRIANGLE = 1  # geometry = (v0, v1, v2)


@njit(**JIT)
def wall_forces(nlocal, x, v, w, radius, mass, cell_area, half_height, kinds, geometry, params, hist, dt, force,
                torque, wall_force, wall_moment):
    """Add wall contact forces to owned particles; accumulate the reaction on each wall [N] and its
    moment about the origin [N m] (the reaction acts at the sphere's contact point).

    hist: (n, n_walls, 4) per particle and wall: tangential force [N] and plastic penetration [m]
    (crushing), reset when the contact ends. The contact area for crushing is the chord of the
    sphere's section by the wall, 2 sqrt(2 r delta - delta^2) (2 r once delta >= r), times the
    element's contact height. Returns (elastic energy in wall contacts [J], contacts in plastic flow).
    """
    nw = kinds.shape[0]
    p = np.empty(3)
    q = np.empty(3)
    n = np.empty(3)
    energy = 0.0
    ncrushing = 0
    for i in range(nlocal):
        for k in range(3):
            p[k] = x[i, k]
        r = radius[i]
        for wi in range(nw):
            g = geometry[wi]
            if kinds[wi] == PLANE:
                dist = (p[0] - g[0]) * g[3] + (p[1] - g[1]) * g[4] + (p[2] - g[2]) * g[5]
                if dist >= r:
                    hist[i, wi, :] = 0.0
                    continue
                n[0], n[1], n[2] = g[3], g[4], g[5]
            else:
                closest_point_on_triangle(p, g[0:3], g[3:6], g[6:9], q)
                d0, d1, d2 = p[0] - q[0], p[1] - q[1], p[2] - q[2]
                dist = math.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
                if dist >= r or dist == 0.0:
                    hist[i, wi, :] = 0.0
                    continue
                n[0], n[1], n[2] = d0 / dist, d1 / dist, d2 / dist
            delta = r - dist
            law = params[wi]  # a record: fields by name (law["kn"] works with and without JIT)
            kn, kt, zeta, mu = law["kn"], law["kt"], law["zeta"], law["mu"]
            cap = crushing_cap(law["crushing_pressure"], 2.0 * r * delta - delta * delta if delta < r else r * r,
                               contact_height(r, cell_area[i], half_height[i]))
            # velocity of the sphere's contact point (the wall is at rest)
            c0 = -r * n[0]
            c1 = -r * n[1]
            c2 = -r * n[2]
            vc0 = v[i, 0] + w[i, 1] * c2 - w[i, 2] * c1
            vc1 = v[i, 1] + w[i, 2] * c0 - w[i, 0] * c2
            vc2 = v[i, 2] + w[i, 0] * c1 - w[i, 1] * c0
            vn = vc0 * n[0] + vc1 * n[1] + vc2 * n[2]
            ft = hist[i, wi]
            dp0 = ft[3]
            fn, ft[3] = plastic_normal_force(kn, zeta, mass[i], delta, dp0, vn, cap)
            ncrushing += 1 if ft[3] > dp0 else 0
            ft[0], ft[1], ft[2], ftm = tangential_force(ft[0], ft[1], ft[2], n[0], n[1], n[2], vc0, vc1, vc2, vn,
                                                        kt, dt, mu * fn)
            f0 = fn * n[0] + ft[0]
            f1 = fn * n[1] + ft[1]
            f2 = fn * n[2] + ft[2]
            force[i, 0] += f0
            force[i, 1] += f1
            force[i, 2] += f2
            torque[i, 0] += c1 * f2 - c2 * f1
            torque[i, 1] += c2 * f0 - c0 * f2
            torque[i, 2] += c0 * f1 - c1 * f0
            wall_force[wi, 0] -= f0
            wall_force[wi, 1] -= f1
            wall_force[wi, 2] -= f2
            q0, q1, q2 = p[0] + c0, p[1] + c1, p[2] + c2
            wall_moment[wi, 0] -= q1 * f2 - q2 * f1
            wall_moment[wi, 1] -= q2 * f0 - q0 * f2
            wall_moment[wi, 2] -= q0 * f1 - q1 * f0
            energy += contact_energy(kn, kt, delta - ft[3], ftm)
    return energy, ncrushing
