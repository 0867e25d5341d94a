"""Towed-line test of Zhu & Ji (2022), section 2.3 and Table 2, in CI: pice/scenes/towed_line.py for
10, 20 and 40 elements (top end in surge, 75 mm amplitude, 1.58 s period, fresh water; statistics
over the last three of six periods) against the static elastic catenary, and its plot.

References (pice.scenes.towed_line.static_reference, pice.platform.catenary.solve_line on a rigid,
frictionless tank floor; checked here against Irvine's elastic catenary with a grounded part,
written out in this file), for Table 2's line (wet weight w = 1.381 N/m, 10.09 N in water):
  T_static = 5.892 N   top tension with the top at its mean position (6.97 m, 1.2 m);
  T_qs     = 6.271 N   cycle mean of the static top tension as the top moves 6.97 +- 0.075 m;
  dz_qs    = 154.1 mm  vertical range of the point 0.8 m from the top between the static shapes
                       at the two extreme top positions.
Measured (this machine): T_rest 5.714 / 5.844 N, T_mean 6.001 / 6.020 N, T_min 0.54 / 1.58 N,
T_max 28.52 / 13.72 N, marker range 143.6 / 147.6 mm for 10 / 20 elements; about 15 s in all
(with compilation and the 40-element line), so not marked slow.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import fsolve

from pice.platform.catenary import Segment, solve_line
from pice.postproc.towed_line import plot_towed_line
from pice.scenes.towed_line import AMP, LENGTH, TOP, line_segment, run, static_reference

ELEMENTS = (10, 20)
T_MAX_RECORDED = {10: 28.5, 20: 13.7}  # [N] the study's summary (benchmarks/towed_line.py --elements 10,20)


@pytest.fixture(scope="module")
def study():
    return {n: run(n) for n in ELEMENTS}, static_reference()


def discretisation_bound(n: int) -> float:
    """Relative offset of the DEM top tension from the continuous catenary's: the top element carries
    the line's tension about half an element below the top, lower by the half element's weight
    w L / (2 n) times V/T (the vertical share at the top): 5.9 % at 10, 3.0 % at 20 elements."""
    seg = line_segment()
    st = solve_line([Segment(seg.length, seg.wet_weight, seg.ea)], horizontal=6.97, vertical=1.2)
    return seg.wet_weight * LENGTH / (2 * n) * st.fairlead_vertical / st.fairlead_tension ** 2


def grounded_catenary_tension(X: float, Z: float) -> float:
    """Top tension [N] of the line (line_segment) from its anchor on a rigid frictionless floor to a top
    X [m] away and Z [m] above, solved here from Irvine (Cable Structures, 1981, Eqs. 2.26-2.27):
    a length L - L_s lies on the floor at the horizontal tension H (stretched by H (L - L_s) / EA),
    the suspended L_s leaves it with no vertical tension:
        x = (L - L_s)(1 + H/EA) + H/w asinh(w L_s / H) + H L_s / EA,
        z = H/w (sqrt(1 + (w L_s / H)^2) - 1) + w L_s^2 / (2 EA),
    and the top tension is sqrt(H^2 + (w L_s)^2)."""
    seg = line_segment()
    w, ea, L = seg.wet_weight, seg.ea, seg.length

    def miss(u):
        H, Ls = u
        x = (L - Ls) * (1 + H / ea) + H / w * math.asinh(w * Ls / H) + H * Ls / ea
        z = H / w * (math.hypot(1.0, w * Ls / H) - 1.0) + w * Ls * Ls / (2.0 * ea)
        return [x - X, z - Z]

    H, Ls = fsolve(miss, [3.0, 4.0], xtol=1e-10)
    assert 0.0 < Ls < L and np.allclose(miss([H, Ls]), 0.0, atol=1e-10)  # part of the line on the floor
    return math.hypot(H, w * Ls)


def test_static_references_are_the_elastic_catenary_on_the_floor(study):
    """The references the DEM line is held to: T_static and T_qs (the mean over 400 phases of the
    surge) from pice's catenary solve equal Irvine's grounded elastic catenary solved here within
    1e-9, and the numbers quoted above (5.892 N, 6.271 N, 154.1 mm) to their last digit."""
    _, ref = study
    assert ref["t_static"] == pytest.approx(grounded_catenary_tension(TOP[0], TOP[2]), rel=1e-9)
    phases = 2 * math.pi * np.arange(400) / 400
    t_qs = np.mean([grounded_catenary_tension(TOP[0] + AMP * math.sin(ph), TOP[2]) for ph in phases])
    assert ref["t_qs_mean"] == pytest.approx(t_qs, rel=1e-9)
    assert ref["t_static"] == pytest.approx(5.892, abs=5e-4)
    assert ref["t_qs_mean"] == pytest.approx(6.271, abs=5e-4)
    assert ref["z_qs_range"] == pytest.approx(0.1541, abs=5e-5)


def test_towed_line_plot_is_a_png(study, tmp_path):
    """--plot's figure (both element counts, tension and marker traces) is written as a PNG."""
    results, _ = study
    out = tmp_path / "towed.png"
    plot_towed_line([results[n] for n in ELEMENTS], out)
    assert out.is_file() and out.stat().st_size > 0
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_towed_line_at_rest_matches_the_static_catenary(study):
    """After 2 s at rest (before the surge) the DEM top tension equals the static elastic catenary
    tension T_static within the discretisation bound (5.9 % at 10, 3.0 % at 20 elements; measured
    -3.0 % and -0.8 %): the DEM line's statics converge to Irvine's catenary."""
    results, ref = study
    for n in ELEMENTS:
        assert results[n]["t_rest"] == pytest.approx(ref["t_static"], rel=discretisation_bound(n))


def test_towed_line_mean_tension_matches_the_static_catenary(study):
    """The mean top tension over the last three periods agrees with the static tension at the mean top
    position, T_static, within -delta_n .. +6.4 % (measured +1.9 % and +2.2 %). Lower limit: T(x) is
    convex, so a cycle mean lies above T at the mean position (Jensen), less the DEM's discretisation
    offset delta_n (discretisation_bound). Upper limit: T_qs, the cycle mean of a line that follows
    the surge quasi-statically (+6.4 %); drag and inertia smooth the slack-taut swing of the dynamic
    line and keep its mean below that."""
    results, ref = study
    for n in ELEMENTS:
        t_mean = results[n]["t_mean"]
        assert ref["t_static"] * (1 - discretisation_bound(n)) <= t_mean <= ref["t_qs_mean"], (n, t_mean, ref)


def test_towed_line_tension_range_shrinks_with_refinement(study):
    """The tension peaks are snap spikes at the slack phase (top moving towards the anchor, T_min
    0.5-1.6 N) whose size falls with the lumped node mass (L / n): they shrink with refinement and
    are gone by 40 elements (benchmark: T_max 9.13 N at 40, 9.04 N at 80, against 9.01 N for the
    static line at the far top position; the last test here checks 40). Here the range
    max - min over the last three periods at 20 elements is below 0.6 of the 10-element one
    (measured 0.43), and T_max matches the study's recorded 28.5 -> 13.7 N within 10 % (measured
    28.52 and 13.72 N; the margin is for other CPUs and compilers: the impact of single nodes is
    sensitive to rounding)."""
    results, _ = study
    span = {n: results[n]["t_max"] - results[n]["t_min"] for n in ELEMENTS}
    assert span[20] < 0.6 * span[10]
    for n in ELEMENTS:
        assert results[n]["t_max"] == pytest.approx(T_MAX_RECORDED[n], rel=0.10)


def test_towed_line_marker_follows_the_static_shapes(study):
    """At the 1.58 s period the line's shape nearly follows its static shapes: the vertical range of
    the point 0.8 m from the top lies within 10 % of dz_qs = 154.1 mm, the range between the static
    catenaries at the two extreme top positions (measured -6.8 % and -4.2 %; drag and inertia lag
    can only reduce it; the paper's DEM marker motion was within 8 % of the experiment), and 10 and
    20 elements agree within 5 % (measured 2.8 %)."""
    results, ref = study
    for n in ELEMENTS:
        assert results[n]["z_range"] == pytest.approx(ref["z_qs_range"], rel=0.10)
    assert results[10]["z_range"] == pytest.approx(results[20]["z_range"], rel=0.05)


def test_towed_line_tension_follows_the_quasi_static_envelope(study):
    """Issue 4 towed test (Table 2 of Zhu & Ji 2022; benchmarks/towed_line.py prints the full study).
    Reference: the quasi-static elastic catenary (pice.platform.catenary) at the top end's mean and far
    positions. At 1.58 s the motion is slow for the line's statics but drag adds a little: the mean top
    tension over the last three periods lies within 5 % of the static tension at the mean position,
    the peak within 5 % of the static tension at the far extreme (+75 mm); the marker 0.8 m from the
    top moves the same with 20 and 40 elements within 2 % (converged)."""
    results, _ = study
    seg = line_segment()
    line = [Segment(seg.length, seg.wet_weight, seg.ea)]
    static_mean = solve_line(line, horizontal=TOP[0], vertical=TOP[2]).fairlead_tension
    static_far = solve_line(line, horizontal=TOP[0] + AMP, vertical=TOP[2]).fairlead_tension
    r20, r40 = results[20], run(40)
    assert r40["t_mean"] == pytest.approx(static_mean, rel=0.05)
    assert r40["t_max"] == pytest.approx(static_far, rel=0.05)
    assert r40["t_min"] > 0.0  # the top stays loaded
    assert r20["z_range"] == pytest.approx(r40["z_range"], rel=0.02)
