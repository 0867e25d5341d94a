"""The floe-field generator (pice/scenes/floe_field.py) against its specification (issue 14, seed 003:
floes of 30-40 m or 20-30 m, 2.5-2.7 m thick, at 50/70/90 %).

References: geometry (every floe convex, counter-clockwise, inside the area and disjoint from every
other, by the separating-axis theorem for convex polygons); the field's own definition (the
concentration within the stated one percentage point; sizes and thicknesses within their ranges,
with the share of floes capped below the size range at 90 % stated and bounded); reproducibility
from the seed.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from pice.scenes.floe_field import CONCENTRATION_TOLERANCE, clip_to_box, floe_field, polygon_area


def _separated(a: np.ndarray, b: np.ndarray) -> bool:
    """True when convex polygons a and b do not overlap (an edge normal of one separates them)."""
    for p in (a, b):
        edges = np.roll(p, -1, axis=0) - p
        for n in np.column_stack([edges[:, 1], -edges[:, 0]]):
            if (a @ n).max() <= (b @ n).min() + 1e-9 or (b @ n).max() <= (a @ n).min() + 1e-9:
                return True
    return False


def _convex_ccw(p: np.ndarray) -> bool:
    e = np.roll(p, -1, axis=0) - p
    f = np.roll(e, -1, axis=0)
    return bool(np.all(e[:, 0] * f[:, 1] - e[:, 1] * f[:, 0] > -1e-9))


@pytest.mark.parametrize("concentration,size", [(0.5, (30.0, 40.0)), (0.7, (30.0, 40.0)), (0.9, (30.0, 40.0)),
                                                (0.7, (20.0, 30.0))])
def test_field_meets_its_specification(concentration, size):
    area = (-300.0, -200.0, 300.0, 200.0)
    field = floe_field(area=area, size=size, thickness=(2.5, 2.7), concentration=concentration, seed=11)
    assert abs(field.concentration - concentration) <= CONCENTRATION_TOLERANCE
    sizes = field.sizes
    assert sizes.max() <= size[1] * (1 + 1e-9)
    inside = (sizes >= size[0] * (1 - 1e-9)).mean()
    # a few floes are capped by their cell (max_fill) below the range: measured 0-0.6 % at 50-70 %,
    # 3-4 % at 90 % (pice/scenes/floe_field.py)
    assert inside >= (0.95 if concentration > 0.8 else 0.99)
    assert abs(sizes.mean() - np.mean(size)) <= 0.05 * np.mean(size)
    assert field.thickness.min() >= 2.5 and field.thickness.max() <= 2.7 and len(field.thickness) == len(sizes)
    for p in field.polygons:
        assert _convex_ccw(p) and polygon_area(p) > 0.0
        assert p[:, 0].min() >= area[0] - 1e-9 and p[:, 0].max() <= area[2] + 1e-9
        assert p[:, 1].min() >= area[1] - 1e-9 and p[:, 1].max() <= area[3] + 1e-9
    centres = np.array([p.mean(axis=0) for p in field.polygons])
    for i, j in itertools.combinations(range(len(field.polygons)), 2):
        if np.linalg.norm(centres[i] - centres[j]) < 1.5 * size[1]:  # farther apart cannot touch
            assert _separated(field.polygons[i], field.polygons[j]), (i, j)


def test_same_seed_same_field_other_seed_other_field():
    kw = dict(area=(0.0, 0.0, 400.0, 300.0), size=(20.0, 30.0), concentration=0.7)
    a, b, c = floe_field(seed=4, **kw), floe_field(seed=4, **kw), floe_field(seed=5, **kw)
    assert len(a.polygons) == len(b.polygons)
    for p, q in zip(a.polygons, b.polygons):
        np.testing.assert_array_equal(p, q)
    np.testing.assert_array_equal(a.thickness, b.thickness)
    assert not all(len(p) == len(q) and np.array_equal(p, q) for p, q in zip(a.polygons, c.polygons))


def test_bad_requests_are_refused_with_the_fix():
    with pytest.raises(ValueError, match="concentration"):
        floe_field(area=(0, 0, 100, 100), concentration=0.99)
    with pytest.raises(ValueError, match="area"):
        floe_field(area=(0, 0, -1, 100))
    with pytest.raises(ValueError, match="size"):
        floe_field(area=(0, 0, 100, 100), size=(40.0, 30.0))


def test_clip_to_box():
    square = np.array([[-1.0, -1.0], [3.0, -1.0], [3.0, 3.0], [-1.0, 3.0]])
    clipped = clip_to_box(square, (0.0, 0.0, 2.0, 1.0))
    assert polygon_area(clipped) == pytest.approx(2.0, rel=1e-12)
