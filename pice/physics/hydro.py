"""Gravity and the water on the ice: the force terms and their parameters (kernels/hydro.py).

A job without [water] gets ``GravityTerm`` alone; with [water], ``WaterTerm`` adds gravity,
buoyancy, Morison drag (Eq. 8 of Zhu & Ji 2022) and heave damping in one pass.
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np

from ..kernels.hydro import buoyancy_energy, gravity_forces, hydro_forces, submerged

Water = namedtuple("Water", ["level", "density", "current_x", "current_y", "drag_coefficient",
                             "skin_drag_coefficient"])
Water.__doc__ = """Still water with a uniform current, as the hydrodynamics kernel reads it: level [m],
density [kg/m^3], current_x, current_y [m/s], drag_coefficient [-] (C_d of Eq. 8: Morison form drag
on each element; 0 when the job asks for skin drag), skin_drag_coefficient [-] (C_w of the ice-ocean
skin friction per unit area; 0 when the job asks for Morison drag)."""


def water_from_job(job) -> Water | None:
    """The job's [water] as a Water record, or None when the job declares none."""
    w = job.water
    if w is None:
        return None
    skin = w.ice_drag == "skin"
    # the underside's stress is shared by the sheet's layers of spheres: each submerged element takes
    # its footprint's share (kernels/hydro.py), so that the sheet feels it once, whatever its layers
    return Water(level=float(w.level), density=float(w.density), current_x=float(w.current[0]),
                 current_y=float(w.current[1]), drag_coefficient=0.0 if skin else float(w.drag_coefficient),
                 skin_drag_coefficient=float(w.skin_drag_coefficient) / sphere_layers(job) if skin else 0.0)


def sphere_layers(job) -> int:
    """HCP layers of the job's sheet (1 for plate cells or no sheet): those sharing one footprint."""
    from ..scenes.level_ice import layer_count

    ice = job.ice
    if ice is None or ice.element_volume == "cell":
        return 1
    return layer_count(thickness=ice.thickness, element_diameter=ice.element_diameter)


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


class GravityTerm:
    """The weight of every owned element, m g along -z [N] (a job without [water])."""

    name = "gravity"

    def __init__(self, gravity: float):
        self.gravity = gravity

    def add_forces(self, p, c, dt):
        gravity_forces(p.nlocal, p.mass, self.gravity, p.force)


class WaterTerm:
    """Gravity, buoyancy of the submerged cap or prism, Morison drag and heave damping [N]."""

    name = "water"

    def __init__(self, water: Water, gravity: float):
        self.water, self.gravity = water, gravity

    def add_forces(self, p, c, dt):
        hydro_forces(p.nlocal, p.x, p.v, p.radius, p.mass, p.cell_area, p.half_height, self.gravity,
                     self.water, p.heave_damping, p.force)

    def buoyancy_energy(self, p) -> float:
        """Potential energy of the buoyancy of the owned elements [J]."""
        w = self.water
        return float(buoyancy_energy(p.nlocal, p.x, p.radius, p.cell_area, p.half_height, w.level, w.density,
                                     self.gravity))
