"""The sea as the platform's kernels see it: a physics.waves.Sea's components as one named tuple of
arrays and scalars (numba reads it by field name), with no components for still water.

Still water is a SeaComponents whose arrays are empty: the kernels test ``sea.amplitude.shape[0]``
and take exactly their still-water arithmetic then, so a job without [waves] gives the results it
gave before the waves existed, bit for bit, at the cost of one test per call.
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
from numba import njit

from ..kernels import JIT
from ..kernels.waves import sea_point

SeaComponents = namedtuple("SeaComponents", ["amplitude", "omega", "k", "direction", "phase", "depth", "g",
                                             "density"])
SeaComponents.__doc__ = """A linear sea's components (physics/waves.py): amplitude [m], omega [rad/s], k [rad/m],
direction (n, 2) unit vectors, phase [rad], arrays of one entry per component; depth [m] (inf: deep),
g [m/s^2], density [kg/m^3] of the water. Coordinates: z up from the still water level."""


def still_water(*, g: float = 9.81, density: float = 1025.0) -> SeaComponents:
    """A sea of no components."""
    return SeaComponents(np.zeros(0), np.zeros(0), np.zeros(0), np.zeros((0, 2)), np.zeros(0), math.inf,
                         float(g), float(density))


def sea_components(sea) -> SeaComponents:
    """A physics.waves.Sea as SeaComponents (contiguous float arrays); None: still water."""
    if sea is None:
        return still_water()
    if isinstance(sea, SeaComponents):
        return sea
    c = np.ascontiguousarray
    return SeaComponents(c(sea.amplitude, float), c(sea.omega, float), c(sea.k, float),
                         c(np.asarray(sea.direction, float).reshape(-1, 2)), c(sea.phase, float), float(sea.depth),
                         float(sea.g), float(sea.density))


@njit(**JIT)
def wave_at(sea, x, y, z, t):
    """(eta [m], u_x, u_y, u_z [m/s], a_x, a_y, a_z [m/s^2], dynamic pressure [Pa]) of ``sea`` at the
    point (x, y, z) [m], z up from the still level, at time t [s] (kernels.waves.sea_point)."""
    return sea_point(sea.amplitude, sea.omega, sea.k, sea.direction, sea.phase, sea.depth, sea.g, sea.density,
                     x, y, z, t)
