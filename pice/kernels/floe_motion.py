"""Rigid floes' kinematics in one call each (numba, arrays in and out): their polyhedra in space,
their rotations, angular velocities and free rotation over a step (platform/rigid_body.py's exact
splitting, floe by floe)."""

import numpy as np
from numba import njit

from ..platform.rigid_body import angular_velocity, free_rotation
from . import JIT
from .geometry import rotation_matrix


@njit(**JIT)
def world_polyhedra(body_pts, counts, x, q):
    """(n, F, V, 3) face points in space [m] of the n floes' body-frame polyhedra at poses x, q."""
    out = np.empty_like(body_pts)  # only the first counts[k, f] points of a face are ever read
    for k in range(body_pts.shape[0]):
        R = rotation_matrix(q[k])
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
        out[k] = rotation_matrix(q[k])
    return out


@njit(**JIT)
def floe_omegas(q, L, inertia):
    """(n, 3) angular velocities [rad/s] in space from the angular momenta L and principal moments."""
    out = np.empty((q.shape[0], 3))
    for k in range(q.shape[0]):
        out[k] = angular_velocity(q[k], L[k], inertia[k])
    return out


@njit(**JIT)
def turn_all(q, L, inertia, dt):
    """Each attitude turned by the exact free rotation over dt [s] (in place)."""
    for k in range(q.shape[0]):
        q[k] = free_rotation(q[k], L[k], inertia[k], dt)
