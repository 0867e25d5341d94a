"""The platform: rank 0's bodies and their mooring lines, stepped together (DESIGN.md, the step, item 5).

Per ice step of dt: ``kick`` (half step with the loads of the previous evaluation), ``drift``
(bodies move and turn; the lines sub-step at their own stable step with their fairleads carried
by the hulls), then, once the ice loads of the new pose have been reduced to rank 0, ``loads`` and
``kick`` again. Fairleads are points fixed in their body's frame; a line's pull on its fairlead
acts on the body at that point.

Time: ``time`` [s] is the platform's clock, advanced by ``drift``; the lines' sub-steps run from the
start of the step (sub-step k of n ending at t + k dt/n) and the bodies' loads are taken at the new
time, so a sea (``sea``, platform.sea.SeaComponents; None: still water) is felt when each force
acts (docs/waves.md). In waves, ``wave_intervals`` (platform.wave_intervals.WaveIntervals) sums
the sea at the line nodes, the hull panels' corners and the brace slices at the two ends of
intervals of N platform steps (N dt ~ WAVE_INTERVAL), at their places at the interval's start; the
lines' sub-steps and the bodies' loads interpolate those sums linearly to their own times. The
interval and its ends are part of ``state``, so a restart continues bit for bit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .attachment_kernels import add_line_pull, fairlead_kinematics
from .fused_step import FusedStep
from .hull_waves import wave_points
from .rigid_body import RigidBody
from .sea import sea_components
from .wave_intervals import WAVE_FIELDS, WaveIntervals


@dataclass
class Attachment:
    """Line ``line`` has its fairlead at ``point`` [m] in the frame of body ``body``."""

    line: int
    body: int
    point: np.ndarray


@dataclass
class MooringGroup:
    """Lines of one [[moorings]] entry (DEM MooringLines or QuasiStaticLines) and where they attach."""

    lines: object
    attachments: list[Attachment]

    def arrays(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(line (k,), body (k,), point (k, 3) [m]) of the attachments, for attachment_kernels."""
        if getattr(self, "_arrays", None) is None or len(self._arrays[0]) != len(self.attachments):
            self._arrays = (np.array([a.line for a in self.attachments], np.int64),
                            np.array([a.body for a in self.attachments], np.int64),
                            np.array([a.point for a in self.attachments], float).reshape(-1, 3))
        return self._arrays


def lines_pull(groups: list[MooringGroup], n_bodies: int) -> np.ndarray:
    """(n_bodies, 3) summed pull [N] of all lines on each body, groups and lines in order (the lines'
    part of the "balance" mass before the bodies exist, and Platform.mooring_force)."""
    out = np.zeros((n_bodies, 3))
    for grp in groups:
        pull = grp.lines.reactions(grp.lines.fairleads)
        for a in grp.attachments:
            out[a.body] += pull[a.line]
    return out


class Platform:
    """Bodies, mooring lines and the water they sit in (rank 0 only)."""

    def __init__(self, bodies: list[RigidBody], moorings=None, attachments: list[Attachment] | None = None, *,
                 rho_w: float, g: float, level: float, current=(0.0, 0.0), groups: list[MooringGroup] | None = None,
                 sea=None):
        """sea: a physics.waves.Sea (or SeaComponents) the bodies and DEM lines float in; None or
        a sea of no components: still water, computed exactly as without waves."""
        self.bodies = bodies
        self.groups = list(groups or [])
        if moorings is not None:
            self.groups.insert(0, MooringGroup(moorings, list(attachments or [])))
        self.rho_w, self.g, self.level = rho_w, g, level
        self.current = np.asarray(current, float)
        components = sea_components(sea)
        self.sea = components if components.amplitude.shape[0] > 0 else None
        for grp in self.groups:
            if self.sea is not None and hasattr(grp.lines, "sea"):  # DEM lines (quasi-static ones have no drag)
                grp.lines.sea = self.sea
        steps = [0.5 * grp.lines.stable_step() for grp in self.groups]
        self.line_dt = min(steps) if steps else math.inf
        self.time = 0.0
        # in waves: the sea at the platform's points at the ends of intervals of steps (None: still water)
        self.wave_intervals = WaveIntervals(self.sea) if self.sea is not None else None
        self.ice = np.zeros((len(bodies), 6))
        self.mooring_force = np.zeros((len(bodies), 3))  # pull of all lines on each body [N]
        # one free body on one group of DEM lines in still water: two compiled calls a step (fused_step.py)
        self.fused = FusedStep(self) if FusedStep.applies(self) else None

    @property
    def moorings(self):
        """The first group's lines (None without moorings)."""
        return self.groups[0].lines if self.groups else None

    @property
    def attachments(self) -> list[Attachment]:
        return self.groups[0].attachments if self.groups else []

    # -- geometry ------------------------------------------------------------------------------
    def fairlead_positions(self, group: int = 0) -> tuple[np.ndarray, np.ndarray]:
        """(n_lines, 3) fairlead positions [m] and velocities [m/s] of one group from the bodies' poses."""
        if not self.groups:
            return np.zeros((0, 3)), np.zeros((0, 3))
        line, body, point = self.groups[group].arrays()
        x, v, q, omega = self._body_arrays()
        return fairlead_kinematics(line, body, point, x, v, q, omega, len(line))

    def _body_arrays(self):
        """Every body's x, v, q, omega stacked: (n, 3), (n, 3), (n, 4), (n, 3)."""
        bodies = self.bodies
        return (np.array([b.x for b in bodies]), np.array([b.v for b in bodies]), np.array([b.q for b in bodies]),
                np.array([b.omega for b in bodies]))

    def poses(self) -> np.ndarray:
        """(n_bodies, 13): x, q, v, omega of each body (what rank 0 broadcasts)."""
        if self.fused is not None:
            return self.fused.poses()
        return np.array([b.pose_vector() for b in self.bodies]).reshape(len(self.bodies), 13)

    # -- the step ------------------------------------------------------------------------------
    def begin_step(self, half_dt: float, dt: float) -> None:
        """``kick(half_dt)`` then ``drift(dt)`` [s]: one compiled call on the fused path."""
        if self.fused is not None:
            self.fused.begin_step(half_dt, dt)
            return
        self.kick(half_dt)
        self.drift(dt)

    def finish_step(self, ice: np.ndarray, half_dt: float) -> np.ndarray:
        """``loads(ice)`` then ``kick(half_dt)`` [s]; returns the fairlead tensions (n_lines,) [N] of
        the new loads (``fairlead_tensions``), which the peaks track: one compiled call on the fused
        path. The array is reused by the next step."""
        self.ice = np.asarray(ice, float).reshape(len(self.bodies), 6)
        if self.fused is not None:
            return self.fused.finish_step(self.ice, self.mooring_force, half_dt)
        self.loads()
        tensions = self.fairlead_tensions()
        self.kick(half_dt)
        return tensions

    def kick(self, half_dt: float) -> None:
        if self.fused is not None:
            self.fused.kick(half_dt)
            return
        for b in self.bodies:
            b.kick(half_dt, self.time)

    def drift(self, dt: float) -> None:
        """Move the bodies by dt and sub-step the lines with their fairleads following the hulls. In
        waves the sea's sums are taken first when this step starts an interval (``wave_points``, at
        the poses and nodes of now), and the lines interpolate them over the step."""
        if self.fused is not None:
            self.fused.drift(dt)
            return
        waves = self.wave_intervals
        if waves is not None:
            waves.begin_step(dt, self.time, self.wave_points)
        for b in self.bodies:
            b.drift(dt)
        start = self.time
        self.time += dt
        for k, grp in enumerate(self.groups):
            x, v = self.fairlead_positions(k)
            nsub = max(1, int(math.ceil(dt / self.line_dt - 1e-12)))
            if waves is not None and f"group{k}" in waves.ends:
                ends = waves.ends[f"group{k}"]
                grp.lines.advance(dt / nsub, nsub, x, v, t_start=start,
                                  waves=(ends[0], ends[1], waves.fraction(waves.step), waves.fraction(waves.step + 1)))
            else:
                grp.lines.advance(dt / nsub, nsub, x, v, t_start=start)
        if waves is not None:
            waves.step += 1

    def wave_points(self) -> dict:
        """The points whose sea the platform sums (platform.wave_intervals), at the poses of now:
        "group<k>" the nodes of DEM line group k, "body<k>/corners" and "body<k>/slices" the wave
        panels' vertices and the brace slices of free body k (hull_waves.wave_points):
        {name: (x (n, 3) [m], fields, level [m])}."""
        out = {}
        for k, grp in enumerate(self.groups):
            if hasattr(grp.lines, "sea"):  # DEM lines (quasi-static ones feel no waves)
                out[f"group{k}"] = (grp.lines.x, WAVE_FIELDS, grp.lines.water.level)
        for k, b in enumerate(self.bodies):
            if b.free:
                for name, (x, fields) in wave_points(b).items():
                    out[f"body{k}/{name}"] = (x, fields, self.level)
        return out

    def body_waves(self, k: int) -> dict | None:
        """The sea at free body k's wave points now, interpolated in the held interval
        ({"corners": ..., "slices": ...}, hull_waves.wave_loads); None when no interval holds this
        step (the loads at t = 0, before the first step): the body sums it itself."""
        waves = self.wave_intervals
        if waves is None or waves.step is None or not waves.holds(waves.step) or f"body{k}/corners" not in waves.ends:
            return None
        return {name: waves.at(f"body{k}/{name}", waves.step) for name in ("corners", "slices")}

    def loads(self, ice: np.ndarray | None = None) -> None:
        """Total force and moment on every body: ice (n_bodies, 6, reduced from all ranks), water,
        gravity, damping, current and the mooring lines' pull at the fairleads."""
        if ice is not None:
            self.ice = np.asarray(ice, float).reshape(len(self.bodies), 6)
        if self.fused is not None:
            self.fused.loads(self.ice, self.mooring_force)
            return
        for k, b in enumerate(self.bodies):
            if not b.free:  # a prescribed body moves as told: its loads drive nothing (the ice load
                continue    # and the lines' pull are reported from self.ice and the lines)
            f, m = b.hydro_loads(rho_w=self.rho_w, g=self.g, level=self.level, current=self.current, sea=self.sea,
                                 t=self.time, waves=self.body_waves(k))
            b.force = f + self.ice[k, :3]
            b.torque = m + self.ice[k, 3:]
        n = len(self.bodies)
        force = np.array([b.force for b in self.bodies], float).reshape(n, 3)
        torque = np.array([b.torque for b in self.bodies], float).reshape(n, 3)
        total = np.zeros((n, 3))
        q = np.array([b.q for b in self.bodies], float).reshape(n, 4)
        free = np.array([b.free for b in self.bodies], np.bool_)
        for grp in self.groups:
            line, body, point = grp.arrays()
            add_line_pull(line, body, point, q, grp.lines.reactions(grp.lines.fairleads), free, force, torque, total)
        for k, b in enumerate(self.bodies):
            if b.free:
                b.force, b.torque = force[k], torque[k]
        self.mooring_force = total

    def energies(self) -> dict[str, float]:
        """Energies [J] of the bodies and the lines:

        body_kinetic_energy     sum of RigidBody.kinetic_energy: 1/2 v_B . (m + m_a) v_B plus the
                                rotational 1/2 L_B . (I + I_a)^-1 L_B, with the added mass the
                                equation of motion carries (1/2 m v^2 + 1/2 w . I w without it);
        mooring_kinetic_energy  1/2 m |v|^2 of the DEM line nodes, with their added mass on the
                                velocity normal to the line; 0 for quasi-static lines;
        mooring_elastic_energy  1/2 EA/l0 (l - l0)^2 over the taut DEM elements (tension only, as
                                the bonds); for quasi-static lines the closed-form strain energy
                                of each elastic catenary at its last solve, integral T^2/(2 EA) ds.
        """
        body = sum(b.kinetic_energy() for b in self.bodies)
        kinetic = elastic = 0.0
        for grp in self.groups:
            k, e = grp.lines.energies()
            kinetic += k
            elastic += e
        return {"body_kinetic_energy": float(body), "mooring_kinetic_energy": kinetic,
                "mooring_elastic_energy": elastic}

    def fairlead_tensions(self) -> np.ndarray:
        """(n_lines,) tension [N] at every fairlead, groups in order."""
        if len(self.groups) == 1:
            return self.groups[0].lines.fairlead_tensions()
        return np.concatenate([g.lines.fairlead_tensions() for g in self.groups]) if self.groups else np.zeros(0)

    def anchor_tensions(self) -> np.ndarray:
        return np.concatenate([g.lines.anchor_tensions() for g in self.groups]) if self.groups else np.zeros(0)

    @property
    def n_lines(self) -> int:
        return sum(len(g.attachments) for g in self.groups)

    def polylines(self) -> tuple[np.ndarray, np.ndarray]:
        """(k, 3) points [m] along every line (anchor first) and the global line index of each point."""
        pts, ids, base = [np.zeros((0, 3))], [np.zeros(0, np.int64)], 0
        for g in self.groups:
            x, i = g.lines.polylines()
            pts.append(x)
            ids.append(i + base)
            base += len(g.attachments)
        return np.vstack(pts), np.concatenate(ids)

    # -- checkpoint ----------------------------------------------------------------------------
    _BODY_STATE = ("x", "v", "q", "L", "force", "torque")

    def state(self) -> dict[str, np.ndarray]:
        """Everything that evolves, as flat arrays (the platform is rebuilt from the job first); in
        waves also "waves/...": the step count, the interval held and its ends (WaveIntervals)."""
        out = {"time": np.array(self.time), "ice": self.ice.copy()}
        for k, b in enumerate(self.bodies):
            for name in self._BODY_STATE:
                out[f"body{k}/{name}"] = np.asarray(getattr(b, name), float).copy()
        for k, g in enumerate(self.groups):
            for name, value in g.lines.state().items():
                out[f"group{k}/{name}"] = np.asarray(value).copy()
        if self.wave_intervals is not None:
            for name, value in self.wave_intervals.state().items():
                out[f"waves/{name}"] = value
        return out

    def set_state(self, s: dict) -> None:
        self.time = float(s["time"])
        self.ice = np.asarray(s["ice"], float).copy()
        for k, b in enumerate(self.bodies):
            for name in self._BODY_STATE:
                setattr(b, name, np.asarray(s[f"body{k}/{name}"], float).copy())
        for k, g in enumerate(self.groups):
            g.lines.set_state({name[len(f"group{k}/"):]: v for name, v in s.items() if name.startswith(f"group{k}/")})
        if self.wave_intervals is not None:
            self.wave_intervals.set_state({name[len("waves/"):]: v for name, v in s.items()
                                           if name.startswith("waves/")})
