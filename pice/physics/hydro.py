"""Water parameters for the hydrodynamics kernel."""

from __future__ import annotations

import math

import numpy as np

from ..kernels.hydro import submerged


def water_array(job) -> np.ndarray:
    """[has_water, level, rho_w, current_x, current_y, C_d, 0] for kernels.hydro.hydro_forces."""
    w = job.water
    if w is None:
        return np.zeros(7)
    return np.array([1.0, w.level, w.density, w.current[0], w.current[1], w.drag_coefficient, 0.0])


def heave_damping(job, particles) -> np.ndarray:
    """Linear heave damping [N s/m] per element: zeta * 2 sqrt(m k_w), k_w = rho_w g A_waterplane at rest.

    Stands for wave-radiation damping of a floating element; zero unless water.heave_damping_ratio > 0.
    """
    n = particles.n
    w = job.water
    if w is None or w.heave_damping_ratio == 0.0 or job.gravity == 0.0:
        return np.zeros(n)
    c = np.zeros(n)
    for i in range(n):
        _, _, awp = submerged(particles.x[i, 2], particles.radius[i], particles.cell_area[i],
                              particles.half_height[i], w.level)
        awp = awp if awp > 0 else math.pi * particles.radius[i] ** 2
        c[i] = 2.0 * w.heave_damping_ratio * math.sqrt(particles.mass[i] * w.density * job.gravity * awp)
    return c
