"""The pre-designed buoy of Cai (2018, seed 004, Table 4-2) built as a hull of revolution (issue 16).

References: Table 4-2 (D_max 9 m, D_min 5 m, H 3 m, alpha 45 deg, theta 14.04 deg; waterline
diameter 8.48 m at the draft 2.24 m; displaced volume 73.28 m^3; weight 75.1 t; surface area
154.66 m^2; equivalent shell thickness 0.0619 m with steel of 7,850 kg/m^3) and Eq. 4-16 (the
volume below the draft). The mesh's rings are regular 512-gons whose area is 0.9975 of their
circles', so the volumes and areas are compared within 0.1 %; the table's own figures carry 3-4
digits. The stationary draft is found from the mesh buoyancy (platform.hull_buoyancy) for the
table's mass and water of 1,025 kg/m^3 (73.28 m^3 x 1,025 = 75.1 t, as the table pairs them).
A thin shell's inertia about its centre is checked on a closed cylinder against the analytic one.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from pice.platform.hull_buoyancy import BRACE_RECORD, submerged
from pice.platform.hulls import revolved
from pice.scenes.buoy import buoy_profile, shell_properties, surface_area

TABLE = dict(d_max=9.0, d_min=5.0, height=3.0, alpha_deg=45.0, theta_deg=14.04)
SEGMENTS = 512
RHO_W = 1025.0


def _hull():
    return revolved(buoy_profile(**TABLE), SEGMENTS)


def _volume_below(v, t, level):
    return submerged(v, t, np.zeros(0, BRACE_RECORD), position=np.zeros(3),
                     attitude=np.array([1.0, 0.0, 0.0, 0.0]), level=level)[0]


def test_profile_of_table_4_2():
    prof = buoy_profile(**TABLE)
    np.testing.assert_allclose(prof, [[0.0, 2.5], [0.5, 2.5], [2.5, 4.5], [3.0, 2.5]], atol=1e-3)
    # the waterline diameter at the 2.24 m draft: 8.48 m (theta 14.04 deg is atan(0.25) = 14.036 deg
    # to the table's digits: the keel cylinder is 0.49993 m, the diameter 8.4803 m)
    assert 2.0 * np.interp(2.24, prof[:, 0], prof[:, 1]) == pytest.approx(8.48, abs=1e-3)


def test_displacement_area_thickness_and_draft():
    v, t = _hull()
    vol = _volume_below(v, t, 2.24)
    assert vol == pytest.approx(73.28, rel=1e-3)                       # Table 4-2, Eq. 4-16
    area = surface_area(v, t)
    assert area == pytest.approx(154.66, rel=1e-3)                     # Table 4-2, Eq. 4-20
    mass = RHO_W * 73.28
    assert mass == pytest.approx(7.51e4, rel=1e-3)                      # Table 4-2, Eq. 4-17
    thickness, centre, _ = shell_properties(v, t, mass=mass)
    assert thickness == pytest.approx(0.0619, rel=2e-3)                # Eq. 4-21
    draft = brentq(lambda d: RHO_W * _volume_below(v, t, d) - mass, 0.1, 2.9, xtol=1e-10)
    assert draft == pytest.approx(2.24, rel=1e-3)
    assert 0.0 < centre[2] < 3.0 and np.allclose(centre[:2], 0.0, atol=1e-9)


def test_shell_inertia_of_a_closed_cylinder():
    """Thin closed cylinder (radius R, height L, side and two end disks), uniform surface density:
    I_zz = m_side R^2 + 2 m_disk R^2 / 2; I_xx = m_side (R^2/2 + L^2/12) + 2 m_disk (R^2/4 + (L/2)^2)."""
    R, L, mass = 2.0, 3.0, 1000.0
    v, t = revolved([(0.0, R), (L, R)], 1024)
    _, centre, inertia = shell_properties(v, t, mass=mass)
    a_side, a_disk = 2 * math.pi * R * L, math.pi * R * R
    sigma = mass / (a_side + 2 * a_disk)
    m_side, m_disk = sigma * a_side, sigma * a_disk
    izz = m_side * R * R + 2 * m_disk * R * R / 2
    ixx = m_side * (R * R / 2 + L * L / 12) + 2 * m_disk * (R * R / 4 + (L / 2) ** 2)
    assert centre[2] == pytest.approx(L / 2, abs=1e-9)
    np.testing.assert_allclose(np.diag(inertia), [ixx, ixx, izz], rtol=2e-5)  # 1024-gon: 6e-6 of the circle
    assert abs(inertia[0, 1]) < 1e-6 * izz


def test_cones_that_do_not_fit_are_refused():
    with pytest.raises(ValueError, match="raise the height"):
        buoy_profile(d_max=10.5, d_min=5.0, height=3.0, alpha_deg=70.0, theta_deg=14.04)


#: Cai (2018) Table 6-2: the stationary draft [m] of each design, hull angle (rows) by D_max (columns)
TABLE_6_2 = {30: [2.81, 2.78, 2.74, 2.70, 2.66, 2.61, 2.57, 2.52], 35: [2.73, 2.68, 2.63, 2.57, 2.52, 2.46, 2.41, 2.36],
             40: [2.63, 2.56, 2.50, 2.44, 2.38, 2.32, 2.26, 2.21], 45: [2.51, 2.44, 2.37, 2.30, 2.24, 2.18, 2.13, 2.07],
             50: [2.39, 2.32, 2.25, 2.18, 2.12, 2.06, 2.01, 1.96], 55: [2.28, 2.20, 2.13, 2.06, 2.00, 1.95, 1.90, 1.85],
             60: [2.17, 2.09, 2.02, 1.96, 1.91, 1.86, 1.81, 1.77], 65: [2.07, 2.00, 1.93, 1.87, 1.82, 1.77, 1.73, 1.69]}
D_MAX = [7.0, 7.5, 8.0, 8.5, 9.0, 9.5, 10.0, 10.5]


def test_design_sweep_drafts_against_table_6_2():
    """Every design of Table 6-2 built as the thesis builds it (scenes.buoy.design_profile), with the
    pre-designed buoy's shell (0.0619 m of steel): where the table's draft lies below the widest
    section (2.5 m above the keel) the mesh buoyancy gives it within 3 % (issue 16; measured: to the
    table's two decimals, 0.5 %). Above it the thesis let the lower cone run on past D_max; the real
    closed hull floats deeper than the table says there, or sinks (no draft): checked as such."""
    from pice.scenes.buoy import STEEL_DENSITY, design_profile, stationary_draft

    compared = deeper = sunk = 0
    for alpha, row in TABLE_6_2.items():
        for d_max, table in zip(D_MAX, row):
            try:
                v, t = revolved(design_profile(d_max=d_max, alpha_deg=alpha), SEGMENTS)
            except ValueError:  # D_min <= 0: no such hull
                assert table > 2.5
                sunk += 1
                continue
            mass = STEEL_DENSITY * 0.0619 * surface_area(v, t)
            draft = stationary_draft(v, t, mass=mass)
            if table < 2.5:
                assert draft == pytest.approx(table, rel=0.03), (alpha, d_max)
                assert draft == pytest.approx(table, abs=0.006), (alpha, d_max)  # the table's rounding
                compared += 1
            elif math.isnan(draft):
                sunk += 1
            else:
                assert draft >= table - 0.006, (alpha, d_max)
                deeper += 1
    assert compared == 47 and deeper + sunk == 17  # of the 64 designs of the table


def test_mooring_chain_of_table_4_3():
    """The buoy's single chain (Cai 2018, Table 4-3: 27.76 m from the seabed to the fairlead, 37.98 kg/m
    submerged, 138.8 m, 25.4 kN at the fairlead) laid out by pice's catenary (platform/catenary.py, the
    layout solve that places anchors): the suspended length 54.90 m, the horizontal suspended span
    45 m (the table's "initial horizontal suspended length") and the suspended chain's 2.09 t come
    out within 0.5 % (the table's 3-4 digits; a chain of 0.0445 m wire is stiff: EA 1e12 N makes it
    inextensible, as the thesis's catenary is)."""
    from pice.platform.catenary import Segment, anchor_distance

    w = 37.98 * 9.81  # [N/m] submerged
    chain = [Segment(138.8, w, 1.0e12)]
    x, state = anchor_distance(chain, vertical=27.76, fairlead_tension=2.54e4)
    suspended = 138.8 - state.grounded_length
    assert suspended == pytest.approx(54.90, rel=5e-3)
    assert x - state.grounded_length == pytest.approx(45.0, rel=5e-3)  # the hanging part's span
    assert 37.98 * suspended == pytest.approx(2.09e3, rel=5e-3)
    assert state.fairlead_tension == pytest.approx(2.54e4, rel=1e-6)
