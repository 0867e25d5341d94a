"""Velocity Verlet for translation and rotation of spheres, with prescribed velocity components."""

import math

from numba import njit

from . import JIT


@njit(**JIT)
def kick(nlocal, v, w, force, torque, ext_force, mass, inertia, fix_mask, fix_velocity, half_dt):
    """v += (F + F_ext)/m * half_dt, w += T/I * half_dt; prescribed components are set, not integrated."""
    for i in range(nlocal):
        im = half_dt / mass[i]
        ii = half_dt / inertia[i]
        for k in range(3):
            if fix_mask[i, k]:
                v[i, k] = fix_velocity[i, k]
            else:
                v[i, k] += (force[i, k] + ext_force[i, k]) * im
            w[i, k] += torque[i, k] * ii


@njit(**JIT)
def drift(nlocal, x, v, dt):
    """x += v dt."""
    for i in range(nlocal):
        for k in range(3):
            x[i, k] += v[i, k] * dt


@njit(**JIT)
def max_step_displacement(nlocal, v, w, radius, dt):
    """(largest |v| dt / r, its index, any non-finite velocity) over owned particles."""
    worst = 0.0
    at = -1
    for i in range(nlocal):
        s2 = v[i, 0] * v[i, 0] + v[i, 1] * v[i, 1] + v[i, 2] * v[i, 2]
        o2 = w[i, 0] * w[i, 0] + w[i, 1] * w[i, 1] + w[i, 2] * w[i, 2]
        if not (math.isfinite(s2) and math.isfinite(o2)):
            return math.inf, i, True
        ratio = (math.sqrt(s2) + math.sqrt(o2) * radius[i]) * dt / radius[i]
        if ratio > worst:
            worst = ratio
            at = i
    return worst, at, False
