"""A hull as a thin shell of uniform areal density: its mass, centre of gravity and inertia.

``mass = "shell"`` on a body (pice/job/platform.py) makes its mass rho_s t S, the steel of a shell of
thickness t [m] and density rho_s [kg/m^3] over the hull's surface S (seed 004, Eqs. 4-19..4-21),
and its inertia that of the shell about its centre. A hull of revolution (types "buoy" and
"revolved") is integrated over its true circles (``revolved_shell``, exact: the mass does not depend
on how many sides the mesh has); any other hull over its triangles (``mesh_shell``, exact for the
flat faces it has).
"""

from __future__ import annotations

import math

import numpy as np

# 2-point Gauss-Legendre on [0, 1]: exact for the cubics in s along a frustum's slant
_GAUSS_S = np.array([0.5 - 0.5 / math.sqrt(3.0), 0.5 + 0.5 / math.sqrt(3.0)])


def revolved_shell(profile, *, areal_density: float) -> tuple[float, np.ndarray, np.ndarray]:
    """(mass [kg], centre (3,) [m], principal inertia (roll, pitch, yaw) (3,) [kg m^2] about the centre)
    of the closed shell of revolution about z through the (z, r) rings ``profile`` [m] (as
    hulls.revolved: conical frusta between the rings, flat caps at both ends) of ``areal_density``
    [kg/m^2].

    Over a frustum (z, r) = (z1 + s dz, r1 + s dr), s in [0, 1], dA = 2 pi r L ds with L its slant;
    a cap of radius R at z adds pi R^2, with int r^2 dA = pi R^4 / 2. Then I_zz = sigma int r^2 dA and,
    by symmetry, I_xx = I_yy = sigma int (r^2 / 2 + (z - z_G)^2) dA."""
    prof = np.asarray(profile, float).reshape(-1, 2)
    area = mz = mzz = mrr = 0.0
    for (z1, r1), (z2, r2) in zip(prof[:-1], prof[1:]):
        slant = math.hypot(z2 - z1, r2 - r1)
        r = r1 + _GAUSS_S * (r2 - r1)
        z = z1 + _GAUSS_S * (z2 - z1)
        w = 0.5 * 2.0 * math.pi * slant * r  # quadrature weight x dA/ds
        area, mz, mzz, mrr = area + w.sum(), mz + (w * z).sum(), mzz + (w * z * z).sum(), mrr + (w * r * r).sum()
    for z, r in (prof[0], prof[-1]):
        a = math.pi * r * r
        area, mz, mzz, mrr = area + a, mz + a * z, mzz + a * z * z, mrr + 0.5 * a * r * r
    zg = mz / area
    izz = areal_density * mrr
    ixx = areal_density * (0.5 * mrr + mzz - area * zg * zg)
    return areal_density * area, np.array([0.0, 0.0, zg]), np.array([ixx, ixx, izz])


def mesh_shell(vertices: np.ndarray, triangles: np.ndarray, *,
               areal_density: float) -> tuple[float, np.ndarray, np.ndarray]:
    """(mass [kg], centre (3,) [m], inertia tensor (3, 3) [kg m^2] about the centre) of the triangles
    of a mesh [m] as a shell of ``areal_density`` [kg/m^2]. A triangle's second moment of area is
    exact: A / 12 (sum v v^T + s s^T) with s the sum of its vertices."""
    a, b, c = (vertices[triangles[:, k]] for k in range(3))
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    total = float(area.sum())
    centre = (area[:, None] * (a + b + c) / 3.0).sum(axis=0) / total
    a, b, c = a - centre, b - centre, c - centre
    s = a + b + c
    second = areal_density * np.einsum("t,tij->ij", area / 12.0, np.einsum("ti,tj->tij", a, a)
                                       + np.einsum("ti,tj->tij", b, b) + np.einsum("ti,tj->tij", c, c)
                                       + np.einsum("ti,tj->tij", s, s))
    return areal_density * total, centre, np.trace(second) * np.eye(3) - second
