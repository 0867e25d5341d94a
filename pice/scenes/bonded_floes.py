"""Breakable floes: the floe field of [floes] (scenes/floe_field.py) built of bonded [ice] elements.

The HCP lattice of the level ice is laid over the whole area; an element belongs to a floe when its
sphere lies wholly inside the floe's polygon (its centre at least one radius inside every edge), and
bonds join neighbours of the same floe only. Elements of two floes are then at least one diameter
apart at t = 0, and each floe is a bonded plate of the [ice] material that bends, crushes and breaks
as the level ice does. The order of the elements is the lattice's, so every rank builds the same
elements with the same ids.
"""

from __future__ import annotations

import numpy as np

from .floe_field import floe_field


def inside_eroded(points: np.ndarray, polygon: np.ndarray, margin: float) -> np.ndarray:
    """Mask of the points (n, 2) [m] that lie at least ``margin`` [m] inside the convex
    counter-clockwise polygon (k, 2) [m], i.e. inside every edge's line by ``margin``."""
    keep = np.ones(len(points), dtype=bool)
    for a, b in zip(polygon, np.roll(polygon, -1, axis=0)):
        edge = b - a
        inward = np.array([-edge[1], edge[0]]) / np.hypot(edge[0], edge[1])  # left of a CCW edge is inside
        keep &= (points - a) @ inward >= margin
    return keep


def bonded_floe_positions(x: np.ndarray, floes, ice, *, d: float) -> tuple[np.ndarray, np.ndarray]:
    """The elements of the lattice ``x`` (n, 3) [m] (the level ice's HCP over floes.area, built by
    scenes/level_ice.py) that belong to a floe of the field ``floes`` ([floes], every floe ice.thickness
    thick), and the floe index of each. Raises ValueError when the field cannot be drawn or a floe is
    too small to hold one element of diameter d [m]."""
    field = floe_field(area=floes.area, size=floes.size, thickness=(ice.thickness, ice.thickness),
                       concentration=floes.concentration, seed=floes.seed)
    owner = np.full(len(x), -1, dtype=np.int64)
    r = 0.5 * d
    for k, poly in enumerate(field.polygons):
        lo, hi = poly.min(axis=0) + r, poly.max(axis=0) - r
        near = np.flatnonzero((x[:, 0] >= lo[0]) & (x[:, 0] <= hi[0]) & (x[:, 1] >= lo[1]) & (x[:, 1] <= hi[1]))
        owner[near[inside_eroded(x[near, :2], poly, r)]] = k
    empty = np.setdiff1d(np.arange(len(field.polygons)), owner)
    if len(empty):
        raise ValueError(f"{len(empty)} floe(s) hold no element of diameter {d:g} m (the smallest floe is "
                         f"{field.sizes.min():.3g} m across): use smaller elements (ice.element_diameter) or "
                         "larger floes (floes.size)")
    keep = owner >= 0
    return x[keep], owner[keep]


def same_floe(pairs: np.ndarray, floe: np.ndarray) -> np.ndarray:
    """The (i, j) pairs (m, 2) whose elements belong to the same floe: the bonds of the field."""
    return pairs[floe[pairs[:, 0]] == floe[pairs[:, 1]]]
