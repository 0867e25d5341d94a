"""Linear wave kinematics (numba, arrays in and out): the sums over a sea's components that
physics/waves.py describes (elevation, velocity, acceleration, dynamic pressure)."""

import math

import numpy as np
from numba import njit

from . import JIT


@njit(**JIT)
def sea_elevation(amp, omega, k, direction, phase, x, y, t):
    """eta [m] at each (x[i], y[i]) [m] at time t [s]: the sum over the components."""
    out = np.zeros(x.shape[0])
    for i in range(x.shape[0]):
        e = 0.0
        for j in range(amp.shape[0]):
            e += amp[j] * math.cos(k[j] * (x[i] * direction[j, 0] + y[i] * direction[j, 1]) - omega[j] * t + phase[j])
        out[i] = e
    return out


@njit(**JIT)
def depth_factors(k, z, depth):
    """(C, S, K) of the module docstring at height z [m] (<= 0) in water of depth [m] (inf: deep)."""
    if not math.isfinite(depth):
        e = math.exp(k * z)
        return e, e, e
    ez = math.exp(k * z)
    e2 = math.exp(-k * (z + 2.0 * depth))   # e^(-k (z + 2h))
    eh = math.exp(-2.0 * k * depth)          # e^(-2kh)
    return (ez + e2) / (1.0 - eh), (ez - e2) / (1.0 - eh), (ez + e2) / (1.0 + eh)


@njit(**JIT)
def sea_kinematics(amp, omega, k, direction, phase, depth, g, rho, points, t):
    """Velocity (n, 3), acceleration (n, 3) and dynamic pressure (n,) of the sea at points (n, 3) [m]
    at time t [s]; z is clipped to [-depth, 0] (module docstring)."""
    n = points.shape[0]
    vel = np.zeros((n, 3))
    acc = np.zeros((n, 3))
    pres = np.zeros(n)
    for i in range(n):
        z = min(points[i, 2], 0.0)
        if math.isfinite(depth) and z < -depth:
            z = -depth
        for j in range(amp.shape[0]):
            c, s, kk = depth_factors(k[j], z, depth)
            theta = k[j] * (points[i, 0] * direction[j, 0] + points[i, 1] * direction[j, 1]) - omega[j] * t + phase[j]
            ct, st = math.cos(theta), math.sin(theta)
            aw, aw2 = amp[j] * omega[j], amp[j] * omega[j] * omega[j]
            uh, ah = aw * c * ct, aw2 * c * st
            vel[i, 0] += uh * direction[j, 0]
            vel[i, 1] += uh * direction[j, 1]
            vel[i, 2] += aw * s * st
            acc[i, 0] += ah * direction[j, 0]
            acc[i, 1] += ah * direction[j, 1]
            acc[i, 2] -= aw2 * s * ct
            pres[i] += rho * g * amp[j] * kk * ct
    return vel, acc, pres


@njit(**JIT)
def sea_point(amp, omega, k, direction, phase, depth, g, rho, x, y, z, t):
    """Everything the sea gives at one point (x, y, z) [m] (z up from the still level, clipped to
    [-depth, 0] for the kinematics) at time t [s], without allocating: (eta [m], u_x, u_y, u_z
    [m/s], a_x, a_y, a_z [m/s^2], dynamic pressure [Pa]), eta taken at (x, y). The same sums as
    ``sea_elevation`` and ``sea_kinematics``, for kernels that visit points one by one."""
    zc = min(z, 0.0)
    if math.isfinite(depth) and zc < -depth:
        zc = -depth
    eta = u0 = u1 = u2 = a0 = a1 = a2 = p = 0.0
    for j in range(amp.shape[0]):
        c, s, kk = depth_factors(k[j], zc, depth)
        theta = k[j] * (x * direction[j, 0] + y * direction[j, 1]) - omega[j] * t + phase[j]
        ct, st = math.cos(theta), math.sin(theta)
        aw, aw2 = amp[j] * omega[j], amp[j] * omega[j] * omega[j]
        uh, ah = aw * c * ct, aw2 * c * st
        eta += amp[j] * ct
        u0 += uh * direction[j, 0]
        u1 += uh * direction[j, 1]
        u2 += aw * s * st
        a0 += ah * direction[j, 0]
        a1 += ah * direction[j, 1]
        a2 -= aw2 * s * ct
        p += rho * g * amp[j] * kk * ct
    return eta, u0, u1, u2, a0, a1, a2, p
