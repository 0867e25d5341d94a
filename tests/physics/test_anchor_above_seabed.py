"""Anchors above the seabed (issue 13, case 1): the layout solve, the quasi-static lines and the DEM
lines' starting shape all take the seabed at water.level - water.depth, not at the anchor.

References, independent of pice.platform.catenary:
* Table 1 of Zhu & Ji (2022) (``../shared/seeds/000_...``): ends 1000 m apart at 45 degrees,
  L = 1026 m, w = 2 kN/m, EA = 2052 kN, between two fixed points in mid-water. Irvine's elastic
  catenary (Cable Structures, 1981, Eqs. 2.26-2.27) solved here with scipy gives H = 304.858 kN,
  V_anchor = -537.93 kN (the line leaves the anchor downward and sags 192 m below it), fairlead
  tension 1544.46 kN and a stretched length of L + int T/EA ds (closed form below).
  As a job: the fairlead on a held body, the anchor 707.107 m below and out in 2000 m of water.
  Each model must place the anchor and start there within 0.1 % (H, both end tensions, stretched
  length). The DEM line has 10 m elements (lumped-node error ~1e-4).
* a line that leaves an anchor 40 m above the seabed, lies on it and rises to the fairlead: the
  cable ODE shot piece by piece (descent to the seabed, grounded part at tension H, rise);
* Table 5's line over a seabed 10 m below its anchor: the DEM line settles at the pretension.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scenes import job_from_text
from scipy.integrate import solve_ivp
from scipy.optimize import fsolve

from pice.platform.catenary import Segment, anchor_distance, profile, solve_line

L1, W1, EA1 = 1026.0, 2.0e3, 2052.0e3  # Table 1
SPAN = 1000.0 * math.cos(math.pi / 4)   # 707.107 m across and down


def irvine_table1():
    """(H, V_anchor) [N] of Table 1 between fixed points: Irvine's equations solved with fsolve."""
    def miss(u):
        H, va = u
        vt = va + W1 * L1
        x = H / W1 * (math.asinh(vt / H) - math.asinh(va / H)) + H * L1 / EA1
        z = H / W1 * (math.hypot(1, vt / H) - math.hypot(1, va / H)) + (va * L1 + 0.5 * W1 * L1 * L1) / EA1
        return [x - SPAN, z - SPAN]

    return fsolve(miss, [3e5, -5e5], xtol=1e-13)


def stretched_length(H, va):
    """L + (1/EA) int_0^L sqrt(H^2 + (va + w s)^2) ds [m] (closed form)."""
    def prim(v):
        return 0.5 * (v * math.hypot(H, v) + H * H * math.asinh(v / H)) / W1
    return L1 + (prim(va + W1 * L1) - prim(va)) / EA1


def table1_job(model: str) -> str:
    """A held box with one Table 1 line: fairlead 4 m below the water, anchor 707.107 m below and out,
    seabed 2000 m down; the pretension is Table 1's fairlead tension. The ice lies far away."""
    H, va = irvine_table1()
    pretension = math.hypot(H, va + W1 * L1)
    return f"""\
[run]
duration = 0.001
dt = 1.0e-4
snapshots = 0
[water]
depth = 2000.0
[ice]
length = 3.0
width = 3.0
origin = [-300.0, 0.0]
youngs_modulus = 1.0e9
flexural_strength = 0.5e6
compressive_strength = 2.0e6
[[bodies]]
name = "held"
hull = {{type = "box", size = [10.0, 10.0, 8.0]}}
mass = 4.0e5
inertia = [1.0e7, 1.0e7, 1.0e7]
position = [0.0, 0.0, 0.0]
motion = "prescribed"
velocity = [[0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]]
[[moorings]]
body = "held"
model = "{model}"
fairleads = [[5.0, 0.0, -4.0]]
headings = [0.0]
anchor_depth = {SPAN!r}
pretension = {pretension!r}
element_length = 10.0
[[moorings.segments]]
length = {L1}
ea = {EA1}
diameter = 0.1
wet_weight = {W1}
"""


@pytest.mark.parametrize("model", ["quasi_static", "dem"])
def test_table1_with_a_midwater_anchor(model):
    """The job's layout puts the anchor 707.107 m out, and the line starts in Table 1's state in both
    models: H, fairlead and anchor tensions and stretched length within 0.1 %. (Before issue 13 the
    seabed was taken at the anchor: quasi-static H = 149 kN, the DEM line started at 1211 kN.)"""
    from pice.platform.build import build_platform, hulls_from_job

    H, va = irvine_table1()
    top, bottom = math.hypot(H, va + W1 * L1), math.hypot(H, va)
    job = job_from_text(table1_job(model))
    platform = build_platform(job, hulls_from_job(job, default_kn=1.0e8, reach=0.5))  # as set-up builds it
    lines = platform.groups[0].lines
    fl = np.array([5.0, 0.0, -4.0])
    if model == "quasi_static":
        anchor = lines.anchors_x[0]
        state = lines.states[0]
        assert not state.touches_seabed
        pts = lines.polylines(points_per_segment=2000)[0]
    else:
        anchor = lines.x[lines.anchors[0]]
        pts = lines.x
        assert pts[:, 2].min() > -2000.0 + 100.0  # clear of the seabed
    assert anchor[0] - fl[0] == pytest.approx(SPAN, rel=1e-3)
    assert fl[2] - anchor[2] == pytest.approx(SPAN, rel=1e-9)
    f_top = lines.reactions(lines.fairleads)[0]
    f_bottom = lines.reactions(lines.anchors)[0] if model == "dem" else lines.anchor_pull[0]
    assert abs(f_top[0]) == pytest.approx(H, rel=1e-3)
    assert np.linalg.norm(f_top) == pytest.approx(top, rel=1e-3)
    assert np.linalg.norm(f_bottom) == pytest.approx(bottom, rel=1e-3)
    length = float(np.sum(np.linalg.norm(np.diff(pts, axis=0), axis=1)))
    assert length == pytest.approx(stretched_length(H, va), rel=1e-3)
    assert length > 1.3 * L1  # the strongly elastic line of Table 1


def shoot(H, v0, length, ea=5.0e8, w=1.0e3):
    """(dx, dz, V at the end) of the cable ODE over ``length`` of unstretched arc from V = v0."""
    def rhs(s, y):
        T = math.hypot(H, y[2])
        k = 1.0 / T + 1.0 / ea
        return [H * k, y[2] * k, w]
    sol = solve_ivp(rhs, (0.0, length), [0.0, 0.0, v0], rtol=1e-12, atol=1e-9, method="DOP853")
    return sol.y[:, -1]


def test_grounded_line_from_an_anchor_above_the_seabed():
    """600 m of line (1 kN/m, EA 5e8 N), anchor 40 m above the seabed, fairlead 500 m across and 200 m
    up: it leaves the anchor downward to the seabed (the descent reaches exactly 40 m down where V
    = 0), lies on it at tension H, and rises to the fairlead: the ODE through the three pieces meets
    the fairlead within 1e-6 of the span; the profile lies on the seabed along the grounded part."""
    line = [Segment(600.0, 1.0e3, 5.0e8)]
    st = solve_line(line, horizontal=500.0, vertical=200.0, anchor_height=40.0)
    H, va = st.horizontal_tension, st.anchor_vertical
    assert st.touches_seabed and va < 0.0
    descent = -va / 1.0e3
    x1, z1, v1 = shoot(H, va, descent)
    assert z1 == pytest.approx(-40.0, abs=1e-6 * 600) and abs(v1) < 1e-6 * H
    x2 = st.grounded_length * (1.0 + H / 5.0e8)
    x3, z3, v3 = shoot(H, 0.0, 600.0 - descent - st.grounded_length)
    assert x1 + x2 + x3 == pytest.approx(500.0, abs=1e-6 * 600)
    assert z1 + z3 == pytest.approx(200.0, abs=1e-6 * 600)
    assert v3 == pytest.approx(st.fairlead_vertical, rel=1e-8)
    prof = profile(line, st, 200)
    assert prof[:, 2].min() == pytest.approx(-40.0, abs=1e-9)
    on_bed = np.abs(prof[:, 2] + 40.0) < 1e-9
    assert np.ptp(prof[on_bed, 1]) == pytest.approx(x2, rel=1e-9)
    # the seabed at the anchor (the old assumption) gives another line: the anchor height matters
    assert solve_line(line, horizontal=500.0, vertical=200.0).horizontal_tension != pytest.approx(H, rel=0.01)


def test_dem_line_starts_at_the_pretension_over_a_seabed_10m_below_the_anchor():
    """Table 5's line (Zhu & Ji 2022) from a fairlead 385 m above an anchor 10 m above the seabed, at a
    pretension (150 kN) where 31 m of it lie on the seabed: the layout and the DEM line (started on
    the layout's catenary over the real seabed, then settled) agree on the fairlead tension within
    1 % (the seabed is a penalty spring under the DEM line); the seabed at the anchor would be
    2.6 % off."""
    from pice.platform.layout import table5_segments
    from pice.platform.mooring_lines import build_lines

    segs = table5_segments()
    cat = [Segment(s.length, s.wet_weight, s.ea) for s in segs]
    x, st = anchor_distance(cat, vertical=385.0, fairlead_tension=150.0e3, anchor_height=10.0)
    assert st.grounded_length > 25.0 and st.fairlead_tension == pytest.approx(150.0e3, rel=1e-9)
    old = solve_line(cat, horizontal=x, vertical=385.0)  # the seabed at the anchor
    assert abs(old.fairlead_tension / 150.0e3 - 1.0) > 0.02
    ml = build_lines([((0.0, 0.0, -400.0), (x, 0.0, -15.0), segs)], element_length=5.0, water_density=1025.0,
                     water_level=0.0, seabed_z=-410.0, bond_damping=0.3)
    assert ml.x[:, 2].min() == pytest.approx(-410.0, abs=1e-6)  # started on the real seabed
    ml.relax(tol=1.0)
    assert ml.fairlead_tensions()[0] == pytest.approx(150.0e3, rel=0.01)
