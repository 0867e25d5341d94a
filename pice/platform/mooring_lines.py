"""DEM mooring lines on rank 0: construction, sub-stepping at the lines' own stable step, tensions.

A line runs from its anchor to its fairlead through segments (Table 5 of Zhu & Ji 2022), each cut
into elements of at most ``element_length``; the nodes start on the quasi-static elastic catenary
(platform.catenary), so a line begins close to equilibrium. The physics of a node (bonds, weight,
Morison drag, seabed) and the sub-step are the numba kernels of platform.mooring_line_kernels;
their parameters are named records built once here (``build_lines``) and read by field name in
numba: a structured array of LINE_ELEMENT_RECORD (one record per element) and the LineWater and
Seabed named tuples. In waves, ``sea`` (platform.sea.SeaComponents, set by the platform from the
job's [waves]) moves the water the Morison loads see; still water by default.
"""

from __future__ import annotations

import math
from collections import namedtuple
from dataclasses import dataclass, field

import numpy as np

from .catenary import Segment, profile, solve_line
from .sea import SeaComponents, still_water
from .mooring_line_kernels import (FIXED, FREE, PRESCRIBED, advance_lines, line_energies, line_forces, node_constants,
                                   node_force_norms, relax_lines)
from .wave_intervals import WAVE_FIELDS, node_waves

# One element (bond) of a DEM line: axial stiffness ea [N], unstretched length l0 [m], hydrodynamic
# diameter D [m], wet_weight [N/m], the Morison coefficients drag_normal C_dn, drag_tangential C_dt
# and added_mass C_a, and the damping_ratio of the bond's axial dashpot.
LINE_ELEMENT_RECORD = np.dtype([("ea", np.float64), ("l0", np.float64), ("diameter", np.float64),
                                ("wet_weight", np.float64), ("drag_normal", np.float64),
                                ("drag_tangential", np.float64), ("added_mass", np.float64),
                                ("damping_ratio", np.float64)])

LineWater = namedtuple("LineWater", ["density", "level"])
LineWater.__doc__ = """The water the lines hang in: density [kg/m^3], level of its surface [m]."""

Seabed = namedtuple("Seabed", ["z", "stiffness", "damping_ratio", "friction", "slip_velocity"])
Seabed.__doc__ = """The seabed under the lines: height z [m] (-inf: none), penalty stiffness [N/m per m of
line] (0: none), damping_ratio of its dashpot, Coulomb friction coefficient, slip_velocity [m/s]
up to which the friction is regularised (proportional to the sliding speed)."""


@dataclass(frozen=True)
class LineSegment:
    """Physical properties of one segment of a mooring line (SI units)."""

    length: float            # unstretched [m]
    ea: float                # axial stiffness [N]
    diameter: float          # equivalent hydrodynamic diameter D [m]
    wet_weight: float        # weight in water per length [N/m]
    dry_mass: float          # mass per length [kg/m]
    drag_normal: float = 1.2
    drag_tangential: float = 0.008
    added_mass: float = 1.0


MAX_RELAX_NODE_STEPS = 1.0e8  # node updates a relaxation may take (~15 s here; settling takes 2e6-1e7)


@dataclass
class MooringLines:
    """All lines of a scene as one node set (kernels work on flat arrays)."""

    x: np.ndarray
    v: np.ndarray
    mass: np.ndarray
    prev: np.ndarray
    seg: np.ndarray
    kind: np.ndarray
    props: np.ndarray        # (n_elements,) LINE_ELEMENT_RECORD
    anchors: np.ndarray      # node index of each line's anchor
    fairleads: np.ndarray    # node index of each line's fairlead
    water: LineWater
    current: np.ndarray      # (3,) [m/s]
    seabed: Seabed
    force: np.ndarray = field(default=None)
    tension: np.ndarray = field(default=None)
    added_mass: np.ndarray = field(default=None)
    tangent: np.ndarray = field(default=None)
    time: float = 0.0
    settled: bool = True     # False when the last relax stopped at its cap before reaching its tol
    sea: SeaComponents = field(default_factory=still_water)  # the waves the nodes sit in (z from water.level)

    def __post_init__(self):
        n = len(self.x)
        self.force = np.zeros((n, 3))
        self.tension = np.zeros(n)
        self.added_mass = np.zeros(n)
        self.tangent = np.zeros((n, 3))
        self.constants = node_constants(self.prev, self.seg, self.props)  # what each node stands for
        self._no_waves = np.empty((0, WAVE_FIELDS))
        self._forces()

    def _forces(self):
        line_forces(self.x, self.v, self.mass, self.prev, self.seg, self.props, self.constants, self.kind,
                    self.water, self.current, self.seabed, self.sea, self.time, self.force, self.tension,
                    self.added_mass, self.tangent)

    def stable_step(self) -> float:
        """Stability limit of the node chain [s]: 1/sqrt(max k/m) (omega_max = 2 sqrt(k/m) for a chain),
        reduced for the bond dashpots and the seabed spring."""
        bonded = self.prev >= 0
        el = self.props[self.seg[bonded]]
        k = el["ea"] / el["l0"]
        m = np.minimum(self.mass[bonded], self.mass[self.prev[bonded]])
        omega2 = float(np.max(4.0 * k / m))
        omega2 += float(self.seabed.stiffness) * float(np.max(self.props["l0"])) / float(self.mass.min())
        zeta = float(max(self.props["damping_ratio"].max(), self.seabed.damping_ratio))
        return 2.0 / math.sqrt(omega2) * (math.sqrt(1 + zeta * zeta) - zeta)

    def advance(self, dt: float, nsub: int, fairlead_x=None, fairlead_v=None, *, t_start: float | None = None,
                waves=None) -> None:
        """Advance by nsub sub-steps of dt [s]; fairlead_x/v (n_lines, 3) are the prescribed
        fairlead positions [m] and velocities [m/s] at the END of the interval (linear in between).
        t_start [s]: the time the interval starts at (default: the lines' own ``time``; the platform
        gives its own clock); ``time`` is t_start + nsub dt after.

        In waves the sub-steps interpolate the sea at the nodes linearly in time between two ends
        (mooring_line_kernels.advance_lines): ``waves`` = (wave0, wave1, a0, a1), the sea at the nodes
        (n, WAVE_FIELDS) at the two ends of an interval and the fractions of it this call runs from
        and to (the platform's platform.wave_intervals.WaveIntervals); None: the sea taken here, at
        the nodes' start positions at t_start and t_start + nsub dt (a0 = 0, a1 = 1)."""
        fl = self.fairleads
        x0 = self.x[fl].copy()
        x1 = x0 if fairlead_x is None else np.asarray(fairlead_x, float).reshape(-1, 3)
        v1 = self.v[fl].copy() if fairlead_v is None else np.asarray(fairlead_v, float).reshape(-1, 3)
        t0 = self.time if t_start is None else float(t_start)
        if waves is not None:
            wave0, wave1, a0, a1 = waves
        else:
            wave0 = wave1 = self._no_waves  # still water
            a0, a1 = 0.0, 1.0
            if self.sea.amplitude.shape[0] > 0:
                n = len(self.x)
                wave0, wave1 = np.empty((n, WAVE_FIELDS)), np.empty((n, WAVE_FIELDS))
                node_waves(self.sea, self.x, self.water.level, t0, t0 + nsub * dt, wave0, wave1)
        advance_lines(self.x, self.v, self.mass, self.prev, self.seg, self.props, self.constants, self.kind,
                      self.water, self.current, self.seabed, wave0, wave1, float(a0), float(a1), self.force,
                      self.tension, self.added_mass, self.tangent, fl, x0, x1, v1, dt, nsub)
        self.time = t0 + dt * nsub

    def relax(self, *, tol: float = 1.0, max_time: float = 600.0, max_node_steps: float | None = None) -> int:
        """Bring the lines to static equilibrium with their ends held (kinetic damping); the nodes
        start on the continuous catenary, which a chain of straight elements cannot follow exactly
        (its chords are shorter than the arc by ~ L kappa^2 dl^2 / 24). tol: largest net force on a
        node [N]; at most max_time [s] of relaxation and max_node_steps node updates (default
        MAX_RELAX_NODE_STEPS). Returns the relaxation steps taken; ``settled`` says whether the lines
        reached ``tol``."""
        dt = 0.5 * self.stable_step()
        current = self.current.copy()
        self.current[:] = 0.0
        budget = MAX_RELAX_NODE_STEPS if max_node_steps is None else max_node_steps
        cap = max(1, min(int(min(max_time / dt, 1e18)), int(budget / len(self.x))))
        steps = relax_lines(self.x, self.v, self.mass, self.prev, self.seg, self.props, self.constants, self.kind,
                            self.water, self.current, self.seabed, self.force, self.tension, self.added_mass,
                            self.tangent, dt, cap, tol)
        self.current[:] = current
        self.v[:] = 0.0
        self._forces()
        self.settled = steps < cap or self.largest_free_force() < tol
        return steps

    def largest_free_force(self) -> float:
        """The largest net force on a free node [N] (what ``relax`` brings below its tol)."""
        free = self.kind == FREE
        return float(np.linalg.norm(self.force[free], axis=1).max()) if free.any() else 0.0

    def energies(self) -> tuple[float, float]:
        """(kinetic [J], elastic [J]) of the lines (mooring_line_kernels.line_energies): 1/2 m |v|^2
        of the nodes with their added mass on the normal velocity, and 1/2 EA/l0 (l - l0)^2 of the
        taut elements (tension only, as the bonds)."""
        kinetic, elastic = line_energies(self.x, self.v, self.mass, self.prev, self.seg, self.props,
                                         self.added_mass, self.tangent)
        return float(kinetic), float(elastic)

    def reactions(self, nodes: np.ndarray) -> np.ndarray:
        """(k, 3) force [N] the line exerts on the support at each fixed/prescribed node (its anchor
        or its body): all loads on that node, whose half element the support carries."""
        return self.force[nodes].copy()

    def fairlead_tensions(self) -> np.ndarray:
        """(n_lines,) |reaction| [N] at each fairlead."""
        return node_force_norms(self.force, self.fairleads)

    def anchor_tensions(self) -> np.ndarray:
        """(n_lines,) |reaction| [N] at each anchor."""
        return node_force_norms(self.force, self.anchors)

    def polylines(self) -> tuple[np.ndarray, np.ndarray]:
        """(n_nodes, 3) node positions [m] (each line's nodes contiguous, anchor first) and the line
        index of each node."""
        ids = np.zeros(len(self.x), np.int64)
        for k, (a, f) in enumerate(zip(self.anchors, self.fairleads)):
            ids[a:f + 1] = k
        return self.x.copy(), ids

    # -- checkpoint ----------------------------------------------------------------------------
    _STATE = ("x", "v", "force", "tension", "added_mass", "tangent")

    def state(self) -> dict[str, np.ndarray]:
        out = {k: getattr(self, k) for k in self._STATE}
        out["time"] = np.array(self.time)
        return out

    def set_state(self, s: dict) -> None:
        for k in self._STATE:
            getattr(self, k)[:] = s[k]
        self.time = float(s["time"])


def build_lines(lines, *, element_length: float, water_density: float, water_level: float,
                seabed_z: float | None, current=(0.0, 0.0, 0.0), bond_damping: float = 0.0,
                seabed_stiffness: float = 1.0e5, seabed_damping: float = 0.5, seabed_friction: float = 0.5,
                fairlead_kind: int = PRESCRIBED) -> MooringLines:
    """Nodes for each line given as (anchor (3,), fairlead (3,), [LineSegment, ...] anchor first).

    Nodes start on the quasi-static catenary through anchor and fairlead (with seabed contact when
    ``seabed_z`` [m] is given: the seabed's height, which an anchor may lie above).
    seabed_stiffness [N/m per m of line], seabed_damping (ratio), seabed_friction (Coulomb),
    element_length the longest element [m].
    """
    xs, masses, prevs, segs, kinds, props = [], [], [], [], [], []
    anchors, fairleads = [], []
    for anchor, fairlead, segments in lines:
        anchor, fairlead = np.asarray(anchor, float), np.asarray(fairlead, float)
        horiz = fairlead[:2] - anchor[:2]
        hdist = float(np.linalg.norm(horiz))
        e_h = horiz / hdist if hdist > 0 else np.array([1.0, 0.0])
        static = solve_line([Segment(s.length, s.wet_weight, s.ea) for s in segments],
                            horizontal=hdist, vertical=float(fairlead[2] - anchor[2]), seabed=seabed_z is not None,
                            anchor_height=max(float(anchor[2]) - seabed_z, 0.0) if seabed_z is not None else 0.0)
        prof = profile([Segment(s.length, s.wet_weight, s.ea) for s in segments], static, 2000)
        base = len(xs)
        s_nodes = [0.0]
        for s in segments:
            n_el = max(1, int(math.ceil(s.length / element_length - 1e-9)))
            for k in range(n_el):
                s_nodes.append(s_nodes[-1] + s.length / n_el)
                props.append((s.ea, s.length / n_el, s.diameter, s.wet_weight, s.drag_normal,
                              s.drag_tangential, s.added_mass, bond_damping))
        s_nodes = np.asarray(s_nodes)
        px = np.interp(s_nodes, prof[:, 0], prof[:, 1])
        pz = np.interp(s_nodes, prof[:, 0], prof[:, 2])
        for k, s in enumerate(s_nodes):
            xs.append([anchor[0] + px[k] * e_h[0], anchor[1] + px[k] * e_h[1], anchor[2] + pz[k]])
            prevs.append(base + k - 1 if k > 0 else -1)
            segs.append(len(props) - (len(s_nodes) - 1) + k - 1 if k > 0 else 0)
            kinds.append(FIXED if k == 0 else (fairlead_kind if k == len(s_nodes) - 1 else FREE))
        # lumped masses: half of each adjacent element
        el_mass = np.array([segments_mass(segments, element_length)]).ravel()
        m = np.zeros(len(s_nodes))
        m[:-1] += 0.5 * el_mass
        m[1:] += 0.5 * el_mass
        masses.extend(m)
        anchors.append(base)
        fairleads.append(base + len(s_nodes) - 1)
    seabed = Seabed(z=float(seabed_z) if seabed_z is not None else -math.inf,
                    stiffness=float(seabed_stiffness) if seabed_z is not None else 0.0,
                    damping_ratio=float(seabed_damping), friction=float(seabed_friction), slip_velocity=0.01)
    return MooringLines(x=np.asarray(xs, float), v=np.zeros((len(xs), 3)), mass=np.asarray(masses, float),
                        prev=np.asarray(prevs, np.int64), seg=np.asarray(segs, np.int64),
                        kind=np.asarray(kinds, np.int64), props=np.array(props, LINE_ELEMENT_RECORD),
                        anchors=np.asarray(anchors, np.int64), fairleads=np.asarray(fairleads, np.int64),
                        water=LineWater(density=float(water_density), level=float(water_level)),
                        current=np.asarray(current, float),
                        seabed=seabed)


def segments_mass(segments, element_length: float) -> list[float]:
    """Mass [kg] of each element, anchor first."""
    out = []
    for s in segments:
        n_el = max(1, int(math.ceil(s.length / element_length - 1e-9)))
        out.extend([s.dry_mass * s.length / n_el] * n_el)
    return out
