"""Submerged volume and centre of buoyancy of a closed triangle mesh (Eq. 12 of Zhu & Ji 2022).

Each triangle (in space coordinates) is clipped at the water plane z = level and the part below
is fanned into triangles; each forms a tetrahedron with a reference point ON the water plane, whose
signed volume is (1/6) (a - p) . ((b - p) x (c - p)) (Eq. 12). The missing lid of the clipped mesh
lies in the water plane, so its tetrahedra have zero volume: the sum over the clipped triangles is
the exact submerged volume of the closed mesh, and the volume-weighted tetrahedron centroids give
the centre of buoyancy. Outward normals (counter-clockwise seen from outside) give positive volume.
"""

import numpy as np
from numba import njit

from . import JIT


@njit(**JIT)
def _accumulate(p, a, b, c, acc):
    """Add the tetrahedron (p, a, b, c): acc[0] += V, acc[1:4] += V * centroid."""
    ax, ay, az = a[0] - p[0], a[1] - p[1], a[2] - p[2]
    bx, by, bz = b[0] - p[0], b[1] - p[1], b[2] - p[2]
    cx, cy, cz = c[0] - p[0], c[1] - p[1], c[2] - p[2]
    vol = (ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx)) / 6.0
    acc[0] += vol
    for k in range(3):
        acc[1 + k] += vol * 0.25 * (p[k] + a[k] + b[k] + c[k])


@njit(**JIT)
def submerged_volume(vertices, triangles, level):
    """(volume [m^3], centre of buoyancy (3,) [m]) of the part of a closed mesh below z = level.

    vertices: (nv, 3) space coordinates [m]; triangles: (nt, 3) vertex indices, outward orientation.
    The centre is NaN when nothing is submerged.
    """
    acc = np.zeros(4)
    # reference point on the water plane, above the mesh's mean position (keeps tetrahedra small)
    p = np.zeros(3)
    for k in range(2):
        p[k] = vertices[:, k].mean()
    p[2] = level
    poly = np.empty((4, 3))
    for t in range(triangles.shape[0]):
        corners = vertices[triangles[t]]
        npoly = 0
        for e in range(3):  # Sutherland-Hodgman against the half-space z <= level
            a = corners[e]
            b = corners[(e + 1) % 3]
            a_in = a[2] <= level
            b_in = b[2] <= level
            if a_in:
                poly[npoly] = a
                npoly += 1
            if a_in != b_in:
                s = (level - a[2]) / (b[2] - a[2])
                poly[npoly] = a + s * (b - a)
                poly[npoly, 2] = level
                npoly += 1
        for k in range(1, npoly - 1):
            _accumulate(p, poly[0], poly[k], poly[k + 1], acc)
    if acc[0] == 0.0:
        return 0.0, np.full(3, np.nan)
    return acc[0], acc[1:] / acc[0]


@njit(**JIT)
def transform(vertices_body, q_matrix, position):
    """Body-frame vertices -> space frame: x = R x_B + position."""
    out = np.empty_like(vertices_body)
    for i in range(vertices_body.shape[0]):
        for k in range(3):
            out[i, k] = (q_matrix[k, 0] * vertices_body[i, 0] + q_matrix[k, 1] * vertices_body[i, 1]
                         + q_matrix[k, 2] * vertices_body[i, 2] + position[k])
    return out
