"""Gravity, buoyancy and Morison drag on floating elements (arrays in, arrays out).

Buoyancy is rho_w g times the submerged volume: of the spherical cap for "sphere" elements, or of
the element's vertical prism (footprint ``cell_area``, height 2 ``half_height``) for "cell" elements
that stand for their share of a continuous plate. It acts through the centre (no moment).
Drag is either Morison form drag on each element, the first term of Eq. 8 of Zhu & Ji (2022),
f = 1/2 C_d D^2 rho_w |v_r| v_r scaled by the submerged fraction of the element's height, or ice-ocean
skin friction on the sheet's underside, f = rho_w C_w |u_r| u_r A_f with u_r the horizontal current
relative to the element and A_f its footprint (the cell area; sqrt(3)/2 D^2, its share of a close-packed
layer, for a sphere). v_r is the current relative to the element.
"""

import math

from numba import njit

from . import JIT

SPHERE_FOOTPRINT = 2.0 * math.sqrt(3.0)  # footprint / r^2 of a sphere in a close-packed layer: sqrt(3)/2 (2r)^2


@njit(**JIT)
def submerged(zc, r, cell_area, half_height, level):
    """(submerged volume [m^3], submerged height [m], waterplane area [m^2]) of one element."""
    if cell_area > 0.0:
        h = level - (zc - half_height)
        if h <= 0.0:
            return 0.0, 0.0, 0.0
        if h >= 2.0 * half_height:
            return cell_area * 2.0 * half_height, 2.0 * half_height, 0.0
        return cell_area * h, h, cell_area
    h = level - (zc - r)
    if h <= 0.0:
        return 0.0, 0.0, 0.0
    if h >= 2.0 * r:
        return 4.0 / 3.0 * math.pi * r ** 3, 2.0 * r, 0.0
    return math.pi * h * h * (3.0 * r - h) / 3.0, h, math.pi * h * (2.0 * r - h)


@njit(**JIT)
def buoyancy_potential(zc, r, cell_area, half_height, level, rho_w, g):
    """Potential energy [J] of the buoyancy force (zero when dry): rho_w g * integral of V_sub dh."""
    if cell_area > 0.0:
        top = 2.0 * half_height
        h = level - (zc - half_height)
        if h <= 0.0:
            return 0.0
        if h <= top:
            return rho_w * g * cell_area * 0.5 * h * h
        return rho_w * g * cell_area * (0.5 * top * top + top * (h - top))
    top = 2.0 * r
    h = level - (zc - r)
    if h <= 0.0:
        return 0.0
    hh = min(h, top)
    u = math.pi * (r * hh ** 3 / 3.0 - hh ** 4 / 12.0)
    if h > top:
        u += 4.0 / 3.0 * math.pi * r ** 3 * (h - top)
    return rho_w * g * u


@njit(**JIT)
def gravity_forces(nlocal, mass, g, force):
    """Add the weight m g [N] (along -z) to owned particles: the whole of gravity where there is no water."""
    for i in range(nlocal):
        force[i, 2] -= mass[i] * g


@njit(**JIT)
def hydro_forces(nlocal, x, v, radius, mass, cell_area, half_height, g, water, heave_c, force):
    """Add gravity, buoyancy, drag and heave damping to owned particles.

    Args:
        water: physics.hydro.Water (level [m], density [kg/m^3], current_x, current_y [m/s],
            drag_coefficient [-]).
        heave_c: (n,) linear heave damping coefficient [N s/m] (wave radiation), 0 for none.
    """
    level, rho_w, ucx, ucy, cd = water.level, water.density, water.current_x, water.current_y, water.drag_coefficient
    cw = water.skin_drag_coefficient
    for i in range(nlocal):
        force[i, 2] -= mass[i] * g
        r = radius[i]
        vsub, h, awp = submerged(x[i, 2], r, cell_area[i], half_height[i], level)
        if h <= 0.0:
            continue
        force[i, 2] += rho_w * g * vsub
        frac = h / (2.0 * (half_height[i] if cell_area[i] > 0.0 else r))
        if cd > 0.0:
            vr0 = ucx - v[i, 0]
            vr1 = ucy - v[i, 1]
            vr2 = -v[i, 2]
            speed = math.sqrt(vr0 * vr0 + vr1 * vr1 + vr2 * vr2)
            c = 0.5 * cd * (2.0 * r) ** 2 * rho_w * speed * frac
            force[i, 0] += c * vr0
            force[i, 1] += c * vr1
            force[i, 2] += c * vr2
        if cw > 0.0:
            ur0 = ucx - v[i, 0]
            ur1 = ucy - v[i, 1]
            footprint = cell_area[i] if cell_area[i] > 0.0 else SPHERE_FOOTPRINT * r * r
            c = rho_w * cw * math.sqrt(ur0 * ur0 + ur1 * ur1) * footprint
            force[i, 0] += c * ur0
            force[i, 1] += c * ur1
        if heave_c[i] > 0.0:
            force[i, 2] -= heave_c[i] * v[i, 2]


@njit(**JIT)
def buoyancy_energy(nlocal, x, radius, cell_area, half_height, level, rho_w, g):
    """Sum of ``buoyancy_potential`` [J] over the first nlocal elements."""
    e = 0.0
    for i in range(nlocal):
        e += buoyancy_potential(x[i, 2], radius[i], cell_area[i], half_height[i], level, rho_w, g)
    return e
