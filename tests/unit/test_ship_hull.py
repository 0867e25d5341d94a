"""The parametric ship hull of seed 002 (Gong, Polojärvi & Tuhkuri 2017, Table 1: M/T Uikku;
pice/platform/ship.py): convex, closed, non-overlapping pieces; the waterline's length, breadth,
parallel midbody and bow angle and the stem's rake measured on the mesh; the displaced volume against
a hand calculation; the half model; and a short run of the ship through a few floes."""

from __future__ import annotations

import math

import h5py
import numpy as np
import pytest

from pice.cli import main
from pice.kernels.polyhedra import overlap, volume_centroid
from pice.platform.hull_buoyancy import submerged
from pice.platform.hulls import merge
from pice.platform.ship import ship_pieces, ship_volume

# seed 002, Table 1; depth: the 9.5 m draft + the default 5.5 m freeboard (an assumption, docs/ridge_keel.md)
L, LM, B, T, ALPHA, PHI, D = 150.0, 67.5, 22.2, 9.5, 25.2, 29.7, 15.0
DIMS = dict(length=L, midbody=LM, breadth=B, draft=T, waterline_angle=ALPHA, stem_angle=PHI, depth=D)
LB = 0.5 * B / math.tan(math.radians(ALPHA))   # the bow on the waterline: 23.589 m
LS = L - LM - LB                                # the stern: 58.911 m
RAKE = 1.0 / math.tan(math.radians(PHI))        # [m] per metre of height: 1.7532
F = D - T                                       # freeboard [m]


def _volume(v, t) -> float:
    """The divergence theorem: V = 1/6 sum a . (b x c) over the outward triangles [m^3]."""
    a, b, c = v[t[:, 0]], v[t[:, 1]], v[t[:, 2]]
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum()) / 6.0


def _analytic(half: bool) -> list[float]:
    """Each piece's volume by Cavalieri [m^3]: bow and stern the same triangle on every waterplane
    (B L_b / 2, B L_s / 2) over the depth D; the midbody B (L_m + z / tan phi) at height z, z from -T to F."""
    s = 0.5 if half else 1.0
    return [s * 0.5 * B * LB * D, s * B * (LM * D + 0.5 * RAKE * (F ** 2 - T ** 2)), s * 0.5 * B * LS * D]


def _faces(v, t):
    """(pts, counts) of a piece for pice/kernels/polyhedra.py: each triangle one face."""
    pts = np.zeros((len(t), 3, 3))
    pts[:] = v[t]
    return pts, np.full(len(t), 3, np.int64)


def _waterline(v, t, z=0.0) -> np.ndarray:
    """(k, 2) points where the mesh's edges cross the plane z [m]: the waterline's outline."""
    out = []
    for a, b in ((0, 1), (1, 2), (2, 0)):
        p, q = v[t[:, a]], v[t[:, b]]
        cross = (p[:, 2] - z) * (q[:, 2] - z) < 0.0
        s = (z - p[cross, 2]) / (q[cross, 2] - p[cross, 2])
        out.append(p[cross, :2] + s[:, None] * (q[cross, :2] - p[cross, :2]))
    return np.vstack(out)


@pytest.mark.parametrize("half", [False, True], ids=["full", "half"])
def test_every_piece_is_convex_closed_and_of_its_analytic_volume(half):
    """Convex: every vertex on the inner side of every face plane (to 1e-9 of the hull's length).
    Closed: every edge in exactly two triangles, once each way, and the divergence theorem's volume is
    the piece's analytic (Cavalieri) volume to 1e-12."""
    for (v, t), expect in zip(ship_pieces(**DIMS, half=half), _analytic(half)):
        a, b, c = v[t[:, 0]], v[t[:, 1]], v[t[:, 2]]
        n = np.cross(b - a, c - a)
        n /= np.linalg.norm(n, axis=1)[:, None]
        heights = np.einsum("ij,kj->ik", n, v) - np.einsum("ij,ij->i", n, a)[:, None]  # (faces, vertices)
        assert heights.max() < 1e-9 * L
        edges = [(int(i), int(j)) for tri in t for i, j in ((tri[0], tri[1]), (tri[1], tri[2]), (tri[2], tri[0]))]
        assert len(set(edges)) == len(edges) and all((j, i) in set(edges) for i, j in edges)
        assert _volume(v, t) == pytest.approx(expect, rel=1e-12)


@pytest.mark.parametrize("half", [False, True], ids=["full", "half"])
def test_the_pieces_touch_without_overlapping(half):
    """The contact's own clipping (pice/kernels/polyhedra.overlap) finds no volume shared by two pieces
    (below 1e-9 of the smaller), and the pieces' volumes add up to the union's by hand, 35,046 m^3 for
    the full hull to the 15 m deck (ship.ship_volume: the waterplane areas integrated keel to deck)."""
    pieces = ship_pieces(**DIMS, half=half)
    vols = [_volume(v, t) for v, t in pieces]
    for i in range(len(pieces)):
        for j in range(i + 1, len(pieces)):
            pts, counts, _ = overlap(*_faces(*pieces[i]), *_faces(*pieces[j]))
            assert volume_centroid(pts, counts)[0] < 1e-9 * min(vols[i], vols[j])
    assert sum(vols) == pytest.approx(ship_volume(**DIMS, half=half), rel=1e-12)
    assert ship_volume(**DIMS) == pytest.approx(35046.13, abs=0.01)


def test_the_waterline_and_the_stem_measure_table_1():
    """On the union mesh at z = 0: length 150 m, breadth 22.2 m, parallel midbody (the stretch at the
    full half-breadth) 67.5 m; on the bow piece: the half-angle 25.2 deg (stem to shoulder on the
    waterline), the stem's rake 29.7 deg from the horizontal (its centreline edge, keel to deck), and
    the bow's normal angle psi = arctan(tan phi / sin alpha) = 53.26 deg of Malmberg's formula (seed 002,
    after Eq. 1) on its flat side."""
    pieces = ship_pieces(**DIMS)
    v, t = merge(pieces)
    wl = _waterline(v, t)
    assert np.ptp(wl[:, 0]) == pytest.approx(L, abs=1e-9)
    assert np.ptp(wl[:, 1]) == pytest.approx(B, abs=1e-9)
    flat = wl[np.abs(np.abs(wl[:, 1]) - B / 2) < 1e-9]
    assert np.ptp(flat[:, 0]) == pytest.approx(LM, abs=1e-9)
    bv, bt = pieces[0]
    bow = _waterline(bv, bt)
    stem = bow[np.argmax(bow[:, 0])]
    shoulder = bow[np.argmax(bow[:, 1])]
    assert stem[1] == pytest.approx(0.0, abs=1e-12) and shoulder[1] == pytest.approx(B / 2)
    assert math.degrees(math.atan2(shoulder[1], stem[0] - shoulder[0])) == pytest.approx(ALPHA, abs=1e-9)
    centre = bv[np.abs(bv[:, 1]) < 1e-12]
    top, keel = centre[np.argmax(centre[:, 2])], centre[np.argmin(centre[:, 2])]
    assert math.degrees(math.atan2(top[2] - keel[2], top[0] - keel[0])) == pytest.approx(PHI, abs=1e-9)
    a, b, c = bv[bt[:, 0]], bv[bt[:, 1]], bv[bt[:, 2]]
    n = np.cross(b - a, c - a)
    side = n[np.abs(n[:, 1]) > 1e-9]  # the flat sides (deck, keel and the shoulder plane have n_y = 0)
    assert len(side) == 4
    psi = np.degrees(np.arctan2(np.hypot(side[:, 0], side[:, 1]), np.abs(side[:, 2])))
    expect = math.degrees(math.atan(math.tan(math.radians(PHI)) / math.sin(math.radians(ALPHA))))
    assert expect == pytest.approx(53.26, abs=0.01)
    assert np.allclose(psi, expect, atol=1e-9)


def test_the_displaced_volume_at_the_draft_is_the_hand_calculation():
    """The clipped-mesh volume below z = 0 (platform.hull_buoyancy.submerged, the buoyancy's own code)
    against the hand calculation B T L_b / 2 + B (L_m T - T^2 / (2 tan phi)) + B T L_s / 2
    = 2,487.4 + 12,479.4 + 6,212.3 = 21,179.1 m^3 (21,391 t at seed 002's 1010 kg/m^3; block
    coefficient 0.670); the half model displaces half of it and has no point at y < 0."""
    hand = B * T * LB / 2 + B * (LM * T - T ** 2 * RAKE / 2) + B * T * LS / 2
    assert hand == pytest.approx(21179.08, abs=0.01)
    assert hand / (L * B * T) == pytest.approx(0.6695, abs=1e-4)
    for half, share in ((False, 1.0), (True, 0.5)):
        v, t = merge(ship_pieces(**DIMS, half=half))
        vol = submerged(v, t, np.zeros(0), position=np.zeros(3), attitude=np.array([1.0, 0, 0, 0]), level=0.0)[0]
        assert vol == pytest.approx(share * hand, rel=1e-12)
        assert ship_volume(**DIMS, half=half, level=T) == pytest.approx(share * hand, rel=1e-12)
        if half:
            assert v[:, 1].min() >= 0.0 and v[:, 1].max() == pytest.approx(B / 2)


SHIP_IN_FLOES = """
[run]
name = "ship_in_floes"
duration = 4.0
series_every = 20
snapshots = 2

[water]
density = 1010.0
depth = 40.0

[floes]
area = [80.0, -30.0, 130.0, 30.0]
concentration = 0.5
size = [10.0, 14.0]
thickness = [1.0, 1.2]
velocity = [-1.0, 0.0]
seed = 2

[[bodies]]
name = "uikku"
hull = {type = "ship", length = 150.0, midbody = 67.5, breadth = 22.2, draft = 9.5, waterline_angle = 25.2, stem_angle = 29.7%s}
mass = 2.14e7
inertia = [1.0e9, 3.0e10, 3.0e10]
position = [0.0, 0.0, 0.0]
motion = "prescribed"
velocity = [[0.0, 2.0, 0.0, 0.0, 0.0, 0.0, 0.0]]
"""


@pytest.mark.parametrize("half", [False, True], ids=["full", "half"])
def test_a_prescribed_ship_meets_floes(tmp_path, half):
    """Smoke: the ship at 2 m/s into a few floes drifting at 1 m/s towards it (5 m ahead of the stem)
    runs 4 s, the floes touch its pieces (floe_structure_contacts > 0) and push it back (ice_force x < 0)."""
    job = tmp_path / "ship.toml"
    job.write_text(SHIP_IN_FLOES % (", half = true" if half else ""))
    out = tmp_path / "ship.h5"
    assert main(["run", str(job), "-o", str(out)]) == 0
    with h5py.File(out) as f:
        assert f.attrs["status"] == "finished"
        s = f["series"]
        assert s["floe_structure_contacts"][:].max() > 0, "the floes must reach the hull"
        assert s["ice_force"][:, 0, 0].min() < 0.0
