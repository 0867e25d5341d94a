"""The spring boundary: the far-field ice, as the sheet's rear rows tied to anchors that move with it."""

from __future__ import annotations

import numpy as np

from ..kernels.boundary import spring_boundary


class SpringBoundaryTerm:
    """F = -k (x - (a + s)) - 2 zeta sqrt(m k) (v - u) on the tied elements (kernels/boundary.py), with
    the anchors' shift s [m] and velocity u [m/s].

    An unbounded far field (``far_mass`` None): u is the push's speed and s = u t. A finite one (seed
    004's level ice of given length): the anchors are a free mass ``far_mass`` [kg] starting at the
    speed, and the sheet pushes back on it: M du/dt = -F_x, the sum of the springs' pull on the sheet
    over every rank (one reduction a step, only in this case), integrated by leapfrog (u at the half
    steps, s at the steps). Momentum is conserved between the sheet and its far field.

    ``force`` holds this rank's push of the far field on the sheet along x [N] after each step.
    """

    name = "spring boundary"

    def __init__(self, *, speed: float, damping_ratio: float, far_mass: float | None = None, comm=None):
        self.velocity = np.array([speed, 0.0, 0.0])
        self.shift = np.zeros(3)
        self.damping_ratio = damping_ratio
        self.far_mass = far_mass
        self.comm = comm
        self.force = 0.0

    @classmethod
    def of_ice(cls, ice, *, comm) -> "SpringBoundaryTerm":
        """The term of [ice.push] (with its stiffness); a finite far field weighs rho_i h W L [kg]."""
        push = ice.push
        far = None if push.far_field_length is None else ice.density * ice.thickness * ice.width * push.far_field_length
        return cls(speed=push.speed, damping_ratio=push.damping_ratio, far_mass=far, comm=comm)

    def add_forces(self, p, c, dt):
        if self.far_mass is None:
            self.shift = self.velocity * c.time  # an unbounded far field keeps its speed
        self.force = spring_boundary(p.nlocal, p.x, p.v, p.mass, p.anchor, p.anchor_k, self.damping_ratio,
                                     self.velocity, self.shift, p.force)
        if self.far_mass is not None:  # the far field slowed by the sheet's push on it (collective)
            self.velocity[0] -= self.comm.sum(self.force) / self.far_mass * dt
            self.shift[0] += self.velocity[0] * dt

    def state(self) -> dict:
        """The finite far field's state for a checkpoint (empty for an unbounded one)."""
        return {} if self.far_mass is None else {"shift": self.shift.copy(), "velocity": self.velocity.copy()}

    def set_state(self, state: dict) -> None:
        if self.far_mass is not None:
            self.shift, self.velocity = np.array(state["shift"], float), np.array(state["velocity"], float)
