"""DEM mooring lines (chains of nodes with axial bonds, Morison loads, seabed contact).

References: the elastic catenary written out in this file (Irvine, Cable Structures, 1981,
Eqs. 2.26-2.27, solved with scipy), independent of pice.platform.catenary; the pretension of
Zhu & Ji (2022), section 4.1. The towed line of section 2.3: tests/physics/test_towed_line.py.
"""

import math

import numpy as np
import pytest
from scipy.optimize import fsolve

from pice.platform.catenary import Segment, solve_line
from pice.platform.layout import spread_mooring, zhu_ji_fairleads
from pice.platform.mooring_lines import LineSegment, build_lines


def irvine(L, w, ea, H, va, s):
    """(x, z) at unstretched arc length s of an elastic catenary with bottom vertical tension va."""
    v = va + w * s
    x = H / w * (np.arcsinh(v / H) - np.arcsinh(va / H)) + H * s / ea
    z = H / w * (np.hypot(1, v / H) - np.hypot(1, va / H)) + (va * s + 0.5 * w * s * s) / ea
    return x, z


def test_table1_dem_line_settles_to_the_elastic_catenary():
    """Issue 4 catenary test (Table 1 of Zhu & Ji 2022): ends 1000 m apart at 45 degrees, L = 1026 m,
    w = 2 kN/m, EA = 2052 kN. The DEM line (10 m elements) started 20 m off its equilibrium settles:
    end tensions within 1 %, node positions within 0.5 % of the span of the analytic shape.
    (Discretisation error of lumped nodes is O(dl^2): measured ~1e-4 for the tensions.)"""
    L, w, ea = 1026.0, 2.0e3, 2052.0e3
    X = Z = 1000.0 * math.cos(math.pi / 4)

    def miss(u):
        x, z = irvine(L, w, ea, u[0], u[1], L)
        return [x - X, z - Z]

    H, va = fsolve(miss, [3e5, -5e5], xtol=1e-13)
    seg = LineSegment(length=L, ea=ea, diameter=0.1, wet_weight=w, dry_mass=w / 9.81 * 1.15)
    ml = build_lines([((0, 0, 0), (X, 0, Z), [seg])], element_length=10.0, water_density=1025.0,
                     water_level=2000.0, seabed_z=None, bond_damping=0.5)
    ml.x[1:-1, 2] += 20.0  # start away from equilibrium
    dt = 0.5 * ml.stable_step()
    ml.advance(dt, int(600.0 / dt))
    assert np.abs(ml.v).max() < 0.05  # at rest (m/s)
    top = math.hypot(H, va + w * L)
    bottom = math.hypot(H, va)
    assert ml.fairlead_tensions()[0] == pytest.approx(top, rel=0.01)
    assert ml.anchor_tensions()[0] == pytest.approx(bottom, rel=0.01)
    s = np.linspace(0.0, L, len(ml.x))
    xa, za = irvine(L, w, ea, H, va, s)
    err = np.hypot(ml.x[:, 0] - xa, ml.x[:, 2] - za).max()
    assert err < 0.005 * 1000.0


def _quasi_static_force(lines, offset):
    """Sum of the horizontal fairlead forces of the quasi-static catenaries with the fairleads moved
    by ``offset`` along x [N]."""
    total = np.zeros(2)
    for anchor, fl, segs in lines:
        f = fl + np.array([offset, 0.0, 0.0])
        d = f[:2] - anchor[:2]
        h = float(np.linalg.norm(d))
        st = solve_line([Segment(sg.length, sg.wet_weight, sg.ea) for sg in segs], horizontal=h,
                        vertical=float(f[2] - anchor[2]))
        total -= st.horizontal_tension * d / h
    return total


def test_spread_mooring_at_rest_and_surge_restoring_force():
    """Issue 4 spread mooring (Zhu & Ji 2022, section 4.1: 12 lines in 4 bundles 5 degrees apart,
    fairleads 385 m above the anchors, Table 5 lines, pretension 221.7 kN). At rest each DEM fairlead
    tension equals the pretension within 1 %; moved 10, 20 and 30 m in surge, the DEM restoring
    force matches the quasi-static catenary model within 3 % (20 m elements, static equilibrium by
    kinetic damping; measured: 0.07 % and < 0.5 %)."""
    fl, headings = zhu_ji_fairleads()
    lines, layout, x = spread_mooring(fairleads_body=fl, bundle_headings_deg=headings)
    assert not layout.touches_seabed  # the layout finding: at 221.7 kN the Table 5 line hangs free
    ml = build_lines(lines, element_length=20.0, water_density=1025.0, water_level=0.0, seabed_z=-400.0,
                     bond_damping=0.3)
    ml.relax(tol=1.0)
    np.testing.assert_allclose(ml.fairlead_tensions(), 221.7e3, rtol=0.01)
    assert np.linalg.norm(ml.reactions(ml.fairleads).sum(axis=0)[:2]) < 1e-6 * 221.7e3 * 12  # balanced
    for offset in (10.0, 20.0, 30.0):
        moved = [(a, f + np.array([offset, 0.0, 0.0]), sg) for a, f, sg in lines]
        ml = build_lines(moved, element_length=20.0, water_density=1025.0, water_level=0.0, seabed_z=-400.0,
                         bond_damping=0.3)
        ml.relax(tol=1.0)
        dem = ml.reactions(ml.fairleads).sum(axis=0)[:2]
        qs = _quasi_static_force(lines, offset)
        assert dem[0] == pytest.approx(qs[0], rel=0.03)
        assert abs(dem[1]) < 1e-3 * abs(qs[0])
