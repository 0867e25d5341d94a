"""Hull meshes: closed, outward-oriented triangle meshes in the body frame (origin at the CG).

Built from parameters (boxes, the semi-submersible of Zhu & Ji 2022) or read with meshio. Parts
of a hull are separate closed meshes that touch without overlapping, so the submerged volumes of
the parts add up (kernels.hull) and the contact sees their outer faces.
"""

from __future__ import annotations

import math

import numpy as np


def box(lx: float, ly: float, lz: float, centre=(0.0, 0.0, 0.0)) -> tuple[np.ndarray, np.ndarray]:
    """A closed box mesh (8 vertices, 12 outward triangles)."""
    c = np.asarray(centre, float)
    v = np.array([[sx * lx / 2, sy * ly / 2, sz * lz / 2] for sz in (-1, 1) for sy in (-1, 1) for sx in (-1, 1)]) + c
    # vertex k = ix + 2 iy + 4 iz
    faces = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    tris = []
    for a, b, cc, d in faces:
        tris += [(a, b, cc), (a, cc, d)]
    return v, np.asarray(tris, np.int64)


def sloped_block(lx_bottom: float, lx_top: float, ly: float, z0: float, z1: float,
                 centre_xy=(0.0, 0.0)) -> tuple[np.ndarray, np.ndarray]:
    """A block whose +x and -x faces lean outwards from z0 (length lx_bottom) to z1 (length lx_top):
    an ice-resistant slope at bow and stern. y faces are vertical."""
    cx, cy = centre_xy
    v = []
    for z, lx in ((z0, lx_bottom), (z1, lx_top)):
        for sy in (-1, 1):
            for sx in (-1, 1):
                v.append([cx + sx * lx / 2, cy + sy * ly / 2, z])
    v = np.asarray(v, float)
    faces = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    tris = []
    for a, b, c, d in faces:
        tris += [(a, b, c), (a, c, d)]
    return v, np.asarray(tris, np.int64)


def merge(parts) -> tuple[np.ndarray, np.ndarray]:
    """One vertex/triangle set from several closed parts."""
    verts, tris, off = [], [], 0
    for v, t in parts:
        verts.append(v)
        tris.append(t + off)
        off += len(v)
    return np.vstack(verts), np.vstack(tris)


def semi_submersible(*, length: float = 86.2, width: float = 64.6, draft: float = 14.0,
                     pontoon_width: float = 14.0, pontoon_height: float = 8.0, column: float = 17.72,
                     freeboard: float = 12.0, slope_deg: float = 10.0, cg_above_keel: float = 8.9):
    """The moored semi-submersible of Zhu & Ji (2022), Table 3, as far as the paper describes it.

    Assumptions where the paper gives no drawing (docs/semi_submersible.md): a ring pontoon of
    ``pontoon_width`` x ``pontoon_height`` around the 86.2 m x 64.6 m footprint, four square corner
    columns of side ``column`` from the pontoon to ``freeboard`` above the still waterline, whose
    bow (+x) and stern (-x) faces lean out at ``slope_deg`` from the vertical (the 10-degree
    ice-resistant slope of Table 3). The default sizes displace the 35,000 t of Table 3 at the 14 m
    draft within 0.1 % with the centre of buoyancy 5.37 m above the keel (Table 3: 5.4 m). Body frame:
    origin at the CG, ``cg_above_keel`` above the keel.
    """
    zk = -cg_above_keel                     # keel
    zp = zk + pontoon_height                # pontoon top
    zt = zk + draft + freeboard             # column top
    parts = []
    # ring pontoon: two long sides, two short ends in between (touching, not overlapping)
    for sy in (-1, 1):
        parts.append(box(length, pontoon_width, pontoon_height,
                         (0.0, sy * (width - pontoon_width) / 2, zk + pontoon_height / 2)))
    inner_y = width - 2 * pontoon_width
    for sx in (-1, 1):
        parts.append(box(pontoon_width, inner_y, pontoon_height,
                         (sx * (length - pontoon_width) / 2, 0.0, zk + pontoon_height / 2)))
    # columns: x faces lean out by tan(slope) per metre of height
    lean = math.tan(math.radians(slope_deg)) * (zt - zp)
    for sx in (-1, 1):
        for sy in (-1, 1):
            cx = sx * (length - column) / 2 - sx * lean / 2
            cy = sy * (width - column) / 2
            parts.append(sloped_block(column - lean, column + lean, column, zp, zt, (cx, cy)))
    return merge(parts)
