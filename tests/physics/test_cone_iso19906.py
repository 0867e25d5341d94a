"""A DEM cone beside ISO 19906's sloping-structure load (A.8.2.4.4.2, Croasdale; docs/iso19906.md).

The scene of benchmarks/cone_iso19906.py at its coarse resolution and over half its time: a rigid,
fixed, upward-breaking cone, 60 degrees from the horizontal and 14 m across at the waterline (a mesh
hull of a body with prescribed zero velocity, pice/scenes/cone.py), and a level sheet 60 m wide of
2 m plate cells (E 1 GPa, sigma_f 0.56 MPa) drifting onto it at 0.5 m/s for 15 s, driven at the far
field; h = 0.5 m and 1.0 m.

The band, and why: Croasdale's formula breaks the sheet over a width l_c. In 2D (a wide slope)
l_c = w, the cone's width; the standard's 3D form adds the circumferential crack's reach beyond it,
l_c = w + pi^2 L_c / 4 (24 m for h = 1 m here: l_c = 2.7 w), for a sheet failing all round the cone
at once. A sheet that cracks radially first and fails in wedges lies in between, so the DEM's
largest load should lie between the 2D and the 3D (standard) values, and below the standard's
(a design formula, which Croasdale et al. 2016 found 1.6x the Confederation Bridge cones' measured
loads). Measured here: 0.52 MN (2D 0.38, 3D 0.74) and 1.20 MN (0.98, 2.44), i.e. 0.70 and 0.49 of
the standard's; the benchmark's 1 m elements over 30 s give 0.47-0.79 of it for h = 0.5-1 m, the
same band. With the thickness the loads grow as h^1.1-1.2 here (1 m elements over 30 s: h^1.1-1.3),
as Croasdale's breaking term over a fixed width (h^1.25), less steeply than the standard's 3D form
(h^1.7, its l_c growing with L_c ~ h^0.75).

Measured: ~20 s of one core (process time, on a loaded machine) for each thickness, 42 s for the file.
"""

import math

import numpy as np
import pytest

from pice.job import parse_job
from pice.scenes.cone import cone_job, cone_mesh, iso_loads, measure_cone_load, summarize, write_cone_mesh
from pice.simulation import Simulation

GEOMETRY = dict(diameter=14.0, angle_deg=60.0, below=4.0, above=3.0, neck=5.0)


def test_cone_mesh_is_closed_outward_and_centred():
    """The hull a mesh body needs (pice/platform/hulls.py): closed (every edge shared by two
    triangles, in opposite directions), outward (positive volume), origin at the centroid; its volume
    is the exact one of a frustum and a prism on the same regular 48-gons, V = z/3 (A1 + A2 + sqrt(A1 A2))."""
    v, t, centre = cone_mesh(**GEOMETRY, segments=48)
    edges = {(int(a), int(b)) for tri in t for a, b in zip(tri, np.roll(tri, -1))}
    assert len(edges) == 3 * len(t) and all((b, a) in edges for a, b in edges)
    a, b, c = v[t[:, 0]], v[t[:, 1]], v[t[:, 2]]
    vol6 = np.einsum("ij,ij->i", a, np.cross(b, c))
    np.testing.assert_allclose((vol6[:, None] * (a + b + c)).sum(axis=0) / (4.0 * vol6.sum()), 0.0, atol=1e-9)
    cot = 1.0 / math.tan(math.radians(GEOMETRY["angle_deg"]))
    r_w = 0.5 * GEOMETRY["diameter"]
    radius = [r_w + GEOMETRY["below"] * cot, r_w - GEOMETRY["above"] * cot]
    area = [24.0 * r * r * math.sin(2.0 * math.pi / 48) for r in radius]  # regular 48-gon of circumradius r
    exact = ((GEOMETRY["below"] + GEOMETRY["above"]) / 3.0 * (area[0] + area[1] + math.sqrt(area[0] * area[1]))
             + GEOMETRY["neck"] * area[1])
    assert vol6.sum() / 6.0 == pytest.approx(exact, rel=1e-12)
    np.testing.assert_allclose(centre[:2], 0.0, atol=1e-9)  # on the axis


def _run(tmp_path, h: float, seed: int | None = None):
    """One cone run; with a ``seed``, the elements' initial velocities are perturbed by 1e-9 m/s (a
    round-off-sized change, to sample the spread of a fracture record's statistics)."""
    mesh = tmp_path / f"cone_{h}.stl"
    centre = write_cone_mesh(mesh, **GEOMETRY)
    job = parse_job(cone_job(mesh, centre, diameter=GEOMETRY["diameter"], angle_deg=GEOMETRY["angle_deg"],
                             thickness=h, element_diameter=2.0, duration=15.0, length=30.0), source="cone")
    sim = Simulation(job)
    if seed is not None:
        sim.p.v[:sim.p.nlocal] += np.random.default_rng(seed).normal(0.0, 1e-9, (sim.p.nlocal, 3))
    rec = measure_cone_load(sim, near=0.5 * GEOMETRY["diameter"] + 3.0)
    return rec, summarize(rec, start=2.0)


def test_cone_load_between_croasdale_2d_and_3d_and_grows_with_thickness(tmp_path):
    """For h = 0.5 and 1.0 m: the ice fails in bending (at least 90 % of the broken bonds in mode 1,
    none crushed through: the premise of Croasdale's formula), the largest horizontal load lies
    between Croasdale's 2D and 3D loads (module docstring), and the mean and largest loads grow with
    the thickness at least as h^0.8 and at most as h^2 (Croasdale's own exponents: 1.25 for breaking
    over a fixed width, 1.7 for the standard's 3D form here).

    The largest load of one 15 s record is a single event: a change of round-off size moved it from
    0.63 to 0.76 MN at h = 0.5 m (measured, when only the bond kernel's rounding changed), while the
    mean moved 1 %. So each thickness runs three times with the initial velocities perturbed by
    1e-9 m/s, and the median of the three peaks is compared (the means are averaged)."""
    out = {}
    for h in (0.5, 1.0):
        runs = [_run(tmp_path, h, seed) for seed in (1, 2, 3)]
        dem = {key: float(np.median([d[key] for _, d in runs])) for key in ("peak", "ride_up")}
        dem["mean"] = float(np.mean([d["mean"] for _, d in runs]))
        iso = iso_loads(diameter=GEOMETRY["diameter"], angle_deg=GEOMETRY["angle_deg"], thickness=h,
                        ride_up=dem["ride_up"], above=GEOMETRY["above"])
        peaks = ", ".join(f"{d['peak'] / 1e6:.3f}" for _, d in runs)
        print(f"\nh = {h} m: DEM mean {dem['mean'] / 1e6:.3f} MN, peaks {peaks} MN (median/3D "
              f"{dem['peak'] / iso['croasdale']:.2f}), ride-up {dem['ride_up']:.2f} m; Croasdale 2D "
              f"{iso['croasdale_2d'] / 1e6:.3f}, 3D {iso['croasdale'] / 1e6:.3f} MN; breaks by mode "
              f"{runs[0][0].modes.tolist()}; {sum(r.cpu for r, _ in runs):.0f} s cpu")
        for rec, _ in runs:
            assert rec.modes[0] >= 0.9 * rec.modes.sum() > 0 and rec.modes[3] == 0
        assert iso["croasdale_2d"] < dem["peak"] < iso["croasdale"]
        out[h] = dem
    for key in ("mean", "peak"):
        k = math.log(out[1.0][key] / out[0.5][key]) / math.log(2.0)
        assert 0.8 < k < 2.0, (key, k)
