"""Floating equilibrium: free ice settles at the draft Archimedes gives.

Issue claim: "A free sphere and a free sheet settle at the draft Archimedes gives (ice 920 kg/m^3 in
water 1035 kg/m^3) within 0.5 %."

Reference (Archimedes, solved here independently of pice's rest_elevation):
  * sphere of radius r: rho_i (4/3) pi r^3 = rho_w pi h^2 (3 r - h) / 3 for the submerged cap height
    h (the draft), solved with scipy's brentq on (0, 2r);
  * "cell" element (a vertical prism standing for its share of the plate): draft = t rho_i / rho_w.

Each case starts 0.2 m above its rest height, with heave damping (0.3 of critical) and Morison drag
(C_d = 1), and runs 10 s: the heave period is ~2 s and the amplitude decays as exp(-0.3 omega t),
omega ~ 3 rad/s, so after 10 s the residual is ~1e-5 of the 0.2 m offset -- far inside 0.5 %.
Measured: relative draft error 1.1e-5 (spheres) and 9.5e-6 (cells).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from pice.job import parse_job
from pice.simulation import Simulation

RHO_I, RHO_W = 920.0, 1035.0
THICKNESS = 1.0  # = element diameter: one layer
LEVEL = 0.0


def sphere_draft(r: float) -> float:
    """Submerged cap height [m] of a floating sphere of radius r (Archimedes)."""
    def excess(h):
        return RHO_W * math.pi * h * h * (3.0 * r - h) / 3.0 - RHO_I * 4.0 / 3.0 * math.pi * r ** 3
    return brentq(excess, 0.0, 2.0 * r, xtol=1e-14, rtol=1e-15)


def cell_draft(t: float) -> float:
    """Draft [m] of a vertical prism of height t (Archimedes)."""
    return t * RHO_I / RHO_W


def _job(volume, length, width):
    return parse_job({
        "run": {"duration": 10.0},
        "water": {"density": RHO_W, "level": LEVEL, "heave_damping_ratio": 0.3, "ice_drag": "morison", "drag_coefficient": 1.0},
        "ice": {"length": length, "width": width, "thickness": THICKNESS, "element_diameter": 1.0,
                "density": RHO_I, "element_volume": volume},
        "bond": {"normal_stiffness": 1.72e7, "shear_stiffness": 1.72e6, "breakable": False},
    })


CASES = [
    pytest.param("sphere", 1.0, 1.0, marks=pytest.mark.nojit, id="sphere-single"),
    pytest.param("sphere", 6.0, 4.0, id="sphere-sheet-6x4"),
    pytest.param("cell", 1.0, 1.0, marks=pytest.mark.nojit, id="cell-single"),
    pytest.param("cell", 6.0, 4.0, id="cell-sheet-6x4"),
]


@pytest.mark.nojit
def test_sphere_draft_reference():
    """Sanity of the reference itself: for rho_i/rho_w = 0.8889 the cap holds 88.9 % of the sphere's
    volume, and r < h < 2 r rho_i/rho_w (more than half is submerged, and the dry top cap is narrower
    than a prism, so it is taller than 11.1 % of the diameter: h = 0.79269 m for r = 0.5 m).
    Tolerance 1e-12 (brentq to 1e-14)."""
    r = 0.5
    h = sphere_draft(r)
    assert math.pi * h * h * (3 * r - h) / 3 / (4 / 3 * math.pi * r ** 3) == pytest.approx(RHO_I / RHO_W, rel=1e-12)
    assert r < h < 2 * r * RHO_I / RHO_W
    assert h == pytest.approx(0.79269, abs=1e-5)


@pytest.mark.parametrize("volume, length, width", CASES)
def test_settles_at_archimedes_draft(volume, length, width):
    """Released 0.2 m above rest, every element settles with draft = level - (z_centre - half height)
    equal to the Archimedes draft within 0.5 % (the issue; measured ~1e-5), and is at rest
    (|v_z| < 1e-4 m/s, the decayed heave). The half height is r for spheres and t/2 for cells.
    """
    sim = Simulation(_job(volume, length, width))
    p = sim.p
    if length > 1.0:
        assert p.n >= 20 and p.bond_count() > 30  # a bonded sheet, not a single element
    else:
        assert p.n == 1
    half = 0.5 if volume == "sphere" else 0.5 * THICKNESS
    np.testing.assert_allclose(p.half_height, half)
    expected = sphere_draft(0.5) if volume == "sphere" else cell_draft(THICKNESS)
    p.x[:, 2] += 0.2
    sim.compute_forces()
    z_start = p.x[:, 2].copy()
    sim.advance(int(math.ceil(10.0 / sim.dt)))
    assert np.all(p.x[:, 2] < z_start - 0.15)  # it really came down
    draft = LEVEL - (p.x[:, 2] - half)
    err = np.abs(draft / expected - 1.0).max()
    assert err < 5e-3, f"draft {draft.mean():.6f} m vs Archimedes {expected:.6f} m: {err:.3g}"
    assert np.abs(p.v[:, 2]).max() < 1e-4
    assert sim.c.broken == 0
