"""A rigid, fixed, upward-breaking cone in drifting level ice: the DEM beside ISO 19906's cone loads.

The cone is the hull of a body held still (``motion = "prescribed"``, zero velocity), written as a
closed triangle mesh (``cone_mesh``, ``write_cone_mesh``): a frustum whose surface rises at
``angle_deg`` from the horizontal through the waterline diameter, a vertical neck above it (the
column Croasdale's block-turning term H_T assumes) and flat caps. ``cone_job`` puts a level sheet
in front of it, driven at the far field ([ice.push] springs, the side edges held in y) and drifting
with the current (skin drag then only brakes the broken pieces caught at the cone);
``measure_cone_load`` runs it and returns the horizontal ice load on the cone. Used by
benchmarks/cone_iso19906.py and tests/physics/test_cone_iso19906.py; docs/iso19906.md has the
comparison.
"""

from __future__ import annotations

import math
import pathlib
from typing import NamedTuple

import numpy as np

from ..platform.hulls import revolved


def cone_mesh(*, diameter: float, angle_deg: float, below: float, above: float, neck: float,
              segments: int = 48) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(vertices (nv, 3) [m], triangles (nt, 3), centre (3,) [m]) of the cone, closed and outward.

    The surface's waterline (z = 0) circle has ``diameter`` [m]; the slope runs from ``below`` [m]
    under the waterline to ``above`` [m] over it, then the neck rises vertically ``neck`` [m] more.
    The ``segments``-gon's vertices lie on the circles. The vertices are returned in the body frame,
    origin at the solid's centroid (its centre of gravity if homogeneous); ``centre`` is where
    that origin lies when the waterline is at z = 0.
    """
    cot = 1.0 / math.tan(math.radians(angle_deg))
    r_w = 0.5 * diameter
    rings = [(-below, r_w + below * cot), (above, r_w - above * cot), (above + neck, r_w - above * cot)]
    if rings[1][1] <= 0.0:
        raise ValueError(f"the slope closes below z = {above} m: lower `above` or widen the cone")
    v, t = revolved(rings, segments)
    a, b, c = v[t[:, 0]], v[t[:, 1]], v[t[:, 2]]
    vol6 = np.einsum("ij,ij->i", a, np.cross(b, c))  # six times the signed tetrahedra volumes
    centre = (vol6[:, None] * (a + b + c)).sum(axis=0) / (4.0 * vol6.sum())
    return v - centre, t, centre


def write_cone_mesh(path: str | pathlib.Path, **geometry) -> np.ndarray:
    """Write ``cone_mesh(**geometry)`` to ``path`` (any meshio format, e.g. .stl, .vtu); return its centre."""
    import meshio

    v, t, centre = cone_mesh(**geometry)
    meshio.write(str(path), meshio.Mesh(v, [("triangle", t)]))
    return centre


def cone_job(mesh: str | pathlib.Path, centre, *, diameter: float, angle_deg: float, thickness: float,
             element_diameter: float, duration: float, speed: float = 0.5, length: float = 50.0,
             width: float = 60.0, friction: float = 0.15, youngs_modulus: float = 1.0e9,
             flexural_strength: float = 0.56e6, stiffness: float = 1.0e6) -> dict:
    """The job (a dict for pice.job.parse_job) of a sheet ``length`` x ``width`` [m] of ``thickness``
    [m] drifting at ``speed`` [m/s] onto the cone of ``mesh`` (its body-frame origin at ``centre``).

    The sheet is centred on the cone's axis in y, its front edge 0.3 m short of where its lowest
    element would touch the slope. Its rear two rows are tied to anchors moving at ``speed`` and its
    side edges held in y, by springs of ``stiffness`` [N/m] per element (the far field, as in
    jobs/zhu_ji_2022_semisub.toml). The ice is the reference scene's: rho_i 920, rho_w 1035 kg/m^3,
    ``youngs_modulus`` [Pa], nu 0.3, ``flexural_strength`` [Pa], sigma_c 2.5 MPa, with [crushing]
    (ISO 19906 pressure for the cone's width); ``friction`` is the ice-cone friction.
    """
    r, a = 0.5 * element_diameter, math.radians(angle_deg)
    z_c = thickness * (0.5 - 920.0 / 1035.0)  # the elements' centres when afloat [m]
    # a sphere at z_c touches the slope once its centre is r / sin(a) from it horizontally
    front = -(0.5 * diameter - z_c / math.tan(a) + r / math.sin(a)) + r - 0.3  # the sheet's front edge [m]
    return {
        "run": {"duration": duration, "check_every": 10},
        "water": {"density": 1035.0, "current": [speed, 0.0]},
        "ice": {"density": 920.0, "thickness": thickness, "element_diameter": element_diameter,
                "element_volume": "cell", "length": length, "width": width,
                "origin": [front - length, -0.5 * width], "velocity": [speed, 0.0],
                "youngs_modulus": youngs_modulus, "poissons_ratio": 0.3, "flexural_strength": flexural_strength,
                "compressive_strength": 2.5e6,
                "push": {"speed": speed, "rows": 2, "stiffness": stiffness, "side_stiffness": stiffness,
                         "damping_ratio": 1.0}},
        "bond": {"friction": 0.3, "damping_ratio": 0.1},
        "contact": {"restitution": 0.3, "friction": 0.15},
        "crushing": {"structure": "iso19906"},
        "bodies": [{"name": "cone", "hull": {"type": "mesh", "file": str(mesh)}, "mass": 5.0e6,
                    "inertia": [1.0e8, 1.0e8, 1.0e8], "position": [float(c) for c in centre],
                    "motion": "prescribed", "velocity": [[0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]],
                    "friction": friction}],
    }


class ConeRecord(NamedTuple):
    """What ``measure_cone_load`` returns: a row every ``every`` seconds."""

    time: np.ndarray      # [s] at the row
    mean_x: np.ndarray    # mean horizontal (drift-wise) ice load since the previous row [N]
    max_x: np.ndarray     # its largest value at any step since the previous row [N]
    mean_z: np.ndarray    # mean vertical ice load since the previous row [N] (down: < 0)
    ride_up: np.ndarray   # highest top of an ice element within ``near`` of the cone's axis [m]
    modes: np.ndarray     # (4,) broken bonds by failure mode 1..4 at the end
    elements: int         # elements of the sheet
    cpu: float            # process time of the run [s]


def measure_cone_load(sim, *, near: float, every: float = 0.1) -> ConeRecord:
    """Run ``sim`` to its duration and record the cone's ice load and how high the ice rides up
    within ``near`` [m] of its axis (one rank)."""
    import time as clock

    start = clock.process_time()
    steps = max(1, int(round(every / sim.dt)))
    rows = []
    while sim.c.step < sim.total_steps:
        sim.advance(min(steps, sim.total_steps - sim.c.step))
        row = sim.series_row()
        p, n = sim.p, sim.p.nlocal
        close = np.hypot(p.x[:n, 0] - sim.poses[0, 0], p.x[:n, 1] - sim.poses[0, 1]) < near
        top = p.x[:n, 2][close] + p.half_height[:n][close]
        rows.append((sim.c.time, row["ice_force_mean"][0, 0], row["ice_force_max"][0, 0],
                     row["ice_force_mean"][0, 2], float(top.max()) if top.size else 0.0))
    modes = np.bincount([int(e[4]) for e in sim.c.events], minlength=5)[1:5]
    a = np.array(rows)
    return ConeRecord(a[:, 0], a[:, 1], a[:, 2], a[:, 3], a[:, 4], modes, int(sim.n_initial),
                      clock.process_time() - start)


def summarize(rec: ConeRecord, *, start: float, window: float = 1.0) -> dict:
    """The DEM's load over t > ``start`` [s]: ``mean`` and ``peak`` (the largest at any step) of the
    horizontal load [N], ``peak_mean`` the mean of its maxima over windows of ``window`` [s] (a
    steadier peak: about one breaking cycle each), ``vertical`` the mean vertical load [N] (up > 0)
    and ``ride_up`` the mean height the ice reaches on the cone [m]."""
    on = rec.time > start + 1e-9
    t = rec.time[on]
    block = np.floor((t - start - 1e-9) / window).astype(int)
    maxima = [rec.max_x[on][block == k].max() for k in np.unique(block)]
    return dict(mean=float(rec.mean_x[on].mean()), peak=float(rec.max_x[on].max()),
                peak_mean=float(np.mean(maxima)), vertical=float(rec.mean_z[on].mean()),
                ride_up=float(rec.ride_up[on].mean()))


def iso_loads(*, diameter: float, angle_deg: float, thickness: float, ride_up: float, above: float,
              friction: float = 0.15, youngs_modulus: float = 1.0e9, flexural_strength: float = 0.56e6) -> dict:
    """ISO 19906's horizontal loads [N] on the cone for the sheet of ``cone_job`` (rho_i 920, rho_w 1035,
    nu 0.3): Croasdale (A.8.2.4.4.2) with no rubble, 3D (``croasdale``, the standard's) and 2D
    (``croasdale_2d``, l_c = w), and 3D with the rubble height the DEM shows (``croasdale_rubble``,
    h_r = ``ride_up`` [m]); Ralston (A.8.2.4.4.3, ``ralston``) with the sheet riding up to that height
    (h_r = h, D_T the diameter there, at most ``above`` [m], the top of the slope)."""
    from ..physics.iso19906 import cone_load, ralston_cone_load

    common = dict(diameter=diameter, angle_deg=angle_deg, thickness=thickness, flexural_strength=flexural_strength,
                  friction=friction, ice_density=920.0, water_density=1035.0)
    flex = dict(common, youngs_modulus=youngs_modulus, poissons_ratio=0.3, ice_friction=0.15)
    top = diameter - 2.0 * min(max(ride_up, 0.0), above) / math.tan(math.radians(angle_deg))
    return dict(croasdale=cone_load(**flex, rubble_height=0.0).horizontal,
                croasdale_2d=cone_load(**flex, rubble_height=0.0, three_d=False).horizontal,
                croasdale_rubble=cone_load(**flex, rubble_height=max(ride_up, 0.0)).horizontal,
                ralston=ralston_cone_load(**common, top_diameter=top, ride_up_thickness=thickness).horizontal)
