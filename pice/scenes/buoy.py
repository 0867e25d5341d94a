"""The moored buoy of Cai (2018, seed 004, section 4.2): a hollow steel double cone (issue 16).

From the keel up the hull is a short cylinder of the minimum diameter, a cone widening downwards
at the downward-sloping hull angle alpha (from the horizontal) to the maximum diameter, and a cone
narrowing upwards at the upward-sloping angle theta back to the minimum diameter at the top. With
the thesis's pre-designed buoy (Table 4-2: D_max 9 m, D_min 5 m, H 3 m, alpha 45 deg, theta 14.04
deg) the cylinder is H / 6 = 0.5 m high, as its Eq. 4-16 has it, and the widest section lies 2.5 m
above the keel.

The hull is a thin steel shell (Eqs. 4-19..4-21): its mass is rho_s t S for the surface area S and
the equivalent thickness t. ``shell_properties`` integrates the shell over the hull's triangles:
mass, centre of gravity and inertia tensor, where the thesis approximates the inertia by a hollow
cone with KG = 1 m (Eq. 4-18).
"""

from __future__ import annotations

import math

import numpy as np

from ..platform.hulls import buoy_design_profile

STEEL_DENSITY = 7850.0  # [kg/m^3] (Eq. 4-19)

design_profile = buoy_design_profile  # one design of Table 6-1 (its home: platform.hulls)


def buoy_profile(*, d_max: float, d_min: float, height: float, alpha_deg: float, theta_deg: float):
    """(z, r) rings [m] of the buoy hull, keel at z = 0 (module docstring), for platform.hulls.revolved.

    Raises ValueError when the two cones do not fit the height."""
    r_max, r_min = 0.5 * d_max, 0.5 * d_min
    if not (0.0 < r_min < r_max):
        raise ValueError(f"d_min = {d_min} m, d_max = {d_max} m: need 0 < d_min < d_max")
    lower = (r_max - r_min) * math.tan(math.radians(alpha_deg))
    upper = (r_max - r_min) * math.tan(math.radians(theta_deg))
    keel = height - lower - upper
    if keel < 0.0:
        raise ValueError(f"height = {height} m: the cones at {alpha_deg} and {theta_deg} deg need "
                         f"{lower + upper:.4g} m; raise the height or lower the hull angles")
    rings = [(0.0, r_min)] + ([(keel, r_min)] if keel > 0.0 else []) + [(keel + lower, r_max), (height, r_min)]
    return np.array(rings)


def surface_area(vertices: np.ndarray, triangles: np.ndarray) -> float:
    """Area [m^2] of a triangle mesh."""
    a, b, c = (vertices[triangles[:, k]] for k in range(3))
    return float(0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1).sum())


def shell_properties(vertices: np.ndarray, triangles: np.ndarray, *, mass: float):
    """(equivalent thickness t [m], centre of gravity (3,) [m], inertia tensor (3, 3) [kg m^2] about it) of
    a thin steel shell of ``mass`` [kg] over the mesh: t = mass / (rho_s S) (Eq. 4-21), the mass spread
    uniformly over the area. A triangle's second moment of area is exact: A / 12 (sum v v^T + s s^T)
    with s the sum of its vertices."""
    a, b, c = (vertices[triangles[:, k]] for k in range(3))
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    total = area.sum()
    sigma = mass / total  # [kg/m^2]
    centre = (area[:, None] * (a + b + c) / 3.0).sum(axis=0) / total
    a, b, c = a - centre, b - centre, c - centre
    s = a + b + c
    second = np.einsum("t,tij->ij", area / 12.0,
                       np.einsum("ti,tj->tij", a, a) + np.einsum("ti,tj->tij", b, b) + np.einsum("ti,tj->tij", c, c)
                       + np.einsum("ti,tj->tij", s, s)) * sigma
    inertia = np.trace(second) * np.eye(3) - second
    return mass / (STEEL_DENSITY * total), centre, inertia


def stationary_draft(vertices: np.ndarray, triangles: np.ndarray, *, mass: float, rho_w: float = 1025.0) -> float:
    """The keel's depth [m] at which a hull of revolution (keel at z = 0, upright) of ``mass`` [kg]
    floats: rho_w V(d) = mass, from the mesh buoyancy (platform.hull_buoyancy). NaN when the closed
    hull cannot carry its mass (it sinks)."""
    from scipy.optimize import brentq

    from ..platform.hull_buoyancy import BRACE_RECORD, submerged

    def excess(d):
        return rho_w * submerged(vertices, triangles, np.zeros(0, BRACE_RECORD), position=np.zeros(3),
                                 attitude=np.array([1.0, 0.0, 0.0, 0.0]), level=d)[0] - mass

    top = float(vertices[:, 2].max())
    if excess(top) < 0.0:
        return math.nan
    return float(brentq(excess, 0.0, top, xtol=1e-10))

