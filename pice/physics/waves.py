"""Linear (Airy) waves in water of finite or infinite depth: regular waves, and irregular seas from a
JONSWAP spectrum (issue 14; seed 003's sea environment: the wave field undisturbed by ice and hull).

A sea is a sum of components j, each of amplitude a_j [m], angular frequency w_j [rad/s],
wavenumber k_j [rad/m] from the dispersion relation w^2 = g k tanh(k h), direction (cos, sin) and
phase phi_j. With theta_j = k_j (x cos + y sin) - w_j t + phi_j and z up from the still water level:

    elevation        eta = sum a cos(theta)
    velocity         u_h = sum a w C(z) cos(theta) (cos, sin),   u_z = sum a w S(z) sin(theta)
    acceleration     a_h = sum a w^2 C(z) sin(theta) (cos, sin), a_z = -sum a w^2 S(z) cos(theta)
    dynamic pressure p = rho g sum a K(z) cos(theta)

with C = cosh(k (z + h)) / sinh(k h), S = sinh(k (z + h)) / sinh(k h), K = cosh(k (z + h)) / cosh(k h),
written with exponentials so that deep water (k h large, or h infinite: C = S = K = e^(k z)) is
exact and nothing overflows. Linear theory is valid up to the still water level; above it (z > 0,
under a crest) the kinematics are those at z = 0 (constant extrapolation), and below the seabed
those at the seabed.

The JONSWAP spectrum is DNV-RP-C205's (section 3.5.5) with its peak enhancement gamma and widths
0.07 / 0.09, normalised numerically so that its variance is Hs^2 / 16 exactly. A realisation splits
[0.5, 4] w_p into ``components`` equal bins of width dw and draws one frequency uniformly in each,
with amplitude sqrt(2 S dw) and a phase uniform in [0, 2 pi), all from ``seed``: with the
frequencies off a common grid the record does not repeat (at the bins' midpoints it would after
2 pi / dw, 1,370 s for seed 003's sea with 200 components, shorter than its 4,000 s runs).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from ..kernels.waves import sea_elevation, sea_kinematics

GRAVITY = 9.81  # [m/s^2]


def wavenumber(omega, depth: float = math.inf, g: float = GRAVITY):
    """k [rad/m] with omega^2 = g k tanh(k depth) for angular frequencies omega [rad/s] > 0 (array or
    scalar) and depth [m] (inf: deep water, k = omega^2 / g). Newton from a start that is exact in
    both limits; converged to round-off (relative residual < 1e-14)."""
    w = np.asarray(omega, float)
    k_deep = w * w / g
    if not math.isfinite(depth):
        return k_deep if w.ndim else float(k_deep)
    # Eckart's explicit approximation: within 5 % everywhere, then Newton
    k = k_deep / np.sqrt(np.tanh(k_deep * depth))
    for _ in range(50):
        t = np.tanh(k * depth)
        f = g * k * t - w * w
        df = g * t + g * k * depth * (1.0 - t * t)
        step = f / df
        k = k - step
        if np.all(np.abs(step) <= 1e-15 * k):
            break
    return k if w.ndim else float(k)


def jonswap(omega, hs: float, tp: float, gamma: float = 3.3):
    """JONSWAP spectral density S(omega) [m^2 s/rad] for significant wave height hs [m], peak period
    tp [s] and peak enhancement gamma (DNV-RP-C205 3.5.5.1, sigma 0.07 below the peak and 0.09 above),
    normalised so that its integral over all omega is hs^2 / 16."""
    w = np.asarray(omega, float)
    shape = _jonswap_shape(w, tp, gamma)
    grid = np.linspace(1e-3, 12.0, 200_001) * (2.0 * math.pi / tp)
    total = np.trapezoid(_jonswap_shape(grid, tp, gamma), grid)
    return hs * hs / 16.0 * shape / total


def _jonswap_shape(w, tp, gamma):
    """The unnormalised JONSWAP form: w^-5 exp(-5/4 (w_p / w)^4) gamma^exp(-(w - w_p)^2 / (2 s^2 w_p^2))."""
    wp = 2.0 * math.pi / tp
    out = np.zeros_like(w)
    pos = w > 0
    x = w[pos]
    sigma = np.where(x <= wp, 0.07, 0.09)
    out[pos] = x ** -5 * np.exp(-1.25 * (wp / x) ** 4) * gamma ** np.exp(-0.5 * ((x - wp) / (sigma * wp)) ** 2)
    return out


def peak_period(period: float, gamma: float, kind: str) -> float:
    """T_p [s] of a JONSWAP sea given its mean period T_1 (kind "mean") or zero-crossing period T_z
    (kind "zero_crossing") [s], by DNV-RP-C205's fits (3.5.5.4), 1 <= gamma <= 7; "peak" returns it."""
    g = gamma
    if kind == "peak":
        return float(period)
    if kind == "mean":
        return period / (0.7303 + 0.04936 * g - 0.006556 * g * g + 0.0003610 * g ** 3)
    if kind == "zero_crossing":
        return period / (0.6673 + 0.05037 * g - 0.006230 * g * g + 0.0003341 * g ** 3)
    raise ValueError(f"period kind {kind!r}: use 'peak', 'mean' or 'zero_crossing'")


@dataclass(frozen=True)
class Sea:
    """The components of a linear sea (module docstring): arrays of one entry per component."""

    amplitude: np.ndarray   # [m]
    omega: np.ndarray       # [rad/s]
    k: np.ndarray           # [rad/m]
    direction: np.ndarray   # (n, 2) unit vector of propagation in x-y
    phase: np.ndarray       # [rad]
    depth: float = math.inf  # [m]
    g: float = GRAVITY
    density: float = 1025.0  # [kg/m^3]

    @classmethod
    def regular(cls, *, height: float, period: float, direction_deg: float = 0.0, phase: float = 0.0,
                depth: float = math.inf, g: float = GRAVITY, density: float = 1025.0) -> Sea:
        """One Airy wave of height [m] (crest to trough), period [s], heading [deg] from +x."""
        w = 2.0 * math.pi / period
        return cls._make([0.5 * height], [w], direction_deg, [phase], depth, g, density)

    @classmethod
    def jonswap(cls, *, hs: float, tp: float, gamma: float = 3.3, direction_deg: float = 0.0,
                components: int = 200, seed: int = 0, depth: float = math.inf, g: float = GRAVITY,
                density: float = 1025.0) -> Sea:
        """An irregular long-crested sea of the JONSWAP spectrum (module docstring)."""
        wp = 2.0 * math.pi / tp
        edges = np.linspace(0.5 * wp, 4.0 * wp, components + 1)
        dw = edges[1] - edges[0]
        rng = np.random.default_rng(seed)
        phase = rng.uniform(0.0, 2.0 * math.pi, components)
        w = edges[:-1] + dw * rng.uniform(0.0, 1.0, components)  # one frequency drawn in each bin
        amp = np.sqrt(2.0 * jonswap(w, hs, tp, gamma) * dw)
        return cls._make(amp, w, direction_deg, phase, depth, g, density)

    @classmethod
    def _make(cls, amp, w, direction_deg, phase, depth, g, density) -> Sea:
        w = np.asarray(w, float)
        a = math.radians(direction_deg)
        direction = np.tile([math.cos(a), math.sin(a)], (len(w), 1))
        return cls(np.asarray(amp, float), w, np.asarray(wavenumber(w, depth, g), float).reshape(-1), direction,
                   np.asarray(phase, float), float(depth), float(g), float(density))

    def elevation(self, x, y, t: float) -> np.ndarray:
        """eta [m] at horizontal points x, y [m] (arrays of one shape) at time t [s]."""
        x, y = np.broadcast_arrays(np.asarray(x, float), np.asarray(y, float))
        out = sea_elevation(self.amplitude, self.omega, self.k, self.direction, self.phase, x.ravel(), y.ravel(),
                            float(t))
        return out.reshape(x.shape)

    def kinematics(self, points, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(velocity (n, 3) [m/s], acceleration (n, 3) [m/s^2], dynamic pressure (n,) [Pa]) of the
        undisturbed wave field at points (n, 3) [m] (z up from the still level) at time t [s]."""
        pts = np.ascontiguousarray(np.asarray(points, float).reshape(-1, 3))
        return sea_kinematics(self.amplitude, self.omega, self.k, self.direction, self.phase, self.depth,
                              self.g, self.density, pts, float(t))


def sea_from_job(job) -> Sea | None:
    """The job's [waves] as a Sea over its water (depth: water.depth, else deep; density, gravity), or
    None: still water."""
    w = job.waves
    if w is None:
        return None
    water = job.water
    depth = water.depth if water.depth is not None else math.inf
    g = job.gravity if job.gravity > 0 else GRAVITY
    if w.spectrum == "regular":
        return Sea.regular(height=w.height, period=w.period, direction_deg=w.direction, phase=w.phase, depth=depth,
                           g=g, density=water.density)
    return Sea.jonswap(hs=w.height, tp=peak_period(w.period, w.gamma, w.period_kind), gamma=w.gamma,
                       direction_deg=w.direction, components=w.components, seed=w.seed, depth=depth, g=g,
                       density=water.density)
