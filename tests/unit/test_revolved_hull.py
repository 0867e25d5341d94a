"""Hulls of revolution (pice/platform/hulls.revolved; `hull = {type = "revolved", profile = ...}`), for the
Kulluk's conical hull (issue 14) and the buoy's double cone (issue 16).

References: the volume of a frustum of a regular n-gon pyramid, h / 3 (A0 + A1 + sqrt(A0 A1)) with
A = (n / 2) r^2 sin(2 pi / n) (exact for the mesh, whose vertices lie on the circles: 1e-12), and the
submerged volume of the same solid cut by a water plane between two rings (the hull-buoyancy
clipping of Eq. 12 against the same formula); the mesh is closed (every edge shared by two
triangles in opposite directions); a bad profile is refused with the fix.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from pice.errors import JobError
from pice.job import parse_job
from pice.platform.hull_buoyancy import submerged
from pice.platform.hulls import revolved

N = 48
# a Kulluk-like profile (seed 003 Table 1): keel 62 m wide, 70 m at the waterline, 81 m at the deck
PROFILE = [(-12.5, 31.0), (-10.06, 31.0), (0.0, 35.0), (9.0, 40.5)]


def _area(r: float) -> float:
    return 0.5 * N * r * r * math.sin(2.0 * math.pi / N)


def _frustums(profile) -> float:
    return sum((z1 - z0) / 3.0 * (_area(r0) + _area(r1) + math.sqrt(_area(r0) * _area(r1)))
               for (z0, r0), (z1, r1) in zip(profile, profile[1:]))


def test_volume_and_closure():
    v, t = revolved(PROFILE, N)
    edges = {(int(a), int(b)) for tri in t for a, b in zip(tri, np.roll(tri, -1))}
    assert len(edges) == 3 * len(t) and all((b, a) in edges for a, b in edges)
    a, b, c = v[t[:, 0]], v[t[:, 1]], v[t[:, 2]]
    volume = np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0
    assert volume == pytest.approx(_frustums(PROFILE), rel=1e-12)


@pytest.mark.parametrize("level", [-11.0, -5.0, 0.0, 4.5])
def test_submerged_volume_below_a_water_plane(level):
    v, t = revolved(PROFILE, N)
    vol, _ = submerged(v, t, np.zeros(0, dtype=[("p0", float, (3,)), ("p1", float, (3,)), ("radius", float)]),
                       position=np.zeros(3), attitude=np.array([1.0, 0.0, 0.0, 0.0]), level=level)
    below = [(z, r) for z, r in PROFILE if z < level]
    k = len(below)
    (z0, r0), (z1, r1) = PROFILE[k - 1], PROFILE[k]
    cut = (level, r0 + (r1 - r0) * (level - z0) / (z1 - z0))  # the ring at the water plane
    assert vol == pytest.approx(_frustums(below + [cut]), rel=1e-10)


def test_job_takes_a_profile_and_refuses_a_bad_one():
    def job(profile):
        return parse_job({"run": {"duration": 1.0, "dt": 1e-3}, "water": {"density": 1025.0},
                          "ice": {"length": 8.0, "width": 6.0, "origin": [100.0, 0.0], "youngs_modulus": 1e9,
                                  "flexural_strength": 5e5, "compressive_strength": 2.5e6},
                          "bodies": [{"name": "kulluk", "hull": {"type": "revolved", "profile": profile},
                                      "mass": 2.8e7, "inertia": [1e10, 1e10, 1e10], "position": [0.0, 0.0, 0.0]}]})
    assert job(PROFILE).bodies[0].hull.profile[2] == (0.0, 35.0)
    with pytest.raises(JobError, match="z increasing"):
        job([(0.0, 30.0), (-1.0, 31.0)])
    with pytest.raises(JobError, match="r > 0"):
        job([(0.0, 30.0), (1.0, 0.0)])
