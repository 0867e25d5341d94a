"""Quasi-static elastic catenary (pice.platform.catenary) against an independent shooting solution.

Reference: the equilibrium ODE of a linear-elastic cable along its unstretched arc length s,
    dx/ds = H (1/T + 1/EA),  dz/ds = V (1/T + 1/EA),  dV/ds = w,  T = sqrt(H^2 + V^2),
integrated numerically (scipy solve_ivp, rtol 1e-12) and shot to the fairlead; a grounded part lies
straight on the seabed with tension H. Tolerances 1e-6 relative: both are exact up to the ODE
integration error (~1e-10) and the root solves (~1e-12).
"""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq, fsolve

from pice.platform.catenary import Segment, anchor_distance, profile, solve_line, strain_energy

pytestmark = pytest.mark.nojit

TABLE1 = [Segment(length=1026.0, weight=2.0e3, ea=2052.0e3)]  # Table 1 of Zhu & Ji (2022)
TABLE5 = [Segment(20.0, 0.43e3, 675.0e6), Segment(250.0, 0.23e3, 900.2e6), Segment(190.0, 0.52e3, 700.8e6)]


def shoot(segments, H, v_start, z0=0.0):
    """Integrate the cable ODE from the lower end (s = 0) with vertical tension v_start: end (x, z, V)."""
    x, z, v = 0.0, z0, v_start
    for seg in segments:
        def rhs(s, y, seg=seg):
            V = y[2]
            T = math.hypot(H, V)
            k = 1.0 / T + 1.0 / seg.ea
            return [H * k, V * k, seg.weight]
        sol = solve_ivp(rhs, (0.0, seg.length), [x, z, v], rtol=1e-12, atol=1e-9, method="DOP853")
        x, z, v = sol.y[:, -1]
    return x, z, v


def test_table1_catenary_between_two_fixed_points():
    """Table 1: ends 1000 m apart on a 45-degree slope, L = 1026 m, w = 2 kN/m, EA = 2052 kN."""
    X = Z = 1000.0 * math.cos(math.pi / 4)
    st = solve_line(TABLE1, horizontal=X, vertical=Z, seabed=False)

    def miss(u):
        x, z, _ = shoot(TABLE1, u[0], u[1])
        return [x - X, z - Z]

    H, va = fsolve(miss, [st.horizontal_tension * 1.1, st.anchor_vertical * 0.9], xtol=1e-13)
    assert st.horizontal_tension == pytest.approx(H, rel=1e-6)
    assert st.anchor_tension == pytest.approx(math.hypot(H, va), rel=1e-6)
    assert st.fairlead_tension == pytest.approx(math.hypot(H, va + 2.0e3 * 1026.0), rel=1e-6)
    # the shape: profile points against the ODE at the same arc lengths, within 1e-6 of the span
    prof = profile(TABLE1, st)
    for s_, x_, z_, t_ in prof[::10]:
        if s_ == 0:
            continue
        x, z, v = shoot([Segment(s_, 2.0e3, 2052.0e3)], H, va)
        assert abs(x - x_) < 1e-6 * 1000 and abs(z - z_) < 1e-6 * 1000
        assert t_ == pytest.approx(math.hypot(H, v), rel=1e-6)
    # the strongly elastic line (EA = w L) stretches a lot: its stretched length exceeds L by > 30 %
    stretched = np.sum(np.hypot(np.diff(prof[:, 1]), np.diff(prof[:, 2])))
    assert stretched > 1.3 * 1026.0


def test_inextensible_limit_is_the_classic_catenary():
    """EA -> infinity between two points at equal height: L = 2 H/w sinh(w X / 2H), sag H/w (cosh - 1)."""
    w, X = 1000.0, 100.0
    L = 120.0
    line = [Segment(L, w, 1e16)]
    st = solve_line(line, horizontal=X, vertical=0.0, seabed=False)
    H = brentq(lambda h: 2 * h / w * math.sinh(w * X / (2 * h)) - L, w * X / 600.0, 1e9, xtol=1e-12)
    assert st.horizontal_tension == pytest.approx(H, rel=1e-8)
    sag = -profile(line, st, 400)[:, 2].min()
    assert sag == pytest.approx(H / w * (math.cosh(w * X / (2 * H)) - 1.0), rel=1e-5)


def test_line_resting_on_the_seabed():
    """A slack line: the grounded part is straight at tension H, the rest a catenary from V = 0."""
    line = [Segment(600.0, 1.0e3, 5.0e8)]
    st = solve_line(line, horizontal=500.0, vertical=200.0)
    assert st.touches_seabed and st.anchor_vertical == 0.0
    hanging = 600.0 - st.grounded_length
    x_bed = st.grounded_length * (1 + st.horizontal_tension / 5.0e8)
    x, z, v = shoot([Segment(hanging, 1.0e3, 5.0e8)], st.horizontal_tension, 0.0)
    assert x_bed + x == pytest.approx(500.0, rel=1e-6)
    assert z == pytest.approx(200.0, rel=1e-6)
    assert st.fairlead_vertical == pytest.approx(v, rel=1e-9)
    # the solution is continuous across touchdown: a taut line has no grounded length
    taut = solve_line(line, horizontal=560.0, vertical=200.0)
    assert not taut.touches_seabed


def test_spread_mooring_layout_reaches_the_pretension():
    """Issue 4 layout solve: the 3-segment line of Table 5, fairlead 385 m above the anchor, pretension
    221.7 kN (Zhu & Ji 2022, section 4.1). The anchor distance found gives that fairlead tension, and
    the ODE through the same anchor and fairlead agrees. With Table 5's wet weights (165 kN in all)
    the line hangs clear of the seabed at this pretension (finding reported in the issue note)."""
    x, st = anchor_distance(TABLE5, vertical=385.0, fairlead_tension=221.7e3)
    assert st.fairlead_tension == pytest.approx(221.7e3, rel=1e-9)
    xs, zs, vs = shoot(TABLE5, st.horizontal_tension, st.anchor_vertical)
    assert xs == pytest.approx(x, rel=1e-7) and zs == pytest.approx(385.0, rel=1e-7)
    assert not st.touches_seabed and st.anchor_vertical > 0.0
    assert 200.0 < x < 260.0


def test_strain_energy_is_the_integral_of_t_squared_over_2ea():
    """catenary.strain_energy (closed form) against the ODE quadrature of dE/ds = T^2 / (2 EA) along
    the unstretched arc length (solve_ivp, rtol 1e-12), within 1e-9: Table 1 between fixed points
    (V changes sign along the line), Table 5's three segments hanging free, and a line resting on the
    seabed, whose grounded part adds H^2 L_g / (2 EA) (tension H along it)."""
    def quadrature(segments, H, v_start):
        energy, v = 0.0, v_start
        for seg in segments:
            def rhs(s, y, seg=seg):
                V = v + seg.weight * s
                return [(H * H + V * V) / (2.0 * seg.ea)]
            energy += solve_ivp(rhs, (0.0, seg.length), [0.0], rtol=1e-12, atol=1e-12, method="DOP853").y[0, -1]
            v += seg.weight * seg.length
        return energy

    X = Z = 1000.0 * math.cos(math.pi / 4)
    st = solve_line(TABLE1, horizontal=X, vertical=Z, seabed=False)
    assert st.anchor_vertical < 0.0 < st.fairlead_vertical
    assert strain_energy(TABLE1, st) == pytest.approx(quadrature(TABLE1, st.horizontal_tension, st.anchor_vertical),
                                                      rel=1e-9)
    _, st = anchor_distance(TABLE5, vertical=385.0, fairlead_tension=221.7e3)
    assert strain_energy(TABLE5, st) == pytest.approx(quadrature(TABLE5, st.horizontal_tension, st.anchor_vertical),
                                                      rel=1e-9)
    line = [Segment(600.0, 1.0e3, 5.0e8)]
    st = solve_line(line, horizontal=500.0, vertical=200.0)
    H, grounded = st.horizontal_tension, st.grounded_length
    assert grounded > 0.0
    ref = H * H * grounded / (2.0 * 5.0e8) + quadrature([Segment(600.0 - grounded, 1.0e3, 5.0e8)], H, 0.0)
    assert strain_energy(line, st) == pytest.approx(ref, rel=1e-9)


@pytest.mark.filterwarnings("error")
@pytest.mark.parametrize("ea, tension", [(1.0, 1.0e300), (1e-300, 5.0e3), (1e20, 1.0e7)])
def test_extreme_lines_fail_fast_and_quietly(ea, tension, monkeypatch):
    """Issue 13, case 3: lines the catenary can hardly hold (EA = 1 N and 1e-300 N under 10 kN of
    their own weight; EA = 1e20 N, too stiff for a tension of 1e7 N to be resolved in double
    precision), at fairlead tensions up to 1e300 N: the layout solve either gives the tension asked
    for or raises ValueError (LayoutError) with a one-line reason, with no OverflowError and no
    RuntimeWarning (they are errors here), after a bounded number of line evaluations (at most
    100,000; measured ~55,000, under 3 s, when every fallback is exhausted; 29 for a sound line)."""
    from pice.platform import catenary

    calls = []
    spans = catenary.spans
    monkeypatch.setattr(catenary, "spans", lambda *a: calls.append(1) or spans(*a))
    line = [Segment(100.0, 100.0, ea)]
    try:
        _, st = anchor_distance(line, vertical=48.0, fairlead_tension=tension, anchor_height=2.0)
    except ValueError as exc:
        assert str(exc) and "\n" not in str(exc)
    else:
        assert st.fairlead_tension == pytest.approx(tension, rel=1e-6)
    with pytest.raises(ValueError, match="no static equilibrium"):
        solve_line(line, horizontal=1.0e300, vertical=48.0)
    assert 0 < len(calls) < 100_000
