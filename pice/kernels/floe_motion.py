"""Rigid floes' kinematics in one call each (numba, arrays in and out, scalar arithmetic: no small
temporaries or 3 x 3 BLAS products per floe): their polyhedra in space, their rotations, angular
velocities and free rotation over a step (the exact splitting of platform/rigid_body.py's
``free_rotation``: about the principal axes 0, 1, 2, 1, 0 for h, h, dt, h, h with h = dt / 2)."""

import math

import numpy as np
from numba import njit

from . import JIT


@njit(**JIT)
def _matrix(q, R):
    """Write the rotation matrix (body to space) of the quaternion q (w, x, y, z; not necessarily
    unit) into R (3, 3)."""
    w, x, y, z = q[0], q[1], q[2], q[3]
    s = 2.0 / (w * w + x * x + y * y + z * z)
    R[0, 0], R[0, 1], R[0, 2] = 1.0 - s * (y * y + z * z), s * (x * y - w * z), s * (x * z + w * y)
    R[1, 0], R[1, 1], R[1, 2] = s * (x * y + w * z), 1.0 - s * (x * x + z * z), s * (y * z - w * x)
    R[2, 0], R[2, 1], R[2, 2] = s * (x * z - w * y), s * (y * z + w * x), 1.0 - s * (x * x + y * y)


@njit(**JIT)
def world_polyhedra(body_pts, counts, x, q):
    """(n, F, V, 3) face points in space [m] of the n floes' body-frame polyhedra at poses x, q."""
    out = np.empty_like(body_pts)  # only the first counts[k, f] points of a face are ever read
    R = np.empty((3, 3))
    for k in range(body_pts.shape[0]):
        _matrix(q[k], R)
        for f in range(counts.shape[1]):
            for i in range(counts[k, f]):
                p = body_pts[k, f, i]
                for a in range(3):
                    out[k, f, i, a] = R[a, 0] * p[0] + R[a, 1] * p[1] + R[a, 2] * p[2] + x[k, a]
    return out


@njit(**JIT)
def floe_rotations(q):
    """(n, 3, 3) body-to-space rotations of the attitudes q (n, 4)."""
    out = np.empty((q.shape[0], 3, 3))
    for k in range(q.shape[0]):
        _matrix(q[k], out[k])
    return out


@njit(**JIT)
def floe_omegas(q, L, inertia):
    """(n, 3) angular velocities [rad/s] in space, w = R I^-1 R^T L, from the angular momenta L (n, 3)
    [kg m^2/s] in space and the principal moments (n, 3) [kg m^2]."""
    out = np.empty((q.shape[0], 3))
    R = np.empty((3, 3))
    for k in range(q.shape[0]):
        _matrix(q[k], R)
        b0 = (R[0, 0] * L[k, 0] + R[1, 0] * L[k, 1] + R[2, 0] * L[k, 2]) / inertia[k, 0]
        b1 = (R[0, 1] * L[k, 0] + R[1, 1] * L[k, 1] + R[2, 1] * L[k, 2]) / inertia[k, 1]
        b2 = (R[0, 2] * L[k, 0] + R[1, 2] * L[k, 1] + R[2, 2] * L[k, 2]) / inertia[k, 2]
        for a in range(3):
            out[k, a] = R[a, 0] * b0 + R[a, 1] * b1 + R[a, 2] * b2
    return out


@njit(**JIT)
def turn_all(q, L, inertia, dt):
    """Each attitude q (n, 4) turned in place by the exact free rotation over dt [s] with its space-frame
    angular momentum L (n, 3) fixed (principal moments inertia (n, 3)): five exact rotations about the
    body axes (module docstring), then normalised."""
    R = np.empty((3, 3))
    lb = np.empty(3)
    h = 0.5 * dt
    for k in range(q.shape[0]):
        _matrix(q[k], R)
        for a in range(3):  # L in the body frame
            lb[a] = R[0, a] * L[k, 0] + R[1, a] * L[k, 1] + R[2, a] * L[k, 2]
        w, x, y, z = q[k, 0], q[k, 1], q[k, 2], q[k, 3]
        for axis, tau in ((0, h), (1, h), (2, dt), (1, h), (0, h)):
            angle = tau * lb[axis] / inertia[k, axis]
            c, s = math.cos(0.5 * angle), math.sin(0.5 * angle)
            # q <- q (c, s e_axis): the body turns about its own axis
            if axis == 0:
                w, x, y, z = w * c - x * s, w * s + x * c, y * c + z * s, z * c - y * s
            elif axis == 1:
                w, x, y, z = w * c - y * s, x * c - z * s, w * s + y * c, z * c + x * s
            else:
                w, x, y, z = w * c - z * s, x * c + y * s, y * c - x * s, w * s + z * c
            # in the body frame the angular momentum turns the opposite way
            j, m = (axis + 1) % 3, (axis + 2) % 3
            ca, sa = math.cos(angle), math.sin(angle)
            lj, lm = lb[j], lb[m]
            lb[j] = ca * lj + sa * lm
            lb[m] = -sa * lj + ca * lm
        norm = math.sqrt(w * w + x * x + y * y + z * z)
        q[k, 0], q[k, 1], q[k, 2], q[k, 3] = w / norm, x / norm, y / norm, z / norm
