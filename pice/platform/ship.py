"""A parametric ship hull from its main dimensions (seed 002, Gong, Polojärvi & Tuhkuri 2017, Table 1:
M/T Uikku), as convex pieces that rigid ice blocks and floes meet (pice/kernels/polyhedra.py).

The shape (docs/ridge_keel.md, "The ship"), body frame x forward, y to port, z up, origin on the
centreline at the design waterline, half-way along the waterline length (the centre of gravity
assumed there):

* **bow**: a wedge whose two flat sides each contain the stem line. On every waterplane the bow is the
  same triangle, the sides meeting the centreline at the waterline half-angle alpha and reaching the
  half-breadth B/2 at the shoulder, B / (2 tan alpha) aft of the stem; the triangle moves aft by
  1 / tan(phi) per metre of depth, so the stem rakes at the stem angle phi from the horizontal. The
  bow's normal then leans at psi = arctan(tan phi / sin alpha) from the horizontal, the angle of
  Malmberg's formula (seed 002, Eq. 1).
* **parallel midbody**: full breadth B, ``midbody`` long on the waterline; its forward end is the bow's
  raked shoulder plane, its aft end a vertical transverse plane.
* **stern**: a wedge with vertical sides and a flat bottom, from the full breadth at the midbody's aft
  end to a point on the centreline ``length`` aft of the stem on the waterline (the seed gives no
  stern; it meets rubble only in the widest keel).

Every piece is a prism-like hexahedron or triangular prism between a keel plane z = -draft and a deck
plane z = depth - draft, convex as the intersection of its face planes; neighbours share a face and
do not overlap, so the union's volume is the sum of the pieces'. ``half``: the y >= 0 half (the seed's
half models with a symmetry wall at y = 0), the origin unchanged.
"""

from __future__ import annotations

import math

import numpy as np

from .hulls import merge

FREEBOARD = 5.5  # [m] the default depth - draft (a loaded tanker's; the seed gives none)
PIECES = ("bow", "midbody", "stern")  # ship_pieces' order


def entrance(*, breadth: float, waterline_angle: float) -> float:
    """The bow's length on the waterline [m]: B / (2 tan alpha), ``breadth`` B [m], ``waterline_angle``
    alpha [deg]."""
    return 0.5 * breadth / math.tan(math.radians(waterline_angle))


def _extrusion(bottom: np.ndarray, top: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A closed outward mesh between two horizontal polygons (n, 3) [m], each counter-clockwise seen
    from above, top[i] above bottom[i], every side quad planar."""
    n = len(bottom)
    tris = [(0, i + 1, i) for i in range(1, n - 1)]               # bottom cap, facing down
    tris += [(n, n + i, n + i + 1) for i in range(1, n - 1)]      # top cap, facing up
    for i in range(n):
        j = (i + 1) % n
        tris += [(i, j, n + j), (i, n + j, n + i)]
    return np.vstack([bottom, top]).astype(float), np.asarray(tris, np.int64)


def ship_pieces(*, length: float, midbody: float, breadth: float, draft: float, waterline_angle: float,
                stem_angle: float, depth: float | None = None, half: bool = False) -> list[tuple[np.ndarray, np.ndarray]]:
    """[bow, midbody, stern]: each a closed, outward, convex triangle mesh (vertices (n, 3) [m],
    triangles (m, 3)) in the body frame (module docstring). ``length`` [m] on the waterline,
    ``midbody`` [m] the parallel midbody on the waterline, ``breadth`` [m], ``draft`` [m],
    ``waterline_angle`` [deg] the bow's half-angle on the waterline, ``stem_angle`` [deg] the stem's
    rake from the horizontal, ``depth`` [m] keel to deck (None: draft + FREEBOARD); ``half``: the y >= 0 half. ValueError when
    the pieces do not fit (the job's HullSpec says which key)."""
    depth = draft + FREEBOARD if depth is None else depth
    bow = entrance(breadth=breadth, waterline_angle=waterline_angle)
    rake = 1.0 / math.tan(math.radians(stem_angle))   # [m] aft per metre of depth
    stern = length - midbody - bow
    if stern <= 0.0 or depth <= draft or midbody <= draft * rake:
        raise ValueError(f"these dimensions do not fit: stern {stern:.4g} m (> 0), depth - draft "
                         f"{depth - draft:.4g} m (> 0), midbody at the keel {midbody - draft * rake:.4g} m (> 0)")
    x_stem, x_fore = 0.5 * length, 0.5 * length - bow           # stem and fore shoulder, on the waterline
    x_aft, x_end = x_fore - midbody, -0.5 * length               # aft shoulder, stern's end
    b, y0 = 0.5 * breadth, 0.0 if half else -0.5 * breadth
    z_keel, z_deck = -draft, depth - draft

    def level(z, outline, raked):
        """The outline (x, y) at height z, the raked points shifted forward by z / tan(phi)."""
        return np.array([(x + (z * rake if r else 0.0), y, z) for (x, y), r in zip(outline, raked)])

    shapes = [
        # bow: stem, shoulder to port, shoulder to starboard (or the centreline); all raked
        ([(x_stem, 0.0), (x_fore, b), (x_fore, y0)], [True, True, True]),
        # midbody: fore starboard, fore port (raked), aft port, aft starboard
        ([(x_fore, y0), (x_fore, b), (x_aft, b), (x_aft, y0)], [True, True, False, False]),
        # stern: aft shoulder starboard, port, the end on the centreline
        ([(x_aft, y0), (x_aft, b), (x_end, 0.0)], [False, False, False]),
    ]
    return [_extrusion(level(z_keel, o, r), level(z_deck, o, r)) for o, r in shapes]


def ship_volume(*, length: float, midbody: float, breadth: float, draft: float, waterline_angle: float,
                stem_angle: float, depth: float | None = None, half: bool = False,
                level: float | None = None) -> float:
    """The hull's volume [m^3] below the height ``level`` above the keel [m] (default: the deck, the
    whole hull; ``level = draft``: the displaced volume at the design draft), by hand: the bow's
    triangle B L_b / 2 and the stern's B L_s / 2 on every waterplane, the midbody's B (L_m + z / tan phi)
    at height z above the waterline, integrated from the keel."""
    h = (draft + FREEBOARD if depth is None else depth) if level is None else level
    bow = entrance(breadth=breadth, waterline_angle=waterline_angle)
    rake = 1.0 / math.tan(math.radians(stem_angle))
    stern = length - midbody - bow
    z0, z1 = -draft, h - draft
    area = 0.5 * breadth * (bow + stern) * h + breadth * (midbody * h + 0.5 * rake * (z1 ** 2 - z0 ** 2))
    return 0.5 * area if half else area


def ship_hull(spec) -> tuple[list[tuple[np.ndarray, np.ndarray]], tuple[np.ndarray, np.ndarray]]:
    """(the convex pieces, their union as one mesh) of a "ship" HullSpec (pice/job/platform.py)."""
    pieces = ship_pieces(**spec.ship_dimensions)
    return pieces, merge(pieces)
