"""Small geometry shared by the kernels: closest point on a triangle, quaternion algebra.

Quaternions are (w, x, y, z); a unit quaternion q takes body-frame vectors to the space frame.
"""

import numpy as np
from numba import njit

from . import JIT


@njit(**JIT)
def closest_point_on_triangle(p, a, b, c, out):
    """Closest point to p on triangle abc, written into ``out`` (Ericson, Real-Time Collision
    Detection, 5.1.5). All points (3,) [m]."""
    ab = b - a
    ac = c - a
    ap = p - a
    d1 = ab @ ap
    d2 = ac @ ap
    if d1 <= 0.0 and d2 <= 0.0:
        out[:] = a
        return
    bp = p - b
    d3 = ab @ bp
    d4 = ac @ bp
    if d3 >= 0.0 and d4 <= d3:
        out[:] = b
        return
    vc = d1 * d4 - d3 * d2
    if vc <= 0.0 and d1 >= 0.0 and d3 <= 0.0:
        out[:] = a + (d1 / (d1 - d3)) * ab
        return
    cp = p - c
    d5 = ab @ cp
    d6 = ac @ cp
    if d6 >= 0.0 and d5 <= d6:
        out[:] = c
        return
    vb = d5 * d2 - d1 * d6
    if vb <= 0.0 and d2 >= 0.0 and d6 <= 0.0:
        out[:] = a + (d2 / (d2 - d6)) * ac
        return
    va = d3 * d6 - d5 * d4
    if va <= 0.0 and (d4 - d3) >= 0.0 and (d5 - d6) >= 0.0:
        out[:] = b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b)
        return
    denom = 1.0 / (va + vb + vc)
    out[:] = a + ab * (vb * denom) + ac * (vc * denom)


@njit(**JIT)
def quat_mul(a, b):
    """Hamilton product a b of quaternions (w, x, y, z)."""
    return np.array([
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    ])


@njit(**JIT)
def rotation_matrix(q):
    """3 x 3 matrix R(q) taking body-frame vectors to the space frame (q need not be normalised)."""
    w, x, y, z = q[0], q[1], q[2], q[3]
    s = 2.0 / (w * w + x * x + y * y + z * z)
    return np.array([
        [1.0 - s * (y * y + z * z), s * (x * y - w * z), s * (x * z + w * y)],
        [s * (x * y + w * z), 1.0 - s * (x * x + z * z), s * (y * z - w * x)],
        [s * (x * z - w * y), s * (y * z + w * x), 1.0 - s * (x * x + y * y)],
    ])
