"""The towed-line test of Zhu & Ji (2022), section 2.3 and Table 2: a model mooring line whose top
end surges, as a DEM line (pice.platform.mooring_lines) beside its static elastic catenary.

Line 7.305 m, dry mass 0.162 kg/m, diameter 5.2 mm, E = 77.2 GPa, the top 1.2 m above and 6.97 m
from the anchor on the tank floor, in fresh water; the top surges with 75 mm amplitude and a 1.58 s
period, ramped in over the first period. ``run(n)`` tows the line of ``n`` elements and returns its
traces and statistics over the last three periods; ``static_reference()`` gives the static elastic
catenary references. benchmarks/towed_line.py prints the study (and plots it with
pice.postproc.towed_line); tests/physics/test_towed_line.py checks it.
"""

from __future__ import annotations

import math
import time

import numpy as np

from ..platform.catenary import Segment, profile, solve_line
from ..platform.mooring_lines import LineSegment, build_lines

LENGTH, DRY, D, E = 7.305, 0.162, 0.0052, 77.2e9  # [m], dry mass [kg/m], diameter [m], Young's modulus [Pa]
RHO = 1000.0                       # fresh water [kg/m^3]
AMP, PERIOD = 0.075, 1.58          # surge of the top end: amplitude [m], period [s]
TOP = np.array([6.97, 0.0, 1.2])   # mean top position [m] (anchor at the origin on the tank floor)


def surge(t: float):
    """Top-end position [m] and velocity [m/s]: 75 mm, 1.58 s, ramped in over the first period
    (a half-cosine ramp: no velocity jump at the start)."""
    w = 2 * math.pi / PERIOD
    ramp, dramp = (0.5 - 0.5 * math.cos(math.pi * t / PERIOD), 0.5 * math.pi / PERIOD * math.sin(math.pi * t / PERIOD)) \
        if t < PERIOD else (1.0, 0.0)
    x = AMP * ramp * math.sin(w * t)
    v = AMP * (dramp * math.sin(w * t) + ramp * w * math.cos(w * t))
    return TOP + np.array([x, 0.0, 0.0]), np.array([v, 0.0, 0.0])


def line_segment() -> LineSegment:
    """Table 2's line for the DEM model (drag and added-mass coefficients: assumptions)."""
    area = math.pi * D * D / 4
    return LineSegment(length=LENGTH, ea=E * area, diameter=D, wet_weight=(DRY - RHO * area) * 9.81,
                       dry_mass=DRY, drag_normal=1.2, drag_tangential=0.01, added_mass=1.0)


def static_reference(samples: int = 400) -> dict:
    """Static elastic catenary references (pice.platform.catenary, rigid frictionless tank floor):

    t_static   top tension [N] with the top at its mean position TOP (the line at rest);
    t_qs_mean  the cycle mean of the static top tension as the top moves through x = 6.97 + 0.075 sin
               (a line following the surge quasi-statically; above t_static, T(x) being convex);
    z_qs_range vertical range [m] of the point 0.8 m (unstretched) from the top between the static
               shapes at the two extreme top positions.
    """
    seg = line_segment()
    cat = [Segment(seg.length, seg.wet_weight, seg.ea)]

    def state(dx):
        return solve_line(cat, horizontal=TOP[0] + dx, vertical=TOP[2])

    phases = 2 * math.pi * np.arange(samples) / samples
    z_mark = [np.interp(LENGTH - 0.8, *profile(cat, state(dx), 400)[:, [0, 2]].T) for dx in (-AMP, AMP)]
    return {"t_static": state(0.0).fairlead_tension,
            "t_qs_mean": float(np.mean([state(AMP * math.sin(p)).fairlead_tension for p in phases])),
            "z_qs_range": abs(z_mark[1] - z_mark[0])}


def run(elements: int, periods: int = 6, outer_dt: float = 1e-3) -> dict:
    """Tow the DEM line with ``elements`` elements for ``periods`` periods after 2 s at rest.

    Returns the traces t [s], tension (top) [N], z (marker 0.8 m from the top) [m]; over the last
    three periods t_min, t_max, t_mean [N], z_range [m]; t_rest [N], the top tension at the end of
    the 2 s at rest; the sub-step dt [s] and the wall time [s] of the towed part.
    """
    seg = line_segment()
    ml = build_lines([((0.0, 0.0, 0.0), TOP, [seg])], element_length=LENGTH / elements, water_density=RHO,
                     water_level=1.3, seabed_z=0.0, bond_damping=0.2, seabed_stiffness=2.0e3,
                     seabed_friction=0.3)
    dt = 0.5 * ml.stable_step()
    nsub = max(1, math.ceil(outer_dt / dt))
    dt = outer_dt / nsub
    # arc-length position of the marker 0.8 m from the top: interpolate between the nodes
    s_nodes = np.linspace(0.0, LENGTH, len(ml.x))
    s_mark = LENGTH - 0.8
    k = int(np.searchsorted(s_nodes, s_mark)) - 1
    frac = (s_mark - s_nodes[k]) / (s_nodes[k + 1] - s_nodes[k])
    ml.advance(dt, round(2.0 / dt))  # settle from the static shape (2 s at rest)
    t_rest = float(ml.fairlead_tensions()[0])
    steps = round(periods * PERIOD / outer_dt)
    t_hist, tension, z_mark = np.empty(steps), np.empty(steps), np.empty(steps)
    t0 = time.perf_counter()
    for n in range(steps):
        t = (n + 1) * outer_dt
        xf, vf = surge(t)
        ml.advance(dt, nsub, xf[None, :], vf[None, :])
        t_hist[n] = t
        tension[n] = ml.fairlead_tensions()[0]
        z_mark[n] = (1 - frac) * ml.x[k, 2] + frac * ml.x[k + 1, 2]
    wall = time.perf_counter() - t0
    last = t_hist > (periods - 3) * PERIOD
    return {"elements": elements, "dt": dt, "wall": wall, "t": t_hist, "tension": tension, "z": z_mark,
            "t_rest": t_rest, "t_min": float(tension[last].min()), "t_max": float(tension[last].max()),
            "t_mean": float(tension[last].mean()), "z_range": float(np.ptp(z_mark[last]))}
