"""Small geometry shared by the kernels: closest point on a triangle, quaternion algebra, points in
oriented boxes.

Quaternions are (w, x, y, z); a unit quaternion q takes body-frame vectors to the space frame.
"""

import math

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


@njit(**JIT)
def points_in_boxes(points, centres, attitudes, half):
    """Which of ``points`` (n x 3) [m] lie inside any of the oriented boxes, each of half-sizes
    ``half`` (m x 3) [m] in its own frame, centred at ``centres`` (m x 3) [m] and turned by the
    quaternions ``attitudes`` (m x 4): a bool per point. The points are binned on a grid of the
    largest box's half-diagonal (coarser where the points are sparse, so the grid holds at most about
    8 n cells), so each box tests only the points near it (O(n + m), not O(n m))."""
    n, m = points.shape[0], centres.shape[0]
    inside = np.zeros(n, dtype=np.bool_)
    if n == 0 or m == 0:
        return inside
    reach = np.sqrt(half[:, 0] ** 2 + half[:, 1] ** 2 + half[:, 2] ** 2)
    h = max(reach.max(), 1e-9)
    lo = np.empty(3)
    span = np.empty(3)
    for a in range(3):
        lo[a] = points[:, a].min()
        span[a] = points[:, a].max() - lo[a]
    while (span[0] / h + 1.0) * (span[1] / h + 1.0) * (span[2] / h + 1.0) > 8.0 * n + 1000.0:
        h *= 2.0  # sparse points over a wide region: coarser cells, so the grid stays O(n)
    dims = np.empty(3, dtype=np.int64)
    for a in range(3):
        dims[a] = int(span[a] / h) + 1
    cell = np.empty(n, dtype=np.int64)
    for i in range(n):
        ix = int((points[i, 0] - lo[0]) / h)
        iy = int((points[i, 1] - lo[1]) / h)
        iz = int((points[i, 2] - lo[2]) / h)
        cell[i] = (ix * dims[1] + iy) * dims[2] + iz
    order = np.argsort(cell)
    start = np.zeros(dims[0] * dims[1] * dims[2] + 1, dtype=np.int64)
    for i in range(n):
        start[cell[i] + 1] += 1
    for c in range(dims[0] * dims[1] * dims[2]):
        start[c + 1] += start[c]
    for k in range(m):
        c = centres[k]
        r = reach[k]
        rot = rotation_matrix(attitudes[k])
        lo_c = np.empty(3, dtype=np.int64)
        hi_c = np.empty(3, dtype=np.int64)
        for a in range(3):
            lo_c[a] = max(int(math.floor((c[a] - r - lo[a]) / h)), 0)
            hi_c[a] = min(int(math.floor((c[a] + r - lo[a]) / h)), dims[a] - 1)
        for ix in range(lo_c[0], hi_c[0] + 1):
            for iy in range(lo_c[1], hi_c[1] + 1):
                for iz in range(lo_c[2], hi_c[2] + 1):
                    q = (ix * dims[1] + iy) * dims[2] + iz
                    for s in range(start[q], start[q + 1]):
                        i = order[s]
                        if inside[i]:
                            continue
                        d0 = points[i, 0] - c[0]
                        d1 = points[i, 1] - c[1]
                        d2 = points[i, 2] - c[2]
                        if abs(d0) > r or abs(d1) > r or abs(d2) > r:
                            continue
                        ok = True
                        for j in range(3):  # (p - c) . R[:, j]: into the block's frame
                            if abs(d0 * rot[0, j] + d1 * rot[1, j] + d2 * rot[2, j]) > half[k, j]:
                                ok = False
                                break
                        if ok:
                            inside[i] = True
    return inside
