"""The box kernel (pice/kernels/box_contact.py) against the general contact of convex polyhedra
(pice/kernels/polyhedron_contact.contact_scalars, itself tested against the exact overlap polyhedron and a
Monte Carlo volume in tests/unit/test_polyhedra.py).

Reference: the general kernel on the same two boxes' world polyhedra. The two compute the same faces'
pieces in other frames and clip them in another order, so they agree to round-off: 1e-9 relative on
the volume, the centroid, the normal, the area and the depth (the operations' round-off is ~1e-15
relative; 1e-9 leaves room for a near-degenerate overlap's sliver faces). Pairs: random sizes (a keel's
0.6-1.4 m blocks, 0.3 m thick) and attitudes, at centre distances from deep overlap to apart, and the
special cases a rubble pile meets: face to face, edge to face, corner to face, coplanar faces, one
inside the other.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from pice.kernels.box_contact import FACES, box_buffer, box_contact_scalars, box_half_extents
from pice.kernels.floe_motion import floe_rotations, world_polyhedra
from pice.kernels.polyhedra import face_planes, prism
from pice.kernels.polyhedron_contact import contact_buffer, contact_scalars


def _box(h):
    """(pts, counts) of the box |x_e| <= h_e in its body frame, as the keel builds its blocks."""
    rect = np.array([[-h[0], -h[1]], [h[0], -h[1]], [h[0], h[1]], [-h[0], h[1]]])
    pts, counts = prism(rect, -h[2], h[2])
    return pts[:6, :4], counts[:6]


def _both(ha, xa, qa, hb, xb, qb):
    """(box kernel, general kernel) results for boxes of half extents h at centres x, attitudes q."""
    body = np.array([_box(ha)[0], _box(hb)[0]])
    counts = np.array([_box(ha)[1], _box(hb)[1]])
    x, q = np.array([xa, xb], float), np.array([qa, qb], float)
    q /= np.linalg.norm(q, axis=1)[:, None]
    pts = world_polyhedra(body, counts, x, q)
    planes = face_planes(pts, counts)
    general = contact_scalars(pts[0], counts[0], planes[0], pts[1], counts[1], planes[1],
                              contact_buffer(pts[0], planes[0], pts[1], planes[1]))
    half = box_half_extents(body, counts)
    rot = floe_rotations(q)
    box = box_contact_scalars(x[0], rot[0], half[0], x[1], rot[1], half[1], box_buffer(), np.empty((8, 3)),
                              np.empty((8, 3)), np.empty(8, np.int64), np.empty(8, np.int64),
                              np.empty((3, 3)), np.empty((3, 3)))
    return np.array(box), np.array(general)


def _agree(box, general):
    if general[0] <= 0.0:
        assert box[0] == 0.0
        return
    scale = np.array([general[0], 1, 1, 1, 1, 1, 1, general[7], general[8]])
    tol = 1e-9 * scale + 1e-13
    compared = slice(None)
    if general[7] < 1e-9 * general[0] ** (2 / 3):
        # one box wholly inside the other: S_A is zero but for round-off, and the normal that noise's
        # direction in both kernels (the contact law's plastic limit then acts on no area)
        assert box[7] < 1e-9 * general[0] ** (2 / 3)
        compared = slice(0, 4)
    assert np.all(np.abs(box - general)[compared] <= tol[compared]), f"box kernel {box} against the general {general}"


def test_face_table_is_each_face_counter_clockwise_from_outside():
    """Each face's corners in order give an outward vector area of 4 h_u h_v along its axis."""
    h = np.array([0.5, 0.3, 0.15])
    corner = np.array([[h[e] if k >> e & 1 else -h[e] for e in range(3)] for k in range(8)])
    for f in range(6):
        p = corner[FACES[f]]
        s = 0.5 * sum(np.cross(p[i] - p[0], p[i + 1] - p[0]) for i in (1, 2))
        e, sign = f >> 1, 1.0 if f % 2 == 0 else -1.0
        want = np.zeros(3)
        want[e] = sign * 4 * h[(e + 1) % 3] * h[(e + 2) % 3]
        np.testing.assert_allclose(s, want, atol=1e-15)


def test_random_pairs_agree_with_the_general_kernel():
    rng = np.random.default_rng(20261206)
    overlapping = 0
    for _ in range(3000):
        ha = np.array([rng.uniform(0.3, 0.7), rng.uniform(0.18, 0.43), 0.15])
        hb = np.array([rng.uniform(0.3, 0.7), rng.uniform(0.18, 0.43), 0.15])
        qa, qb = rng.normal(size=4), rng.normal(size=4)
        # from deep overlap to just apart: the distance a fraction of the two bounding radii
        reach = np.linalg.norm(ha) + np.linalg.norm(hb)
        d = rng.normal(size=3)
        d *= rng.uniform(0.05, 1.05) * reach / np.linalg.norm(d)
        box, general = _both(ha, [0, 0, 0], qa, hb, d, qb)
        _agree(box, general)
        overlapping += general[0] > 0
    assert overlapping > 1000  # the sample covers overlaps as well as pairs apart


@pytest.mark.parametrize("case", ["face", "edge", "corner", "coplanar", "inside", "apart", "touching"])
def test_the_cases_of_a_pile(case):
    """Shallow overlaps as rubble makes them (10-100 um), and the degenerate ones."""
    h = np.array([0.5, 0.3, 0.15])
    one = [1.0, 0.0, 0.0, 0.0]
    tilt = [math.cos(0.2), math.sin(0.2), 0.0, 0.0]  # 0.4 rad about x
    turn = [math.cos(0.4), 0.0, 0.0, math.sin(0.4)]  # 0.8 rad about z
    corner_up = [0.88, 0.28, 0.36, 0.12]
    if case == "face":  # B's bottom 50 um into A's top, shifted
        args = (h, [0, 0, 0], one, h, [0.2, 0.1, 0.3 - 5e-5], turn)
    elif case == "edge":  # B tilted, its lower edge into A's top face
        zb = 0.15 + 0.15 * math.cos(0.4) + 0.3 * math.sin(0.4) - 1e-4
        args = (h, [0, 0, 0], one, h, [0.1, 0.0, zb], tilt)
    elif case == "corner":  # a corner of B into A's top
        rot = floe_rotations(np.array([corner_up]) / np.linalg.norm(corner_up))[0]
        corners = np.array([[h[e] if k >> e & 1 else -h[e] for e in range(3)] for k in range(8)]) @ rot.T
        args = (h, [0, 0, 0], one, h, [0.05, 0.02, 0.15 - corners[:, 2].min() - 1e-4], corner_up)
    elif case == "coplanar":  # tops in one plane, B 50 um into A's side
        args = (h, [0, 0, 0], one, h, [1.0 - 5e-5, 0.1, 0.0], one)
    elif case == "inside":  # B within A
        args = (h, [0, 0, 0], one, 0.4 * h, [0.05, 0.0, 0.0], turn)
    elif case == "apart":
        args = (h, [0, 0, 0], one, h, [0.2, 0.1, 0.3 + 1e-4], turn)
    else:  # faces meeting within EPS: no volume
        args = (h, [0, 0, 0], one, h, [0.2, 0.1, 0.3], one)
    box, general = _both(*args)
    _agree(box, general)
    if case in ("face", "edge", "corner", "coplanar", "inside"):
        assert general[0] > 0.0
    else:
        assert general[0] == 0.0


def test_half_extents_only_for_boxes():
    h = np.array([0.5, 0.3, 0.15])
    pts, counts = _box(h)
    np.testing.assert_allclose(box_half_extents(pts[None], counts[None]), [h])
    hexagon = np.array([[math.cos(a), math.sin(a)] for a in np.arange(6) * math.pi / 3])
    p6, c6 = prism(hexagon, -0.15, 0.15)
    assert box_half_extents(p6[None, :8, :6], c6[None, :8]).shape == (0, 3)
    skew = np.array([[-0.5, -0.3], [0.5, -0.3], [0.6, 0.3], [-0.4, 0.3]])  # a parallelogram prism
    ps, cs = prism(skew, -0.15, 0.15)
    assert box_half_extents(ps[None, :6, :4], cs[None, :6]).shape == (0, 3)
