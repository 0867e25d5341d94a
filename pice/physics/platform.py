"""Rank 0's bodies and their mooring lines, stepped together (DESIGN.md, the step, item 5).

Per ice step of dt: ``kick`` (half step with the loads of the previous evaluation), ``drift``
(bodies move and turn; the lines sub-step at their own stable step with their fairleads carried
by the hulls), then, once the ice loads of the new pose have been reduced to rank 0, ``loads`` and
``kick`` again. Fairleads are points fixed in their body's frame; a line's pull on its fairlead
acts on the body at that point.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..kernels.rigid_body import rotation_matrix
from .body import RigidBody
from .mooring import MooringLines


@dataclass
class Attachment:
    """Line ``line`` has its fairlead at ``point`` [m] in the frame of body ``body``."""

    line: int
    body: int
    point: np.ndarray


class Platform:
    """Bodies, mooring lines and the water they sit in (rank 0 only)."""

    def __init__(self, bodies: list[RigidBody], moorings: MooringLines | None = None,
                 attachments: list[Attachment] | None = None, *, rho_w: float, g: float, level: float,
                 current=(0.0, 0.0)):
        self.bodies = bodies
        self.moorings = moorings
        self.attachments = attachments or []
        self.rho_w, self.g, self.level = rho_w, g, level
        self.current = np.asarray(current, float)
        self.line_dt = 0.5 * moorings.stable_step() if moorings is not None else math.inf
        self.time = 0.0
        self.ice = np.zeros((len(bodies), 6))

    # -- geometry ------------------------------------------------------------------------------
    def fairlead_positions(self) -> tuple[np.ndarray, np.ndarray]:
        """(n_lines, 3) fairlead positions [m] and velocities [m/s] from the bodies' poses."""
        n = len(self.attachments)
        x, v = np.zeros((n, 3)), np.zeros((n, 3))
        for a in self.attachments:
            b = self.bodies[a.body]
            arm = rotation_matrix(b.q) @ a.point
            x[a.line] = b.x + arm
            v[a.line] = b.v + np.cross(b.omega, arm)
        return x, v

    def poses(self) -> np.ndarray:
        """(n_bodies, 13): x, q, v, omega of each body (what rank 0 broadcasts)."""
        return np.array([b.pose_vector() for b in self.bodies]).reshape(len(self.bodies), 13)

    # -- the step ------------------------------------------------------------------------------
    def kick(self, half_dt: float) -> None:
        for b in self.bodies:
            b.kick(half_dt, self.time)

    def drift(self, dt: float) -> None:
        """Move the bodies by dt and sub-step the lines with their fairleads following the hulls."""
        for b in self.bodies:
            b.drift(dt)
        self.time += dt
        if self.moorings is not None:
            x, v = self.fairlead_positions()
            nsub = max(1, int(math.ceil(dt / self.line_dt - 1e-12)))
            self.moorings.advance(dt / nsub, nsub, x, v)

    def loads(self, ice: np.ndarray | None = None) -> None:
        """Total force and moment on every body: ice (n_bodies, 6, reduced from all ranks), water,
        gravity, damping, current and the mooring lines' pull at the fairleads."""
        if ice is not None:
            self.ice = np.asarray(ice, float).reshape(len(self.bodies), 6)
        for k, b in enumerate(self.bodies):
            f, m = b.hydro_loads(rho_w=self.rho_w, g=self.g, level=self.level, current=self.current)
            b.force = f + self.ice[k, :3]
            b.torque = m + self.ice[k, 3:]
        if self.moorings is not None:
            pull = self.moorings.reactions(self.moorings.fairleads)
            for a in self.attachments:
                b = self.bodies[a.body]
                arm = rotation_matrix(b.q) @ a.point
                b.force = b.force + pull[a.line]
                b.torque = b.torque + np.cross(arm, pull[a.line])

    def fairlead_tensions(self) -> np.ndarray:
        return self.moorings.fairlead_tensions() if self.moorings is not None else np.zeros(0)

    def anchor_tensions(self) -> np.ndarray:
        return self.moorings.anchor_tensions() if self.moorings is not None else np.zeros(0)
