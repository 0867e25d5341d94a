"""The platform's step as two compiled calls: one free body on one group of DEM lines in still water.

``Platform`` steps its bodies and lines through Python objects: a rigid body's kick, drift and loads,
the fairleads' kinematics, the lines' sub-steps and their pull, each a kernel called with its own
arguments and small numpy arrays between them. In a full-scene step rank 0 does this between the
ice's kernels, which evict its code and data every step, so the glue costs more than the arithmetic
(docs/performance.md, "The platform and the output"). For the common case (one free body, its lines
DEM, still water: the reference scene, the Kulluk in calm water, the buoy) this module makes each of
``kick``, ``drift`` and ``loads`` one kernel call on the body's state packed in (1, k) arrays, with
the same arithmetic in the same order as the general path, so the results are the same bits
(tests/unit/test_platform.py). A step takes two: ``begin_step`` (the kick and the drift) and
``finish_step`` (the loads, the fairlead tensions and the closing kick), as each call costs more in
Python glue reloaded from memory than in arithmetic.

The body's ``x``, ``v``, ``q``, ``L``, ``force`` and ``torque`` become views of the packed rows, so
everything that reads the body (poses, output, energies, checkpoints) sees the state; code that
assigns a new array to one of them (``Platform.set_state``, a test) is noticed before the next call
and the rows are packed again.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..kernels import JIT
from .attachment_kernels import add_line_pull, fairlead_kinematics
from .mooring_line_kernels import advance_lines
from .rigid_body import angular_velocity, free_rotation, kick_free, still_water_loads

_STATE = ("x", "v", "q", "L", "force", "torque")


@njit(**JIT)
def kick_body(v, L, q, force, torque, mass, half_dt):
    """Half a step [s] of the body's momentum in place (rigid_body.kick_free on row 0)."""
    vn, Ln = kick_free(v[0], L[0], q[0], force[0], torque[0], mass, half_dt)
    v[0] = vn
    L[0] = Ln


@njit(**JIT)
def drift_body_and_lines(x, v, q, L, inertia, line, body, point, n_lines, dt, nsub, lx, lv, lmass, prev, seg,
                         props, constants, kind, water, current, seabed, no_waves, lforce, tension, added_mass,
                         tangent, fairleads):
    """The body moves and turns by dt [s] (x += v dt, the torque-free rotation), then the lines take
    nsub sub-steps of dt / nsub with their fairleads carried from where they were to the body's new
    pose (Platform.drift and MooringLines.advance in still water)."""
    x[0] = x[0] + dt * v[0]
    q[0] = free_rotation(q[0], L[0], inertia, dt)
    omega = np.empty((1, 3))
    omega[0] = angular_velocity(q[0], L[0], inertia)
    fx, fv = fairlead_kinematics(line, body, point, x, v, q, omega, n_lines)
    start = lx[fairleads]
    advance_lines(lx, lv, lmass, prev, seg, props, constants, kind, water, current, seabed, no_waves, no_waves,
                  0.0, 1.0, lforce, tension, added_mass, tangent, fairleads, start, fx, fv, dt / nsub, nsub)


@njit(**JIT)
def body_loads(vertices, triangles, braces, brace_slices, x, v, q, L, mass, inertia, added_mass, damping,
               current_drag, current, rho_w, g, level, ice, line, body, point, lforce, fairleads, free, force,
               torque, total):
    """The body's force [N] and moment [N m] in place: still water (rigid_body.still_water_loads), the
    ice's load ``ice`` (1, 6) and the lines' pull at the fairleads; ``total`` (1, 3) the lines' pull."""
    f, m = still_water_loads(vertices, triangles, braces, brace_slices, x[0], v[0], q[0], L[0], mass, inertia,
                             added_mass, damping, current_drag, current, rho_w, g, level)
    force[0] = f + ice[0, :3]
    torque[0] = m + ice[0, 3:]
    total[:] = 0.0
    add_line_pull(line, body, point, q, lforce[fairleads], free, force, torque, total)


@njit(**JIT)
def kick_and_drift(x, v, q, L, inertia, line, body, point, n_lines, dt, nsub, lx, lv, lmass, prev, seg, props,
                   constants, kind, water, current, seabed, no_waves, lforce, tension, added_mass, tangent, fairleads,
                   force, torque, kick_mass, half_dt):
    """The start of a step in one call: ``kick_body`` by half_dt [s] with ``kick_mass`` [kg] (the mass
    with the added mass), then ``drift_body_and_lines`` by dt [s] (its arguments first)."""
    kick_body(v, L, q, force, torque, kick_mass, half_dt)
    drift_body_and_lines(x, v, q, L, inertia, line, body, point, n_lines, dt, nsub, lx, lv, lmass, prev, seg, props,
                         constants, kind, water, current, seabed, no_waves, lforce, tension, added_mass, tangent,
                         fairleads)


@njit(**JIT)
def loads_and_kick(vertices, triangles, braces, brace_slices, x, v, q, L, mass, inertia, added_mass, damping,
                   current_drag, current, rho_w, g, level, ice, line, body, point, lforce, fairleads, free, force,
                   torque, total, tensions, kick_mass, half_dt):
    """The end of a step in one call: ``body_loads``, the fairlead tensions [N] (|force| at each
    fairlead node, as mooring_lines.node_force_norms) into ``tensions``, then ``kick_body`` by
    half_dt [s] with ``kick_mass`` [kg] (the mass with the added mass)."""
    body_loads(vertices, triangles, braces, brace_slices, x, v, q, L, mass, inertia, added_mass, damping,
               current_drag, current, rho_w, g, level, ice, line, body, point, lforce, fairleads, free, force, torque,
               total)
    for k in range(len(fairleads)):
        f = lforce[fairleads[k]]
        tensions[k] = math.sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2])
    kick_body(v, L, q, force, torque, kick_mass, half_dt)


@njit(**JIT)
def body_pose(x, q, v, L, inertia):
    """(1, 13) x, q, v, omega of the body (RigidBody.pose_vector): a new array, as the poses' broadcast
    holds it while it travels."""
    out = np.empty((1, 13))
    out[0, 0:3] = x[0]
    out[0, 3:7] = q[0]
    out[0, 7:10] = v[0]
    out[0, 10:13] = angular_velocity(q[0], L[0], inertia)
    return out


class FusedStep:
    """Platform.kick, drift and loads of one free body on one group of DEM lines in still water
    (``applies``; anything else takes Platform's general path)."""

    def __init__(self, platform):
        self.platform = platform
        self.body = platform.bodies[0]
        self.group = platform.groups[0]
        b = self.body
        self.mass = b.mass + b.added_mass[:3]          # the kick's diagonal mass [kg]
        self.inertia = b.effective_inertia              # with the added inertia [kg m^2]
        self.free = np.ones(1, np.bool_)
        self.no_waves = self.group.lines._no_waves
        self.tensions = np.zeros(len(self.group.lines.fairleads))  # the step's fairlead tensions [N] (finish_step)
        self.pack()

    @staticmethod
    def applies(platform) -> bool:
        """One free body, one group of lines, DEM, and still water."""
        from .mooring_lines import MooringLines

        return (len(platform.bodies) == 1 and platform.bodies[0].free and platform.sea is None
                and len(platform.groups) == 1 and isinstance(platform.groups[0].lines, MooringLines))

    def pack(self) -> None:
        """Copy the body's state into the packed rows and make its attributes views of them."""
        b = self.body
        self.rows = {name: np.array(getattr(b, name), float).reshape(1, -1) for name in _STATE}
        for name, row in self.rows.items():
            setattr(b, name, row[0])
        self.views = tuple(getattr(b, name) for name in _STATE)  # the very objects (row[0] makes a new view)

    def _bound(self) -> None:
        b, views = self.body, self.views
        if not (b.x is views[0] and b.v is views[1] and b.q is views[2] and b.L is views[3] and b.force is views[4]
                and b.torque is views[5]):
            self.pack()

    def poses(self) -> np.ndarray:
        """(1, 13) the body's pose (Platform.poses)."""
        self._bound()
        r = self.rows
        return body_pose(r["x"], r["q"], r["v"], r["L"], self.inertia)

    def kick(self, half_dt: float) -> None:
        self._bound()
        r = self.rows
        kick_body(r["v"], r["L"], r["q"], r["force"], r["torque"], self.mass, half_dt)

    def _substeps(self, dt: float) -> int:
        """The lines' sub-steps in a step of dt [s] (Platform.drift)."""
        return max(1, int(math.ceil(dt / self.platform.line_dt - 1e-12)))

    def drift(self, dt: float) -> None:
        self.begin_step(0.0, dt, kick=False)

    def begin_step(self, half_dt: float, dt: float, kick: bool = True) -> None:
        """Platform.kick(half_dt) then Platform.drift(dt) [s] in one kernel call (``kick=False``: the drift only)."""
        self._bound()
        r, p = self.rows, self.platform
        start = p.time
        p.time += dt
        lines = self.group.lines
        nsub = self._substeps(dt)
        line, body, point = self.group.arrays()
        args = (r["x"], r["v"], r["q"], r["L"], self.inertia, line, body, point, len(line), dt, nsub,
                lines.x, lines.v, lines.mass, lines.prev, lines.seg, lines.props, lines.constants,
                lines.kind, lines.water, lines.current, lines.seabed, self.no_waves, lines.force,
                lines.tension, lines.added_mass, lines.tangent, lines.fairleads)
        if kick:
            kick_and_drift(*args, r["force"], r["torque"], self.mass, half_dt)
        else:
            drift_body_and_lines(*args)
        lines.time = start + dt / nsub * nsub

    def _loads_args(self, ice: np.ndarray, total: np.ndarray) -> tuple:
        r, p, b = self.rows, self.platform, self.body
        line, body, point = self.group.arrays()
        lines = self.group.lines
        return (b.vertices, b.triangles, b.braces, int(b.brace_slices), r["x"], r["v"], r["q"], r["L"],
                float(b.mass), self.inertia, b.added_mass, b.damping, b.current_drag, p.current, p.rho_w, p.g,
                p.level, ice, line, body, point, lines.force, lines.fairleads, self.free, r["force"], r["torque"],
                total)

    def loads(self, ice: np.ndarray, total: np.ndarray) -> None:
        """The body's force and torque from still water, ``ice`` (1, 6) and the lines; their pull into
        ``total`` (1, 3)."""
        self._bound()
        body_loads(*self._loads_args(ice, total))

    def finish_step(self, ice: np.ndarray, total: np.ndarray, half_dt: float) -> np.ndarray:
        """``loads`` and Platform.kick(half_dt) [s] in one kernel call; returns the fairlead tensions
        [N] (``self.tensions``, written again at the next step)."""
        self._bound()
        loads_and_kick(*self._loads_args(ice, total), self.tensions, self.mass, half_dt)
        return self.tensions
