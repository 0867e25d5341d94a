"""A hull in waves (issue 14, seed 003 Eq. 11): the pressure of the undisturbed linear sea on the
wetted hull surface, integrated panel by panel, and on the braces slice by slice.

With a sea (physics/waves.Sea; platform.sea.SeaComponents) the water pressure at a point r of the
hull is the hydrostatic and the undisturbed dynamic pressure together,

    p(r) = rho_w g (level - z) + p_d(x, y, z - level, t),

and it acts on the part of each triangle below the undisturbed surface over it: the triangle is
clipped at level + eta, eta the mean of the elevations over its three corners, and -p n dA is
integrated over the clipped part exactly for p linear across it (p at the corners of the clipped
polygon; at a cut point p_d is interpolated along its edge). Above the still level the linear
kinematics hold their z = 0 values (physics/waves.py), so p vanishes at z = level + eta: the cut is
where the pressure ends. In still water (eta = p_d = 0) the integral is rho_w g V at the centre of
buoyancy, the Eq. 12 volume of hull_buoyancy, by the divergence theorem (tests/physics/
test_platform_waves.py checks that to round-off); with waves it is the hydrostatic load of the
instantaneous wetted hull plus the Froude-Krylov load (Eq. 11's first term) in one integral, for a
hull of any size against the waves, moments included.

Panels: p is taken linear across a panel, so a panel should be short against the wavelength;
``panel_mesh`` splits a hull's triangles until no edge is longer than a given length (build.py
asks for a tenth of the peak wavelength).

Braces (Eqs. 13-14): each slice's submerged section is cut at level + eta over its axis point, its
buoyancy rho_w g dV acts at the section's centroid, and the Froude-Krylov load of a slender member,
rho_w dV a (a: the undisturbed particle acceleration at the axis point; -grad p_d = rho_w a in
linear theory), adds to it.

The sea at the points: the kernels read it per point, (eta, p_d) at every panel corner and (eta,
u, a) at every slice's axis point, not the sea itself. ``wave_loads`` sums it there at its time
(platform.wave_intervals.corner_waves and node_waves) or takes it from the platform, which sums it
at the ends of intervals of several steps at the points' places at the interval's start and
interpolates it linearly in time (platform.wave_intervals; docs/waves.md, Cost). Either way the
panels are cut, and the hydrostatic pressure taken, at the body's pose of the moment: only the
per-corner sums are interpolated, never the force. Every corner gets its sea, so a waterline
triangle reaching above the highest possible surface still takes the mean of its three corners'
elevations.

Kernels are pure numba functions of arrays and scalars.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..kernels import JIT
from ..kernels.geometry import rotation_matrix
from .hull_buoyancy import brace_axis, slice_section, transform
from .wave_intervals import CORNER_FIELDS, WAVE_FIELDS, corner_waves, node_waves


@njit(**JIT)
def _add_panel(a, b, c, pa, pb, pc, centre, force, moment):
    """Add -int p n dA and -int (r - centre) x p n dA over the triangle (a, b, c) (outward
    orientation) for p linear across it with corner values pa, pb, pc [Pa]."""
    s = 0.5 * np.cross(b - a, c - a)             # n dA [m^2]
    mean = (pa + pb + pc) / 3.0
    # int p r dA / A for linear p and r: ((2 pa + pb + pc) a + ...) / 12
    pr = ((2.0 * pa + pb + pc) * (a - centre) + (pa + 2.0 * pb + pc) * (b - centre)
          + (pa + pb + 2.0 * pc) * (c - centre)) / 12.0
    m = np.cross(pr, s)
    for q in range(3):
        force[q] -= mean * s[q]
        moment[q] -= m[q]


@njit(**JIT)
def hull_wave_pressure(vertices, triangles, level, reach, corner, rho_w, g, centre):
    """(force (3,) [N], moment about ``centre`` (3,) [N m]) of the water pressure, hydrostatic and
    undisturbed dynamic, on the hull mesh below the wave surface (module docstring).

    vertices: (nv, 3) space frame [m]; triangles: (nt, 3) outward; level: still water level [m];
    reach: the highest the surface can rise [m], level + the sum of the amplitudes (a triangle whose
    corners all lie above it is dry); corner: (nv, CORNER_FIELDS) the sea at each vertex, eta [m]
    over it and p_d [Pa] at it (wave_intervals.corner_waves, or interpolated in time between two of
    its sums); rho_w [kg/m^3]; g [m/s^2]; centre (3,) [m] (the CG).
    """
    eta = corner[:, 0]
    pd = corner[:, 1]
    near = vertices[:, 2] <= reach
    force = np.zeros(3)
    moment = np.zeros(3)
    poly = np.empty((4, 3))
    pres = np.empty(4)
    for tri in range(triangles.shape[0]):
        i0, i1, i2 = triangles[tri, 0], triangles[tri, 1], triangles[tri, 2]
        if not (near[i0] or near[i1] or near[i2]):
            continue
        surface = level + (eta[i0] + eta[i1] + eta[i2]) / 3.0
        npoly = 0
        for e in range(3):  # Sutherland-Hodgman against the half-space z <= surface
            ia, ib = triangles[tri, e], triangles[tri, (e + 1) % 3]
            a, b = vertices[ia], vertices[ib]
            a_in, b_in = a[2] <= surface, b[2] <= surface
            if a_in:
                poly[npoly] = a
                pres[npoly] = rho_w * g * (level - a[2]) + pd[ia]
                npoly += 1
            if a_in != b_in:
                s = (surface - a[2]) / (b[2] - a[2])
                poly[npoly] = a + s * (b - a)
                poly[npoly, 2] = surface
                pres[npoly] = rho_w * g * (level - surface) + (1.0 - s) * pd[ia] + s * pd[ib]
                npoly += 1
        for k in range(1, npoly - 1):
            _add_panel(poly[0], poly[k], poly[k + 1], pres[0], pres[k], pres[k + 1], centre, force, moment)
    return force, moment


@njit(**JIT)
def brace_points(braces, R, position, slices):
    """(k slices, 3) [m] the axis points of the braces' slices (``brace_wave_loads``), braces placed
    by R (3, 3) and position [m], brace after brace."""
    out = np.empty((braces.shape[0] * slices, 3))
    for kb in range(braces.shape[0]):
        p0 = R @ braces[kb]["p0"] + position
        p1 = R @ braces[kb]["p1"] + position
        for k in range(slices):
            out[kb * slices + k] = p0 + (k + 0.5) / slices * (p1 - p0)
    return out


@njit(**JIT)
def brace_wave_loads(braces, R, position, level, slices, wave, rho_w, g):
    """(force (3,) [N], moment about ``position`` (3,) [N m]) of buoyancy and Froude-Krylov load on
    the braces (k,) BRACE_RECORD of the body frame, placed by R (3, 3) and position [m]: each slice
    cut at level + eta over its axis point, rho_w g dV up at its section's centroid plus rho_w dV a
    (module docstring). wave: (k slices, WAVE_FIELDS) the sea at the slices' axis points
    (``brace_points``), eta [m] and the acceleration [m/s^2] read."""
    force = np.zeros(3)
    moment = np.zeros(3)
    for kb in range(braces.shape[0]):
        p0 = R @ braces[kb]["p0"] + position
        p1 = R @ braces[kb]["p1"] + position
        axis, length, cos_t, down = brace_axis(p0, p1)
        dl = length / slices
        for k in range(slices):
            c = p0 + (k + 0.5) / slices * axis
            w = wave[kb * slices + k]
            area, drop = slice_section(c[2] - (level + w[0]), cos_t, braces[kb]["radius"])
            if area <= 0.0:
                continue
            dv = area * dl
            df = np.array([rho_w * dv * w[4], rho_w * dv * w[5], rho_w * dv * (g + w[6])])
            m = np.cross(c + drop * down - position, df)
            for q in range(3):
                force[q] += df[q]
                moment[q] += m[q]
    return force, moment


def panel_mesh(vertices, triangles, max_edge: float) -> tuple[np.ndarray, np.ndarray]:
    """(vertices, triangles) of the same surface with every triangle split by its barycentric grid
    into n^2 triangles, n = ceil(longest edge / max_edge [m]): panels for ``hull_wave_pressure``.
    Neighbours may split a shared edge differently (T-junctions): the panels still tile the surface
    exactly, which is all a pressure integral needs."""
    v = np.asarray(vertices, float)
    out_v, out_t, base = [], [], 0
    for a, b, c in np.asarray(triangles, np.int64):
        pa, pb, pc = v[a], v[b], v[c]
        edge = max(np.linalg.norm(pb - pa), np.linalg.norm(pc - pb), np.linalg.norm(pa - pc))
        n = max(1, int(math.ceil(edge / max_edge - 1e-9)))
        index = {}
        for i in range(n + 1):
            for j in range(n + 1 - i):
                index[i, j] = base + len(index)
                out_v.append(pa + (i / n) * (pb - pa) + (j / n) * (pc - pa))
        for i in range(n):
            for j in range(n - i):
                out_t.append((index[i, j], index[i + 1, j], index[i, j + 1]))
                if i + j < n - 1:
                    out_t.append((index[i + 1, j], index[i + 1, j + 1], index[i, j + 1]))
        base += len(index)
    return np.asarray(out_v, float), np.asarray(out_t, np.int64)


def wave_points(body) -> dict:
    """The points whose sea a RigidBody's wave loads read, at its pose: {"corners": ((nv, 3) [m] its
    wave panels' vertices, CORNER_FIELDS), "slices": ((k, 3) [m] its braces' slice axis points,
    WAVE_FIELDS)} (platform.wave_intervals sums the sea there)."""
    R = rotation_matrix(body.q)
    x = np.asarray(body.x, float)
    v_b, _ = body.wave_panels
    return {"corners": (transform(v_b, R, x), CORNER_FIELDS),
            "slices": (brace_points(body.braces, R, x, int(body.brace_slices)), WAVE_FIELDS)}


def wave_loads(body, sea, t: float, *, rho_w: float, g: float, level: float,
               waves=None) -> tuple[np.ndarray, np.ndarray]:
    """(force [N], moment about the CG [N m]) of the water pressure on a RigidBody's wave panels
    (body.wave_panels) and braces at its pose in ``sea`` (SeaComponents) at time t [s].

    waves: {"corners": (nv, CORNER_FIELDS), "slices": (k, WAVE_FIELDS)} the sea at the points of
    ``wave_points`` (interpolated in time by the platform, platform.wave_intervals; the cut and the
    hydrostatic pressure are still taken at the pose of the moment); None: summed here at time t,
    at the pose."""
    R = rotation_matrix(body.q)
    x = np.asarray(body.x, float)
    if waves is None:
        waves = {}
        for name, (pts, fields) in wave_points(body).items():
            now = np.empty((len(pts), fields))
            (corner_waves if fields == CORNER_FIELDS else node_waves)(sea, pts, float(level), float(t), float(t),
                                                                      now, np.empty_like(now))
            waves[name] = now
    v_b, t_b = body.wave_panels
    reach = float(level) + float(np.abs(sea.amplitude).sum())
    f, m = hull_wave_pressure(transform(v_b, R, x), t_b, float(level), reach, waves["corners"], float(rho_w),
                              float(g), x)
    if len(body.braces):
        fb, mb = brace_wave_loads(body.braces, R, x, float(level), int(body.brace_slices), waves["slices"],
                                  float(rho_w), float(g))
        f, m = f + fb, m + mb
    return f, m
