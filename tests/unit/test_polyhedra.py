"""Convex polyhedra: their overlap (pice/kernels/polyhedra.py) and contact geometry
(pice/kernels/polyhedron_contact.py), for rigid floes and blocks.

References: the intersection of axis-aligned boxes (exact: a box); the overlap volume of rotated
prisms against a Monte Carlo estimate (200,000 points, compared within 4 standard errors); the
closed surface of the overlap (its faces on A and on B have opposite vector areas: S_B = -S_A, so
the contact seen from B is the same contact); and the module's claim on the normal and area:
translating B by dx changes the overlap volume by -S_A . dx (central differences, 1e-6).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from pice.kernels.polyhedra import overlap, prism, volume_centroid
from pice.kernels.polyhedron_contact import contact_geometry

SQUARE = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])


def _hexagon(radius, centre, turn):
    a = turn + np.arange(6) * math.pi / 3
    return np.column_stack([centre[0] + radius * np.cos(a), centre[1] + radius * np.sin(a)])


def _inside(pts2, poly):
    """Points (n, 2) inside the convex counter-clockwise polygon (k, 2)."""
    ok = np.ones(len(pts2), bool)
    for a, b in zip(poly, np.roll(poly, -1, axis=0)):
        e = b - a
        ok &= e[0] * (pts2[:, 1] - a[1]) - e[1] * (pts2[:, 0] - a[0]) >= 0.0
    return ok


def test_boxes_face_to_face_and_corner():
    a = prism(SQUARE, 0.0, 1.0)
    vol, centre, normal, area, depth = contact_geometry(*a, *prism(SQUARE + [0.3, 0.0], 0.0, 1.0))
    assert vol == pytest.approx(0.7, rel=1e-12) and depth == pytest.approx(0.7, rel=1e-12)
    np.testing.assert_allclose(centre, [0.65, 0.5, 0.5], atol=1e-12)
    np.testing.assert_allclose(normal, [1.0, 0.0, 0.0], atol=1e-12)
    assert area == pytest.approx(1.0, rel=1e-12)
    # corner overlap [0.3, 1] x [0.2, 1] x [0.5, 1]: its faces on A are x = 1, y = 1, z = 1
    vol, centre, normal, area, _ = contact_geometry(*a, *prism(SQUARE + [0.3, 0.2], 0.5, 1.7))
    assert vol == pytest.approx(0.7 * 0.8 * 0.5, rel=1e-12)
    np.testing.assert_allclose(centre, [0.65, 0.6, 0.75], atol=1e-12)
    s = np.array([0.8 * 0.5, 0.7 * 0.5, 0.7 * 0.8])
    np.testing.assert_allclose(normal * area, s, atol=1e-12)


def test_apart_and_inside():
    a = prism(SQUARE, 0.0, 1.0)
    assert contact_geometry(*a, *prism(SQUARE + [1.5, 0.0], 0.0, 1.0))[0] == 0.0
    small = prism(SQUARE * 0.5 + [0.2, 0.2], 0.1, 0.9)
    vol, centre, _, _, _ = contact_geometry(*small, *a)
    assert vol == pytest.approx(0.25 * 0.8, rel=1e-12)
    np.testing.assert_allclose(centre, [0.45, 0.45, 0.5], atol=1e-12)


def test_rotated_floes_against_monte_carlo_and_symmetry():
    """Two hexagonal floes (10 m, 2.6 m thick), turned and offset, the second 0.4 m higher."""
    pa, pb = _hexagon(10.0, (0.0, 0.0), 0.1), _hexagon(9.0, (15.0, 4.0), 0.4)
    a, b = prism(pa, -2.3, 0.3), prism(pb, -1.9, 0.7)
    vol, centre, normal, area, depth = contact_geometry(*a, *b)
    rng = np.random.default_rng(0)
    n = 200_000
    pts = np.column_stack([rng.uniform(2.0, 12.0, n), rng.uniform(-6.0, 12.0, n), rng.uniform(-1.9, 0.3, n)])
    box = 10.0 * 18.0 * 2.2
    hit = _inside(pts[:, :2], pa) & _inside(pts[:, :2], pb)
    ov, counts, _ = overlap(*a, *b)  # the sampling box holds the whole overlap
    corners = np.concatenate([ov[f, :counts[f]] for f in range(len(counts)) if counts[f]])
    assert corners.min(axis=0)[0] >= 2.0 and corners.max(axis=0)[0] <= 12.0
    assert corners.min(axis=0)[1] >= -6.0 and corners.max(axis=0)[1] <= 12.0
    est, err = box * hit.mean(), box * math.sqrt(hit.mean() * (1 - hit.mean()) / n)
    assert vol > 10.0 and abs(vol - est) < 4.0 * err
    np.testing.assert_allclose(centre, pts[hit].mean(axis=0), atol=4.0 * pts[hit].std(axis=0).max() / math.sqrt(hit.sum()))
    vol_b, centre_b, normal_b, area_b, _ = contact_geometry(*b, *a)
    assert vol_b == pytest.approx(vol, rel=1e-12) and area_b == pytest.approx(area, rel=1e-12)
    np.testing.assert_allclose(centre_b, centre, atol=1e-9)
    np.testing.assert_allclose(normal_b, -normal, atol=1e-12)
    assert depth == pytest.approx(vol / area, rel=1e-14)


def test_normal_and_area_are_the_gradient_of_the_overlap():
    """dV/dx_B = -S_A = -A_c n (module docstring), by central differences of 1 mm."""
    pa, pb = _hexagon(10.0, (0.0, 0.0), 0.1), _hexagon(9.0, (15.0, 4.0), 0.4)
    a = prism(pa, -2.3, 0.3)
    _, _, normal, area, _ = contact_geometry(*a, *prism(pb, -1.9, 0.7))
    h = 1e-3
    grad = []
    for k in range(3):
        dx = np.zeros(3)
        dx[k] = h
        up = prism(pb + dx[:2], -1.9 + dx[2], 0.7 + dx[2])
        down = prism(pb - dx[:2], -1.9 - dx[2], 0.7 - dx[2])
        grad.append((volume_centroid(*overlap(*a, *up)[:2])[0] - volume_centroid(*overlap(*a, *down)[:2])[0]) / (2 * h))
    np.testing.assert_allclose(grad, -area * normal, rtol=1e-6, atol=1e-6 * area)


def test_separated_is_conservative():
    """separated() never calls overlapping bodies apart: 500 random pairs of turned prisms, each either
    reported separated with no overlap, or not (the overlap then decides)."""
    from pice.kernels.polyhedra import separated

    rng = np.random.default_rng(2)
    calls = 0
    for _ in range(500):
        a = prism(_hexagon(rng.uniform(2, 8), (0.0, 0.0), rng.uniform(0, 1)), -1.0, rng.uniform(0.1, 1.0))
        b = prism(_hexagon(rng.uniform(2, 8), rng.uniform(-14, 14, 2), rng.uniform(0, 1)), rng.uniform(-2, 0), 1.2)
        if separated(*a, *b):
            calls += 1
            assert volume_centroid(*overlap(*a, *b)[:2])[0] == 0.0
    assert 50 < calls < 450  # both outcomes exercised


def _random_box(rng, centre_spread):
    """A box of 0.3 x (0.37-0.86) x (0.6-1.4) m (a rubble block of issue 15), turned at random."""
    from scipy.spatial.transform import Rotation

    length = rng.uniform(0.6, 1.4)
    pts, counts = prism(np.array([[0.0, 0.0], [length, 0.0], [length, 0.615 * length], [0.0, 0.615 * length]])
                        - [length / 2, 0.3075 * length], -0.15, 0.15)
    turn = Rotation.random(random_state=rng).as_matrix()
    return pts @ turn.T + rng.uniform(-centre_spread, centre_spread, 3), counts


def test_face_clipping_gives_the_overlap_polyhedron_to_round_off():
    """contact_geometry (the faces of each body clipped by the other's planes) against
    contact_geometry_clipped (the overlap polyhedron, A clipped by B's planes with cap faces): the
    same volume, centroid, normal and area to 1e-9 over 300 random pairs of turned blocks and 100
    of turned hexagonal floes, about 85 % of them overlapping (the two are the same sums over the
    same surface; 1e-9 leaves room for the round-off of the cuts' points)."""
    from pice.kernels.polyhedron_contact import contact_geometry_clipped

    rng = np.random.default_rng(7)
    pairs = [(_random_box(rng, 0.0), _random_box(rng, 0.35)) for _ in range(300)]
    for _ in range(100):
        a = prism(_hexagon(1.0, (0.0, 0.0), rng.uniform(0, 1)), -0.5, 0.5)
        b = prism(_hexagon(0.8, rng.uniform(-1.2, 1.2, 2), rng.uniform(0, 1)), rng.uniform(-0.8, 0.0), 0.6)
        pairs.append((a, b))
    touching = 0
    for a, b in pairs:
        new, ref = contact_geometry(*a, *b), contact_geometry_clipped(*a, *b)
        assert new[0] == pytest.approx(ref[0], rel=1e-9, abs=1e-15)
        if ref[0] > 1e-12:
            touching += 1
            np.testing.assert_allclose(new[1], ref[1], atol=1e-9)
            np.testing.assert_allclose(new[2] * new[3], ref[2] * ref[3], atol=1e-9)
    assert touching > 300


def test_the_part_in_a_half_space_without_its_cap():
    """part_inside (the faces clipped, no cap: the apex on the plane) against clip + volume_centroid
    (the cap built): the same volume, centroid and cut area to 1e-9, over 200 turned blocks cut by
    random planes through them; and a unit cube cut at z = 0.3 exactly (volume 0.3, centroid z 0.15,
    cut area 1, extent across y 1, lowest point 0)."""
    from pice.kernels.polyhedra import clip
    from pice.kernels.polyhedron_contact import part_inside

    buf = np.empty((2, 64, 3))
    cube = prism(SQUARE, 0.0, 1.0)
    vol, c, area, lo, hi, zmin = part_inside(*cube, 0.0, 0.0, 1.0, 0.3, buf, 0.0, 1.0)
    assert vol == pytest.approx(0.3, rel=1e-12) and area == pytest.approx(1.0, rel=1e-12)
    np.testing.assert_allclose(c, [0.5, 0.5, 0.15], atol=1e-12)
    assert (lo, hi, zmin) == (0.0, 1.0, 0.0)
    rng = np.random.default_rng(11)
    cut = 0
    for _ in range(200):
        pts, counts = _random_box(rng, 0.0)
        n = rng.normal(size=3)
        n /= np.linalg.norm(n)
        offset = rng.uniform(-0.3, 0.3)
        vol, c, area, _, _, _ = part_inside(pts, counts, n[0], n[1], n[2], offset, buf)
        sp, sc, side = clip(pts, counts, np.zeros(len(counts), np.int64), n, offset, 1)
        ref_vol, ref_c = volume_centroid(sp, sc)
        ref_area = sum(np.linalg.norm(np.cross(sp[f, k] - sp[f, 0], sp[f, k + 1] - sp[f, 0])) / 2
                       for f in range(len(sc)) if side[f] == 1 for k in range(1, sc[f] - 1))
        assert vol == pytest.approx(ref_vol, rel=1e-9, abs=1e-15)
        if ref_vol > 1e-9:
            cut += 1
            np.testing.assert_allclose(c, ref_c, atol=1e-9)
            assert area == pytest.approx(ref_area, rel=1e-9)
    assert cut > 150
