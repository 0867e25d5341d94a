"""The sea at the platform's moving points, summed at the ends of intervals and interpolated in time
(docs/waves.md, Cost).

The sums over a sea's components are what the platform pays for waves: 200 JONSWAP components at
the Kulluk's 564 line nodes and 576 hull panel corners cost 8.4 ms of CPU time for the two ends,
against ~0.6 ms for the rest of a platform step. The sea changes slowly against the step, so the platform takes these sums only at
the two ends of intervals of N = round(WAVE_INTERVAL / dt) platform steps (8 at dt = 6.2 ms),
at the points' places at the interval's start, and every step and line sub-step in between
interpolates them linearly in time. The points:

- the DEM line nodes: WAVE_FIELDS per node (``node_waves``: eta [m] over it, particle velocity
  [m/s] and acceleration [m/s^2] at it);
- the hull's wave-pressure panel corners: CORNER_FIELDS per corner (``corner_waves``: eta [m] over
  it and the dynamic pressure p_d [Pa] at it), the per-corner quantities that
  hull_waves.hull_wave_pressure integrates; the cut and the hydrostatic pressure are taken at the
  body's pose of the moment, so only the waves are interpolated, never the force;
- the braces' slice axis points: WAVE_FIELDS each (eta over the point and the acceleration are
  what hull_waves.brace_wave_loads reads).

The error, for an interval T = N dt (figures for seed 003's sea, jobs/kulluk_2017_tight70_waves.toml:
JONSWAP, T_p 23.7 s, 200 components, the shortest 6.0 s and 56 m long, the peak 502 m, in 52 m of
water; dt 6.2 ms, N = 8, T = 49.6 ms):

- time: linear interpolation of a harmonic of angular frequency omega over T is off by at most
  (omega T)^2 / 8 of its amplitude: 3.4e-4 for the 6 s component, 2.2e-5 for the peak (23.7 s);
- place: a point keeps the sea of its place at the interval's start; moving at |v| it is off by
  k |v| T of a component's amplitude (the phase k x and the depth factor e^(k z) alike): at 1 m/s,
  5.6e-3 for the 56 m component and 6.2e-4 for the 502 m peak wave. The lines' nodes and the
  Kulluk's hull move at a few tenths of a m/s in its Hs 2 m sea (pi Hs / T_p = 0.27 m/s), so this is
  a bound. At the next interval's start the points' sums are taken afresh where they are then, so
  the interpolated sea steps there by at most this place error.

Both weigh mostly the short components, whose share of the amplitude is small in a JONSWAP sea
(the 6 s component's amplitude is 3 % of the peak's): weighted by the components' amplitudes, the
time error is 6.1e-5 and the place error 1.2e-3 at 1 m/s (3.3e-4 at 0.27 m/s) of the summed
amplitude. Summed once per step (N = 1, as before) the shortest component's errors were 5.3e-6 and
6.9e-4, at 8 times the cost.

Restart: the interval's index and length in steps, the platform's step count and the two ends of
every point set are the ``state`` a checkpoint keeps (Platform.state), so a restarted run takes the
same ends and continues bit for bit. Still water has no WaveIntervals and pays nothing.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..kernels import JIT
from ..kernels.waves import depth_factors

WAVE_INTERVAL = 0.05  # [s] the sea is summed at the platform's points every this long (in steps)
WAVE_FIELDS = 7       # per point: eta [m], u_x, u_y, u_z [m/s], a_x, a_y, a_z [m/s^2]
CORNER_FIELDS = 2     # per panel corner: eta [m], dynamic pressure p_d [Pa]


@njit(**JIT)
def _phase_turns(sea, t0, t1):
    """(cos, sin) of omega_j (t1 - t0) [-] per component: the turn from the phase at t0 to t1."""
    m = sea.amplitude.shape[0]
    cw = np.empty(m)
    sw = np.empty(m)
    for j in range(m):
        cw[j] = math.cos(sea.omega[j] * (t1 - t0))
        sw[j] = math.sin(sea.omega[j] * (t1 - t0))
    return cw, sw


@njit(**JIT)
def node_waves(sea, x, level, t0, t1, out0, out1):
    """The sea at every point at times t0 and t1 [s]: out0, out1 (n, WAVE_FIELDS) get eta [m] over
    (x[i, 0], x[i, 1]) and the particle velocity [m/s] and acceleration [m/s^2] at x[i] (n, 3) [m],
    its height taken from the water's ``level`` [m] and clipped to [-depth, 0] as in
    kernels.waves.sea_point, whose sums these are. One pass over the components: the depth factors
    and the phase's cos and sin at t0 serve t1 too, the phase turned by omega (t1 - t0)."""
    m = sea.amplitude.shape[0]
    cw, sw = _phase_turns(sea, t0, t1)
    amp, omega, k, direction, phase, depth = sea.amplitude, sea.omega, sea.k, sea.direction, sea.phase, sea.depth
    for i in range(x.shape[0]):
        zc = min(x[i, 2] - level, 0.0)
        if math.isfinite(depth) and zc < -depth:
            zc = -depth
        for f in range(WAVE_FIELDS):
            out0[i, f] = 0.0
            out1[i, f] = 0.0
        for j in range(m):
            c, s, _ = depth_factors(k[j], zc, depth)
            theta = k[j] * (x[i, 0] * direction[j, 0] + x[i, 1] * direction[j, 1]) - omega[j] * t0 + phase[j]
            aw, aw2 = amp[j] * omega[j], amp[j] * omega[j] * omega[j]
            ct, st = math.cos(theta), math.sin(theta)
            for out in (out0, out1):
                uh, ah = aw * c * ct, aw2 * c * st
                out[i, 0] += amp[j] * ct
                out[i, 1] += uh * direction[j, 0]
                out[i, 2] += uh * direction[j, 1]
                out[i, 3] += aw * s * st
                out[i, 4] += ah * direction[j, 0]
                out[i, 5] += ah * direction[j, 1]
                out[i, 6] -= aw2 * s * ct
                ct, st = ct * cw[j] + st * sw[j], st * cw[j] - ct * sw[j]  # theta - omega (t1 - t0)


@njit(**JIT)
def corner_waves(sea, x, level, t0, t1, out0, out1):
    """The sea at every panel corner at times t0 and t1 [s]: out0, out1 (n, CORNER_FIELDS) get eta
    [m] over (x[i, 0], x[i, 1]) and the dynamic pressure p_d [Pa] at x[i] (n, 3) [m], its height
    from ``level`` [m] clipped to [-depth, 0] (kernels.waves.sea_point's sums). One pass over the
    components, as ``node_waves``."""
    m = sea.amplitude.shape[0]
    cw, sw = _phase_turns(sea, t0, t1)
    amp, omega, k, direction, phase, depth = sea.amplitude, sea.omega, sea.k, sea.direction, sea.phase, sea.depth
    rho_g = sea.density * sea.g
    for i in range(x.shape[0]):
        zc = min(x[i, 2] - level, 0.0)
        if math.isfinite(depth) and zc < -depth:
            zc = -depth
        e0 = p0 = e1 = p1 = 0.0
        for j in range(m):
            _, _, kk = depth_factors(k[j], zc, depth)
            theta = k[j] * (x[i, 0] * direction[j, 0] + x[i, 1] * direction[j, 1]) - omega[j] * t0 + phase[j]
            ct, st = math.cos(theta), math.sin(theta)
            c1 = ct * cw[j] + st * sw[j]  # cos(theta - omega (t1 - t0))
            e0 += amp[j] * ct
            e1 += amp[j] * c1
            p0 += rho_g * amp[j] * kk * ct
            p1 += rho_g * amp[j] * kk * c1
        out0[i, 0], out0[i, 1], out1[i, 0], out1[i, 1] = e0, p0, e1, p1


@njit(**JIT)
def blend_waves(wave0, wave1, a, out):
    """out = (1 - a) wave0 + a wave1, (n, fields) each: the sea at the fraction a of the interval
    from wave0's time to wave1's (exactly wave1 at a = 1)."""
    for i in range(out.shape[0]):
        for f in range(out.shape[1]):
            out[i, f] = (1.0 - a) * wave0[i, f] + a * wave1[i, f]


class WaveIntervals:
    """The two ends of the current interval for named point sets of the platform (module docstring).

    ``step``: platform steps taken (None: unknown, after a checkpoint that did not keep it; then
    taken from the clock as round(time / dt)); ``index``: the interval held (-1: none), of ``every``
    steps; ``ends[name]``: (2, n, fields) the sea at the set's points at its start and its end."""

    def __init__(self, sea, interval: float = WAVE_INTERVAL):
        """sea: platform.sea.SeaComponents with components; interval [s]."""
        self.sea = sea
        self.interval = float(interval)
        self.step = 0
        self.index = -1
        self.every = 0
        self.ends: dict[str, np.ndarray] = {}

    def steps_per_interval(self, dt: float) -> int:
        """N = round(interval / dt), at least 1, for a step of dt [s]."""
        return max(1, int(round(self.interval / dt)))

    def holds(self, step: int, span: int = 0) -> bool:
        """Whether the held interval covers steps step .. step + span (its end included)."""
        lo = self.index * self.every
        return self.index >= 0 and lo <= step and step + span <= lo + self.every

    def begin_step(self, dt: float, time: float, points) -> None:
        """Before a step of dt [s] from ``time`` [s]: when the held interval does not cover it, sum
        the sea at the two ends of the interval of steps it starts or lies in, at ``points`` now.

        points: {name: (x (n, 3) [m], fields (WAVE_FIELDS or CORNER_FIELDS), level [m])}, called as
        points() only when the sums are due."""
        if self.step is None:
            self.step = int(round(time / dt))
        every = self.steps_per_interval(dt)
        if self.every == every and self.holds(self.step, 1):
            return
        k, into = divmod(self.step, every)
        t0 = time - into * dt
        t1 = t0 + every * dt
        ends = {}
        for name, (x, fields, level) in points().items():
            out = np.empty((2, len(x), fields))
            kernel = node_waves if fields == WAVE_FIELDS else corner_waves
            kernel(self.sea, np.ascontiguousarray(x, dtype=float), float(level), t0, t1, out[0], out[1])
            ends[name] = out
        self.index, self.every, self.ends = k, every, ends

    def fraction(self, step: int) -> float:
        """Where step lies in the held interval: 0 at its start, 1 at its end."""
        return (step - self.index * self.every) / self.every

    def at(self, name: str, step: int) -> np.ndarray:
        """(n, fields) the sea at set ``name``'s points interpolated to ``step`` (held interval)."""
        a, b = self.ends[name]
        out = np.empty_like(a)
        blend_waves(a, b, self.fraction(step), out)
        return out

    # -- checkpoint ----------------------------------------------------------------------------
    def state(self) -> dict[str, np.ndarray]:
        """The step count, the interval held and its ends, for Platform.state (under waves/)."""
        out = {"step": np.array(-1 if self.step is None else self.step), "interval": np.array(self.index),
               "every": np.array(self.every)}
        for name, ends in self.ends.items():
            out[f"ends/{name}"] = ends.copy()
        return out

    def set_state(self, s: dict) -> None:
        """From ``state``'s items; none (a checkpoint without them): the step from the clock, no
        interval held."""
        if "step" not in s:
            self.step, self.index, self.every, self.ends = None, -1, 0, {}
            return
        step = int(s["step"])
        self.step = None if step < 0 else step
        self.index, self.every = int(s["interval"]), int(s["every"])
        self.ends = {name[len("ends/"):]: np.array(v, float) for name, v in s.items() if name.startswith("ends/")}
