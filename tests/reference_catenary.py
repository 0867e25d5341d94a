"""An independent elastic catenary with seabed contact, and a spread mooring built from it (not a test module).

The reference for the mooring's restoring curve (tests/physics/test_restoring_curve.py,
benchmarks/mooring_layouts.py), written from the textbook equations and sharing no code with
pice.platform.catenary. A line of segments (unstretched length L [m], wet weight w [N/m], axial
stiffness EA [N]) runs from an anchor on a flat, frictionless seabed up to its fairlead, which lies
X [m] out and Z [m] above the anchor. With the horizontal tension H [N] (constant along the line)
and the vertical tension V [N] at the top of a hanging segment, V - w L at its bottom, the segment
spans (Faltinsen, Sea Loads on Ships and Offshore Structures, 1990, Sec. 8.2, Eqs. 8.4-8.5 with
elastic stretch; Irvine, Cable Structures, 1981, Eqs. 2.26-2.27):

    x = H/w [asinh(V/H) - asinh((V - w L)/H)] + H L / EA
    z = H/w [sqrt(1 + (V/H)^2) - sqrt(1 + ((V - w L)/H)^2)] + (V^2 - (V - w L)^2) / (2 w EA)

Walking down from the fairlead, V falls by w L per segment. If it stays >= 0 the whole line hangs
(V < 0 at the anchor is impossible with the anchor on the seabed: that part lies on it instead);
otherwise the line touches down where V = 0 and the rest lies straight on the seabed, carrying H
and stretched by H/EA. For a given H, z grows with the fairlead's V; along z = Z, x grows with H:
two nested brentq solves (no starting guess needed, always converging) give (H, V).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

G = 9.81  # [m/s^2]


@dataclass(frozen=True)
class Piece:
    """One homogeneous segment: unstretched length [m], wet weight [N/m], axial stiffness EA [N]."""

    length: float
    w: float
    ea: float


def spans(pieces: list[Piece], H: float, V: float) -> tuple[float, float]:
    """(x, z) [m] of the fairlead above the anchor for horizontal tension H [N] and vertical tension V
    [N] at the fairlead; ``pieces`` anchor first."""
    x = z = 0.0
    for p in reversed(pieces):  # from the fairlead down
        if V <= 0.0:  # on the seabed: straight, tension H
            x += p.length * (1.0 + H / p.ea)
            continue
        hang = min(p.length, V / p.w)  # the part of this segment above the touchdown point
        vb = V - p.w * hang
        x += H / p.w * (math.asinh(V / H) - math.asinh(vb / H)) + H * hang / p.ea
        z += H / p.w * (math.hypot(1.0, V / H) - math.hypot(1.0, vb / H)) + (V * V - vb * vb) / (2.0 * p.w * p.ea)
        x += (p.length - hang) * (1.0 + H / p.ea)  # the rest of it on the seabed
        V = vb
    return x, z


def _bracket_up(f, lo: float, hi: float) -> tuple[float, float]:
    """(lo, hi) with f(hi) > 0, doubling hi (f increasing, f(lo) <= 0)."""
    for _ in range(200):
        if f(hi) > 0.0:
            return lo, hi
        lo, hi = hi, 2.0 * hi
    raise ValueError("no bracket")


def solve(pieces: list[Piece], X: float, Z: float) -> tuple[float, float]:
    """(H, V) [N] at the fairlead of a line whose fairlead is X [m] out and Z [m] above its anchor."""
    weight = sum(p.w * p.length for p in pieces)

    def v_for(H):
        f = lambda V: spans(pieces, H, V)[1] - Z  # noqa: E731
        return brentq(f, *_bracket_up(f, 0.0, weight), xtol=1e-10 * weight, rtol=1e-14)

    def dx(log_h):
        H = math.exp(log_h)
        return spans(pieces, H, v_for(H))[0] - X

    lo = math.log(1e-6 * weight)
    if dx(lo) > 0.0:
        raise ValueError(f"the fairlead at ({X:g}, {Z:g}) m is nearer than the slack line reaches")
    hi = math.log(weight)
    while dx(hi) <= 0.0:
        lo, hi = hi, hi + 1.0
    log_h = brentq(dx, lo, hi, xtol=1e-13, rtol=1e-14)
    return math.exp(log_h), v_for(math.exp(log_h))


def anchor_radius(pieces: list[Piece], Z: float, tension: float) -> float:
    """Horizontal anchor-fairlead distance [m] at which the fairlead tension is ``tension`` [N]."""
    slack = sum(p.length for p in pieces) - Z  # nearer than this the line would pile up
    reach = math.sqrt(sum(p.length * (1 + tension / p.ea) for p in pieces) ** 2 - Z * Z)
    f = lambda X: math.hypot(*solve(pieces, X, Z)) - tension  # noqa: E731
    return brentq(f, slack * 1.001, reach, xtol=1e-9, rtol=1e-14)


def spread(headings_deg, *, radius: float, Z: float) -> np.ndarray:
    """(n, 3) anchors [m] relative to their fairleads: ``radius`` out along each heading, Z below."""
    a = np.radians(np.asarray(headings_deg, float))
    return np.column_stack([radius * np.cos(a), radius * np.sin(a), np.full(len(a), -Z)])


def pulls(pieces: list[Piece], anchors_rel: np.ndarray, offset) -> tuple[np.ndarray, np.ndarray]:
    """Forces of the lines on their fairleads [N] (n, 3) and fairlead tensions [N] (n,), the
    fairleads translated by ``offset`` (3,) [m] from where ``anchors_rel`` was measured."""
    force, tension = [], []
    for a in np.asarray(anchors_rel, float):
        d = np.asarray(offset, float) - a  # fairlead relative to its anchor
        X = math.hypot(d[0], d[1])
        H, V = solve(pieces, X, d[2])
        force.append([-H * d[0] / X, -H * d[1] / X, -V])
        tension.append(math.hypot(H, V))
    return np.array(force), np.array(tension)


def restoring(pieces: list[Piece], anchors_rel: np.ndarray, surge: float) -> tuple[float, float]:
    """(surge restoring force -F_x [N], largest fairlead tension [N]) at ``surge`` [m] (pure translation)."""
    force, tension = pulls(pieces, anchors_rel, (surge, 0.0, 0.0))
    return -float(force[:, 0].sum()), float(tension.max())
