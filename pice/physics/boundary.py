"""The spring boundary: the far-field ice, as the sheet's rear rows tied to anchors that move with it."""

from __future__ import annotations

import numpy as np

from ..kernels.boundary import spring_boundary


class SpringBoundaryTerm:
    """F = -k (x - (a + u t)) - 2 zeta sqrt(m k) (v - u) on the tied elements (kernels/boundary.py).

    ``force`` holds this rank's push of the far field on the sheet along x [N] after each step.
    """

    name = "spring boundary"

    def __init__(self, *, speed: float, damping_ratio: float):
        self.velocity = np.array([speed, 0.0, 0.0])
        self.damping_ratio = damping_ratio
        self.force = 0.0

    def add_forces(self, p, c, dt):
        self.force = spring_boundary(p.nlocal, p.x, p.v, p.mass, p.anchor, p.anchor_k, self.damping_ratio,
                                     self.velocity, c.time, p.force)
