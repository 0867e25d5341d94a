"""Rubble for a ridge keel (issue 15; seed 002, Gong, Polojärvi & Tuhkuri 2017): the blocks released
under water beneath the cover, the keel's shape they are trimmed to, and its porosity.

Release. Every block is a rectangular prism (``blocks.length`` uniform, width ``aspect`` x length,
``thickness``), its yaw uniform in [0, 180) deg and its roll and pitch uniform in +-``TILT`` deg.
``RELEASE`` times the ice of the keel's box at the porosity seed 002 quotes (0.3) is released, so
that the trimmed shape is full. The blocks are packed under the cover in the keel's box (its width
w along x, its length along y) as shelves: each block's world bounding box next to the last along x,
rows along y, layers downwards, GAP apart, so no two blocks touch at t = 0 and the release is as
shallow as their bounding boxes allow (about 4 times the keel's depth). Buoyancy then packs them
against the cover (physics/keel.py).

Trim. A block stays when its centre lies inside the keel: below the cover by at most ``depth``, and
within w / 2 - (cover - z) / tan(pile_angle) of the keel's centre line x (seed 002, Fig. 2).
"""

from __future__ import annotations

import math

import numpy as np

TILT = 20.0      # [deg] largest roll and pitch of a released block
RELEASE = 1.15   # ice released / ice a full keel box holds at porosity 0.3 (the spill the trim removes)
GAP = 0.02       # [m] between the cells' blocks at release


def random_attitudes(n: int, rng: np.random.Generator) -> np.ndarray:
    """(n, 4) unit quaternions (w, x, y, z): yaw uniform in [0, pi), then roll and pitch uniform in
    +-TILT deg (R = R_z(yaw) R_y(pitch) R_x(roll))."""
    yaw = rng.uniform(0.0, math.pi, n)
    tilt = math.radians(TILT)
    pitch, roll = rng.uniform(-tilt, tilt, n), rng.uniform(-tilt, tilt, n)
    cy, sy = np.cos(0.5 * yaw), np.sin(0.5 * yaw)
    cp, sp = np.cos(0.5 * pitch), np.sin(0.5 * pitch)
    cr, sr = np.cos(0.5 * roll), np.sin(0.5 * roll)
    return np.column_stack([cy * cp * cr + sy * sp * sr, cy * cp * sr - sy * sp * cr,
                            cy * sp * cr + sy * cp * sr, sy * cp * cr - cy * sp * sr])


def half_width(keel, z) -> np.ndarray:
    """Half the keel's width [m] at heights z [m] (negative below its bottom or above the cover)."""
    z = np.asarray(z, float)
    below = keel.cover - z
    w = 0.5 * keel.width - below / math.tan(math.radians(keel.pile_angle))
    return np.where((below >= 0.0) & (below <= keel.depth), w, -1.0)


def inside_keel(keel, points: np.ndarray) -> np.ndarray:
    """Mask of the points (n, 3) [m] inside the keel's trapezoidal prism (module docstring)."""
    p = np.asarray(points, float)
    return ((np.abs(p[:, 0] - keel.x) <= half_width(keel, p[:, 2]))
            & (p[:, 1] >= keel.y0) & (p[:, 1] <= keel.y0 + keel.length))


def keel_volume(keel) -> float:
    """The keel's volume [m^3]: its trapezoid's area times its length."""
    bottom = keel.width - 2.0 * keel.depth / math.tan(math.radians(keel.pile_angle))
    return 0.5 * (keel.width + max(bottom, 0.0)) * keel.depth * keel.length


def release_blocks(keel):
    """The released blocks of ``keel`` (a KeelSpec): (rectangles (n, 4, 2) [m] about each block's
    centre, in its own frame, counter-clockwise; centres (n, 3) [m]; attitudes (n, 4)), drawn from
    keel.seed and packed in shelves (module docstring)."""
    from ..kernels.geometry import rotation_matrix

    b = keel.blocks
    rng = np.random.default_rng(keel.seed)
    mean_volume = b.thickness * b.aspect * (b.length[0] ** 2 + b.length[0] * b.length[1] + b.length[1] ** 2) / 3.0
    count = int(math.ceil(RELEASE * 0.7 * keel.width * keel.length * keel.depth / mean_volume))
    length = rng.uniform(b.length[0], b.length[1], count)
    width = b.aspect * length
    q = random_attitudes(count, rng)
    half = np.column_stack([0.5 * length, 0.5 * width, np.full(count, 0.5 * b.thickness)])
    extent = np.array([np.abs(rotation_matrix(q[i])) @ half[i] for i in range(count)])  # world half-box
    x0, x1 = keel.x - 0.5 * keel.width, keel.x + 0.5 * keel.width
    y1 = keel.y0 + keel.length
    centres = np.zeros((count, 3))
    cx, cy, top = x0, keel.y0, keel.cover - GAP
    row = layer = 0.0  # the depth (y) of the current row and the height (z) of the current layer
    for i in range(count):
        ex, ey, ez = 2.0 * extent[i]
        if cx + ex > x1 and cx > x0:  # the next row
            cx, cy, row = x0, cy + row + GAP, 0.0
        if cy + ey > y1 and cy > keel.y0:  # the next layer down
            cx, cy, row, top, layer = x0, keel.y0, 0.0, top - layer - GAP, 0.0
        centres[i] = (cx + 0.5 * ex, cy + 0.5 * ey, top - 0.5 * ez)
        cx += ex + GAP
        row, layer = max(row, ey), max(layer, ez)
    rect = np.zeros((count, 4, 2))
    rect[:, :, 0] = half[:, None, 0] * np.array([-1.0, 1.0, 1.0, -1.0])
    rect[:, :, 1] = half[:, None, 1] * np.array([-1.0, -1.0, 1.0, 1.0])
    return rect, centres, q


def porosity(keel, centres: np.ndarray, attitudes: np.ndarray, rects: np.ndarray, thickness: float, *,
             samples: int = 200_000, seed: int = 0, core: float = 0.0) -> float:
    """The void fraction [-] of the keel's prism (shrunk by ``core`` [m] from its slopes and bottom,
    not from the cover or the ends), sampled at ``samples`` random points (Monte Carlo; standard
    error sqrt(p (1 - p) / samples), 0.001 at the default): a point is ice when it lies inside a
    block (each block's box in its own frame)."""
    from ..kernels.geometry import points_in_boxes

    rng = np.random.default_rng(seed)
    tan = math.tan(math.radians(keel.pile_angle))
    shrunk = keel.model_copy(update={"width": keel.width - 2.0 * core / math.sin(math.radians(keel.pile_angle)),
                                     "depth": keel.depth - core})
    box_lo = np.array([keel.x - 0.5 * shrunk.width, keel.y0, keel.cover - shrunk.depth])
    box_hi = np.array([keel.x + 0.5 * shrunk.width, keel.y0 + keel.length, keel.cover])
    pts = box_lo + rng.random((samples * 2, 3)) * (box_hi - box_lo)
    pts = pts[inside_keel(shrunk, pts)][:samples]
    if not len(pts) or tan <= 0.0:
        raise ValueError("the keel's core holds no sample point: a smaller core")
    half = np.column_stack([np.abs(rects[:, :, 0]).max(axis=1), np.abs(rects[:, :, 1]).max(axis=1),
                            np.full(len(rects), 0.5 * thickness)])
    ice = points_in_boxes(np.ascontiguousarray(pts, dtype=float), np.ascontiguousarray(centres, dtype=float),
                          np.ascontiguousarray(attitudes, dtype=float), half)
    return 1.0 - float(ice.mean())
