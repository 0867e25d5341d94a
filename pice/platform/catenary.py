"""Quasi-static elastic catenary of a multi-segment mooring line over a flat, frictionless seabed.

The cheap mooring model (the restoring force only) and the layout tool of the spread mooring.
Segments run from the anchor (first) to the fairlead (last); each has an unstretched length L [m],
a wet weight per unit length w [N/m] and an axial stiffness EA [N]. With horizontal tension H and
vertical tension V_b at the bottom of a suspended segment (V_t = V_b + w L at its top), the spans
of the linear-elastic catenary are (Irvine, Cable Structures, 1981, Eqs. 2.26-2.27):

    x = H/w [asinh(V_t/H) - asinh(V_b/H)] + H L / EA
    z = H/w [sqrt(1 + (V_t/H)^2) - sqrt(1 + (V_b/H)^2)] + (V_b L + w L^2 / 2) / EA

The seabed lies ``anchor_height`` [m] below the anchor (0: the anchor sits on it; an anchor on a
seamount or a line tested in mid-water, as Table 1 of Zhu & Ji 2022, lies above it). Where the
free-hanging line would dip below the seabed it lies on it instead: it leaves the anchor downward
(when the anchor is above the seabed) to the touchdown point, where its vertical tension is zero,
lies straight on the seabed carrying H (no friction; it only stretches), and rises from the second
touchdown point to the fairlead. Given the fairlead's position relative to the anchor, (H,
V_fairlead) follow from a 2 x 2 root solve; every solve here has a bounded number of iterations
and raises ValueError (never an overflow or a flood of warnings) when it finds no equilibrium.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq, root

MAX_EVALUATIONS = 400   # residual evaluations of one root solve of a line (scipy's hybr maxfev)
MAX_BRACKET_STEPS = 200  # widening steps of a bracket (the layout solve: 1.05^200 ~ 1.7e4 of its start)
_HUGE = 1.0e30           # the residual of a trial state that overflows: far from any solution
MAX_REACH = 1.0e3        # the layout solve looks for anchors within this many line lengths


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
    anchor_vertical: float      # V at the anchor [N] (> 0 the line rises from it; 0 when it starts on the
                                # seabed; < 0 it leaves the anchor downward)
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


def _parts(segments, lo: float, hi: float, reverse: bool = False):
    """(segment, length [m]) of each segment's share of the unstretched arc [lo, hi] from the anchor."""
    out, start = [], 0.0
    for s in segments:
        a, b = max(lo, start), min(hi, start + s.length)
        if b > a:
            out.append((s, b - a))
        start += s.length
    return reversed(out) if reverse else out


def _hang(segments, lo: float, hi: float, H: float, v: float, reverse: bool = False):
    """(horizontal, vertical) span [m] of the suspended arc [lo, hi], walked from ``lo`` upward with
    vertical tension ``v`` [N] there, or (``reverse``) from ``hi`` down to ``lo`` with |V| = ``v`` at
    ``hi`` growing downward: the mirror image of a piece whose tension is zero at its upper end."""
    x = z = 0.0
    for s, length in _parts(segments, lo, hi, reverse):
        dx, dz = _suspended_span(length, s.weight, s.ea, H, v)
        x, z, v = x + dx, z + dz, v + s.weight * length
    return x, z


def _arc_at_weight(segments, weight: float) -> float:
    """Unstretched arc length from the anchor [m] below which the line weighs ``weight`` [N]."""
    s = 0.0
    for seg in segments:
        if weight <= seg.weight * seg.length:
            return s + weight / seg.weight
        weight -= seg.weight * seg.length
        s += seg.length
    return s


def spans(segments: list[Segment], H: float, v_fairlead: float, seabed: bool = True, anchor_height: float = 0.0):
    """(horizontal span [m], vertical span [m], anchor vertical tension [N], grounded length [m]).

    seabed=False: both ends are fixed points in the water (the line may sag below its lower end);
    anchor_height [m]: the anchor's height above the seabed.
    """
    total = sum(s.length for s in segments)
    v_anchor = v_fairlead - sum(s.weight * s.length for s in segments)
    if v_anchor >= 0.0 or not seabed:  # fully suspended (the line may pull the anchor up)
        x, z = _hang(segments, 0.0, total, H, v_anchor)
        return x, z, v_anchor, 0.0
    low = _arc_at_weight(segments, -v_anchor)  # the free line's lowest point (V = 0)
    xf, zf = _hang(segments, low, total, H, 0.0)
    xa, za = _hang(segments, 0.0, low, H, 0.0, reverse=True)  # the anchor lies za above that point
    if za <= anchor_height:  # hangs clear of the seabed
        return xa + xf, zf - za, v_anchor, 0.0
    # on the seabed from the touchdown point below the anchor (the arc where the descent from the
    # anchor reaches the seabed) up to `low`
    touch = 0.0
    if anchor_height > 0.0:
        touch = brentq(lambda s: _hang(segments, 0.0, s, H, 0.0, reverse=True)[1] - anchor_height, 0.0, low,
                       xtol=1e-12 * total, rtol=1e-14, maxiter=200)
    xa = _hang(segments, 0.0, touch, H, 0.0, reverse=True)[0] if touch > 0.0 else 0.0
    x_bed = sum(length * (1.0 + H / s.ea) for s, length in _parts(segments, touch, low))
    hanging_weight = sum(s.weight * length for s, length in _parts(segments, 0.0, touch))
    return xa + x_bed + xf, zf - anchor_height, 0.0 - hanging_weight, low - touch


def solve_line(segments: list[Segment], *, horizontal: float, vertical: float, seabed: bool = True,
               anchor_height: float = 0.0) -> LineState:
    """Static state of a line whose fairlead sits ``horizontal`` [m] from and ``vertical`` [m] above its anchor.

    seabed=False for a line between two fixed points with no seabed below; otherwise the seabed lies
    ``anchor_height`` [m] below the anchor. Raises ValueError when no equilibrium is found within
    MAX_EVALUATIONS evaluations for each of five starting points.
    """
    total_length = sum(s.length for s in segments)
    total_weight = sum(s.weight * s.length for s in segments)
    if math.hypot(horizontal, vertical) <= 0.0:
        raise ValueError("the fairlead coincides with the anchor")
    slack_guess = vertical < total_length and horizontal < total_length
    h0 = max(0.1 * total_weight, 1.0)
    v0 = min(total_weight, 0.5 * total_weight + h0 * vertical / max(horizontal, 1e-9)) if slack_guess else total_weight

    def residual(u):
        if not (math.isfinite(u[0]) and math.isfinite(u[1])) or abs(u[0]) > 700.0:
            return [_HUGE, _HUGE]
        try:
            x, z, _, _ = spans(segments, math.exp(u[0]), u[1], seabed, anchor_height)  # H > 0 by construction
        except (OverflowError, ZeroDivisionError, ValueError):
            return [_HUGE, _HUGE]
        r = [(x - horizontal) / total_length, (z - vertical) / total_length]
        return r if math.isfinite(r[0]) and math.isfinite(r[1]) else [_HUGE, _HUGE]

    best = None
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore", RuntimeWarning)
        for scale in (1.0, 0.1, 10.0, 100.0, 0.01):
            sol = root(residual, [math.log(h0 * scale), v0], method="hybr",
                       options={"xtol": 1e-13, "maxfev": MAX_EVALUATIONS})
            if sol.success and max(abs(r) for r in residual(sol.x)) < 1e-10:
                best = (math.exp(sol.x[0]), float(sol.x[1]))
                break
        if best is None:  # a slack, very stretchy or nearly vertical line: the slower, sure way
            best = _nested_solve(segments, horizontal, vertical, seabed, anchor_height)
            if best is not None and max(abs(r) for r in residual([math.log(best[0]), best[1]])) >= 1e-9:
                best = None
    if best is None:
        raise ValueError(f"no static equilibrium found for a fairlead at ({horizontal:g}, {vertical:g}) m "
                         "from the anchor: the line may be too short for that position")
    H, V = best
    _, _, va, grounded = spans(segments, H, V, seabed, anchor_height)
    return LineState(horizontal_tension=H, fairlead_vertical=V, anchor_vertical=va, grounded_length=grounded)


def _bracket(f, lo: float, hi: float, grow):
    """(lo, hi) with f(lo) < 0 <= f(hi), widening each end with ``grow`` at most 100 times; None if
    none is found or f fails (a trial state that overflows)."""
    try:
        for _ in range(100):
            flo = f(lo)
            if flo < 0.0:
                break
            lo = grow(lo, -1)
        else:
            return None
        for _ in range(100):
            if f(hi) >= 0.0:
                return lo, hi
            hi = grow(hi, 1)
    except (OverflowError, ZeroDivisionError, ValueError):
        return None  # the residual overflows before changing sign: no bracket, the caller falls back
    return None


def _nested_solve(segments, horizontal: float, vertical: float, seabed: bool, anchor_height: float):
    """(H, V_fairlead) [N] by nested bisection, or None: for each H the fairlead's V that gives the
    vertical span (which grows with V), then the H that gives the horizontal span (which grows with
    H along that curve). Bounded: brentq's 100 iterations inside 100-step brackets."""
    weight = sum(s.weight * s.length for s in segments)
    scale = max(weight, 1.0)

    def finite(value):
        if not math.isfinite(value):
            raise ValueError("not finite")
        return value

    def v_for(H):
        dz = lambda V: finite(spans(segments, H, V, seabed, anchor_height)[1] - vertical)  # noqa: E731
        br = _bracket(dz, -scale - H, scale + H, lambda b, side: 2.0 * b if b * side > 0 else -b)
        if br is None:
            raise ValueError("no fairlead tension gives the vertical span")
        return brentq(dz, *br, xtol=1e-13 * (scale + H), rtol=1e-15, maxiter=100)

    def dx(u):
        H = math.exp(u)
        return finite(spans(segments, H, v_for(H), seabed, anchor_height)[0] - horizontal)

    u0 = math.log(scale)
    br = _bracket(dx, u0 - 2.0, u0, lambda u, side: u + 2.0 * side)
    if br is None or not (-700.0 < br[0] and br[1] < 700.0):
        return None
    try:
        u = brentq(dx, *br, xtol=1e-14, rtol=1e-15, maxiter=100)
        return math.exp(u), v_for(math.exp(u))
    except (OverflowError, ZeroDivisionError, ValueError, RuntimeError):
        return None


class LayoutError(ValueError):
    """The layout solve found no anchor distance for the fairlead tension asked for; ``limit`` [N] is
    the nearest tension the line can give (None when the catenary itself could not be solved)."""

    def __init__(self, msg: str, limit: float | None = None):
        super().__init__(msg)
        self.limit = limit


def anchor_distance(segments: list[Segment], *, vertical: float, fairlead_tension: float, seabed: bool = True,
                    anchor_height: float = 0.0) -> tuple[float, LineState]:
    """Horizontal anchor-fairlead distance [m] giving the required fairlead tension [N] (the layout solve),
    over the seabed ``anchor_height`` [m] below the anchor. Bounded (at most about 40 line solves to
    bracket it, then brentq's 100 iterations); raises LayoutError when no distance gives that tension."""
    total_length = sum(s.length for s in segments)

    def excess(x):
        return solve_line(segments, horizontal=x, vertical=vertical, seabed=seabed,
                          anchor_height=anchor_height).fairlead_tension - fairlead_tension

    def solvable(x):
        try:
            return excess(x)
        except ValueError:
            return None

    # nearer than `floor` an inextensible line's slack would pile up on the seabed (a stretchy one
    # reaches less far); no line at a tension up to T reaches beyond `reach` (stretched straight)
    floor = max(total_length - vertical - 2.0 * anchor_height if seabed else 0.0, 1e-3 * total_length) * 1.001
    stretched = min(sum(s.length * (1.0 + fairlead_tension / s.ea) for s in segments), MAX_REACH * total_length)
    reach = math.sqrt(max((stretched - vertical) * (stretched + vertical), 0.0))
    lo, low_excess = floor, solvable(floor)
    if low_excess is None:  # the nearest solvable distance: scan towards the reach, then bisect
        scan = [floor + (max(reach, 2.0 * floor) - floor) * k / 8 for k in range(1, 9)]
        found = next(((x, e) for x in scan if (e := solvable(x)) is not None), None)
        if found is None:
            raise LayoutError(f"the catenary solve found no static state of this line at {vertical:g} m height "
                              f"between {floor:.4g} m and {scan[-1]:.4g} m from the anchor")
        bad, (lo, low_excess) = floor, found
        for _ in range(30):
            mid = 0.5 * (bad + lo)
            e = solvable(mid)
            if e is None:
                bad = mid
            else:
                lo, low_excess = mid, e
    if low_excess > 0.0:
        raise LayoutError(f"a fairlead tension of {fairlead_tension:g} N is below the slackest static state "
                          f"({fairlead_tension + low_excess:g} N) of this line at {vertical:g} m height",
                          limit=fairlead_tension + low_excess)
    hi = max(reach, lo * 1.001)
    for _ in range(MAX_BRACKET_STEPS):
        e = solvable(hi)
        if e is None or e >= 0.0:  # unsolvable there: taut beyond what the tension can hold
            break
        hi *= 1.05
    else:
        raise LayoutError(f"a fairlead tension of {fairlead_tension:g} N is beyond what this line reaches "
                          f"stretched to {hi:.4g} m from the anchor")
    if e is None:  # no state at hi: an end of the bracket where the line is taut beyond T
        hi_value = fairlead_tension
    else:
        hi_value = e

    def bracketed(x):
        if x == hi:
            return hi_value
        e = solvable(x)
        if e is None:
            raise LayoutError(f"the catenary solve found no static state of this line at {vertical:g} m height "
                              f"{x:.6g} m from the anchor, between states of {fairlead_tension + low_excess:.6g} N "
                              f"and more than {fairlead_tension:g} N at its fairlead")
        return e

    x = brentq(bracketed, lo, hi, xtol=1e-13 * total_length, rtol=1e-15, maxiter=100)
    state = solve_line(segments, horizontal=x, vertical=vertical, seabed=seabed, anchor_height=anchor_height)
    if abs(state.fairlead_tension - fairlead_tension) > 1e-6 * fairlead_tension:
        raise LayoutError(f"the catenary solve found no static state of this line at {vertical:g} m height with a "
                          f"fairlead tension of {fairlead_tension:g} N (nearest {state.fairlead_tension:.6g} N at "
                          f"{x:.6g} m)")
    return x, state


def _pieces(segments: list[Segment], state: LineState):
    """(segment, unstretched length [m], vertical tension at its start [N], on the seabed?) of each
    piece of the line from the anchor: a descent while V < 0 (to the seabed), the grounded length,
    then the suspended rest."""
    v, ground = state.anchor_vertical, state.grounded_length
    for seg in segments:
        left = seg.length
        if ground > 0.0 and v < 0.0:  # leaving the anchor downward, to the touchdown point
            hang = min(left, -v / seg.weight)
            yield seg, hang, v, False
            left -= hang
            v = 0.0 if left > 0.0 else v + seg.weight * hang
        if ground > 0.0 and left > 0.0:
            on_bed = min(left, ground)
            yield seg, on_bed, 0.0, True
            left -= on_bed
            ground -= on_bed
        if left > 0.0:
            yield seg, left, v, False
            v += seg.weight * left


def strain_energy(segments: list[Segment], state: LineState) -> float:
    """Elastic energy [J] a line stores in its static state: the integral of T^2 / (2 EA) over the
    unstretched arc length (linear elastic, T = EA x strain). A grounded length carries H; along a
    suspended one V = V_b + w s, so it adds (H^2 L + ((V_b + w L)^3 - V_b^3) / (3 w)) / (2 EA)."""
    H = state.horizontal_tension
    energy = 0.0
    for seg, length, v, on_bed in _pieces(segments, state):
        cubes = 0.0 if on_bed else ((v + seg.weight * length) ** 3 - v ** 3) / (3.0 * seg.weight)
        energy += (H * H * length + cubes) / (2.0 * seg.ea)
    return energy


def profile(segments: list[Segment], state: LineState, points_per_segment: int = 50) -> np.ndarray:
    """(n, 4) rows (unstretched arc length from the anchor [m], x [m], z [m], tension [N]) along the
    line, relative to the anchor: its descent to the seabed, the grounded part (tension H, straight),
    the suspended catenary."""
    H = state.horizontal_tension
    rows = [(0.0, 0.0, 0.0, state.anchor_tension)]
    s = x = z = 0.0
    for seg, length, v, on_bed in _pieces(segments, state):
        if on_bed:
            s, x = s + length, x + length * (1.0 + H / seg.ea)
            rows.append((s, x, z, H))
            continue
        for t in np.linspace(0.0, length, points_per_segment + 1)[1:]:
            dx, dz = _suspended_span(t, seg.weight, seg.ea, H, v)
            rows.append((s + t, x + dx, z + dz, math.hypot(H, v + seg.weight * t)))
        dx, dz = _suspended_span(length, seg.weight, seg.ea, H, v)
        s, x, z = s + length, x + dx, z + dz
    return np.asarray(rows)
