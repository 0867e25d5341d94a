"""Quasi-static elastic catenary of a multi-segment mooring line on a flat, frictionless seabed.

The cheap mooring model (the restoring force only) and the layout tool of the spread mooring.
Segments run from the anchor (first) to the fairlead (last); each has an unstretched length L [m],
a wet weight per unit length w [N/m] and an axial stiffness EA [N]. With horizontal tension H and
vertical tension V_b at the bottom of a suspended segment (V_t = V_b + w L at its top), the spans
of the linear-elastic catenary are (Irvine, Cable Structures, 1981, Eqs. 2.26-2.27):

    x = H/w [asinh(V_t/H) - asinh(V_b/H)] + H L / EA
    z = H/w [sqrt(1 + (V_t/H)^2) - sqrt(1 + (V_b/H)^2)] + (V_b L + w L^2 / 2) / EA

Where the vertical tension would fall below zero the line lies on the seabed: the grounded length
carries the tension H (no friction) and only stretches. Given the fairlead's position relative to
the anchor, (H, V_fairlead) follow from a 2 x 2 root solve.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq, root


@dataclass(frozen=True)
class Segment:
    """One homogeneous part of a line: unstretched length [m], wet weight [N/m], axial stiffness [N]."""

    length: float
    weight: float
    ea: float


@dataclass(frozen=True)
class LineState:
    """Static solution of one line."""

    horizontal_tension: float   # H [N]
    fairlead_vertical: float    # V at the fairlead [N]
    anchor_vertical: float      # V at the anchor [N] (0 when part of the line lies on the seabed)
    grounded_length: float      # unstretched length lying on the seabed [m]

    @property
    def fairlead_tension(self) -> float:
        return math.hypot(self.horizontal_tension, self.fairlead_vertical)

    @property
    def anchor_tension(self) -> float:
        return math.hypot(self.horizontal_tension, self.anchor_vertical)

    @property
    def touches_seabed(self) -> bool:
        return self.grounded_length > 0.0


def _suspended_span(L, w, ea, H, vb):
    vt = vb + w * L
    x = H / w * (math.asinh(vt / H) - math.asinh(vb / H)) + H * L / ea
    z = H / w * (math.hypot(1.0, vt / H) - math.hypot(1.0, vb / H)) + (vb * L + 0.5 * w * L * L) / ea
    return x, z


def spans(segments: list[Segment], H: float, v_fairlead: float, seabed: bool = True):
    """(horizontal span [m], vertical span [m], anchor vertical tension [N], grounded length [m]).

    seabed=False: both ends are fixed points in the water (the line may sag below its lower end).
    """
    total_weight = sum(s.weight * s.length for s in segments)
    v_anchor = v_fairlead - total_weight
    x = z = grounded = 0.0
    if v_anchor >= 0.0 or not seabed:  # fully suspended (the line may pull the anchor up)
        v = v_anchor
        for s in segments:
            dx, dz = _suspended_span(s.length, s.weight, s.ea, H, v)
            x, z, v = x + dx, z + dz, v + s.weight * s.length
        return x, z, v_anchor, 0.0
    # walk down from the fairlead until the vertical tension reaches zero: the touchdown point
    v_top = v_fairlead
    for s in reversed(segments):
        if v_top <= 0.0:  # wholly on the seabed
            x += s.length * (1.0 + H / s.ea)
            grounded += s.length
            continue
        hanging = min(s.length, v_top / s.weight)
        vb = v_top - s.weight * hanging
        dx, dz = _suspended_span(hanging, s.weight, s.ea, H, max(vb, 0.0))
        x, z = x + dx, z + dz
        on_bed = s.length - hanging
        x += on_bed * (1.0 + H / s.ea)
        grounded += on_bed
        v_top = vb
    return x, z, 0.0, grounded


def solve_line(segments: list[Segment], *, horizontal: float, vertical: float, seabed: bool = True) -> LineState:
    """Static state of a line whose fairlead sits ``horizontal`` [m] from and ``vertical`` [m] above its anchor.

    seabed=False for a line between two fixed points with no seabed below (Table 1 of Zhu & Ji 2022).
    """
    total_length = sum(s.length for s in segments)
    total_weight = sum(s.weight * s.length for s in segments)
    if math.hypot(horizontal, vertical) <= 0.0:
        raise ValueError("the fairlead coincides with the anchor")
    slack_guess = vertical < total_length and horizontal < total_length
    h0 = max(0.1 * total_weight, 1.0)
    v0 = min(total_weight, 0.5 * total_weight + h0 * vertical / max(horizontal, 1e-9)) if slack_guess else total_weight

    def residual(u):
        H, V = math.exp(u[0]), u[1]  # H > 0 by construction
        x, z, _, _ = spans(segments, H, V, seabed)
        return [(x - horizontal) / total_length, (z - vertical) / total_length]

    best = None
    for scale in (1.0, 0.1, 10.0, 100.0, 0.01):
        sol = root(residual, [math.log(h0 * scale), v0], method="hybr", options={"xtol": 1e-13})
        if sol.success and max(abs(r) for r in residual(sol.x)) < 1e-10:
            best = sol
            break
    if best is None:
        raise ValueError(f"no static equilibrium found for a fairlead at ({horizontal:g}, {vertical:g}) m "
                         "from the anchor: the line may be too short for that position")
    H, V = math.exp(best.x[0]), float(best.x[1])
    _, _, va, grounded = spans(segments, H, V, seabed)
    return LineState(horizontal_tension=H, fairlead_vertical=V, anchor_vertical=va, grounded_length=grounded)


def anchor_distance(segments: list[Segment], *, vertical: float, fairlead_tension: float) -> tuple[float, LineState]:
    """Horizontal anchor-fairlead distance [m] giving the required fairlead tension [N] (the layout solve)."""
    total_length = sum(s.length for s in segments)

    def excess(x):
        return solve_line(segments, horizontal=x, vertical=vertical).fairlead_tension - fairlead_tension

    # nearer than (length - height) the slack would have to pile up on the seabed: no catenary
    lo = max(total_length - vertical, 1e-3 * total_length) * 1.001
    while True:
        try:
            low_excess = excess(lo)
            break
        except ValueError:
            lo *= 1.01
    if low_excess > 0.0:
        raise ValueError(f"a fairlead tension of {fairlead_tension:g} N is below the slackest static state "
                         f"({fairlead_tension + low_excess:g} N) of this line at {vertical:g} m height")
    hi = total_length  # a stretched line can reach further; widen until the tension is exceeded
    while excess(hi) < 0.0:
        hi *= 1.05
    x = brentq(excess, lo, hi, xtol=1e-9 * total_length, rtol=1e-14)
    return x, solve_line(segments, horizontal=x, vertical=vertical)


def strain_energy(segments: list[Segment], state: LineState) -> float:
    """Elastic energy [J] a line stores in its static state: the integral of T^2 / (2 EA) over the
    unstretched arc length (linear elastic, T = EA x strain). Walks from the anchor as ``profile``:
    a grounded length carries H; along a suspended one V = V_b + w s, so it adds
    (H^2 L + ((V_b + w L)^3 - V_b^3) / (3 w)) / (2 EA)."""
    H = state.horizontal_tension
    v = state.anchor_vertical
    ground = state.grounded_length
    energy = 0.0
    for seg in segments:
        on_bed = min(seg.length, ground)
        ground -= on_bed
        v_top = v + seg.weight * (seg.length - on_bed)
        energy += (H * H * seg.length + (v_top ** 3 - v ** 3) / (3.0 * seg.weight)) / (2.0 * seg.ea)
        v = v_top
    return energy


def profile(segments: list[Segment], state: LineState, points_per_segment: int = 50) -> np.ndarray:
    """(n, 4) rows (unstretched arc length from the anchor [m], x [m], z [m], tension [N]) along the line.

    Walks from the anchor: grounded parts first (tension H, on z = 0), then the suspended catenary.
    """
    H = state.horizontal_tension
    rows = [(0.0, 0.0, 0.0, state.anchor_tension)]
    s = x = z = 0.0
    v = state.anchor_vertical
    ground = state.grounded_length
    for seg in segments:
        on_bed = min(seg.length, ground)
        ground -= on_bed
        if on_bed > 0.0:
            s, x = s + on_bed, x + on_bed * (1.0 + H / seg.ea)
            rows.append((s, x, 0.0, H))
        hanging = seg.length - on_bed
        if hanging > 0.0:
            for t in np.linspace(0.0, hanging, points_per_segment + 1)[1:]:
                dx, dz = _suspended_span(t, seg.weight, seg.ea, H, v)
                rows.append((s + t, x + dx, z + dz, math.hypot(H, v + seg.weight * t)))
            dx, dz = _suspended_span(hanging, seg.weight, seg.ea, H, v)
            s, x, z, v = s + hanging, x + dx, z + dz, v + seg.weight * hanging
    return np.asarray(rows)
