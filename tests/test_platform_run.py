"""A floating body in the time loop (issue 4): ice-hull contact on every rank, the body on rank 0.

References: Newton's third law (the ice load on the hull is the negative of the hull's push on the
ice, so ice + body momentum is conserved where no other horizontal force acts), kinematics of a
prescribed velocity, the checkpoint contract of issue 5 (bit for bit on the same rank count), and
the rigid-body transform of the hull in the VTK export.
"""

from __future__ import annotations

import pathlib

import h5py
import numpy as np
import pytest

from pice.io.checkpoint import read_checkpoint, write_checkpoint
from pice.io.vtk_export import export_vtk
from pice.job import parse_job
from pice.kernels.geometry import rotation_matrix
from pice.runner import run_job
from pice.simulation import Simulation

try:
    import tomllib
except ModuleNotFoundError:  # pragma: no cover
    import tomli as tomllib

# 12 m x 10 m of 1 m ice at 1 m/s, its front 0.05 m from a 20 m x 16 m x 6 m box barge
JOB = """\
[run]
duration = {duration}
dt = 1.0e-4
series_every = {series_every}
snapshots = 3

[water]
density = 1025.0
current = [{current}, 0.0]
drag_coefficient = {drag}
depth = 60.0

[ice]
thickness = 1.0
element_diameter = 1.0
length = 12.0
width = 10.0
origin = [0.0, -5.0]
velocity = [1.0, 0.0]
youngs_modulus = 1.0e9
flexural_strength = 0.3e6
compressive_strength = 1.5e6

[bond]
damping_ratio = 0.05

[[bodies]]
name = "barge"
hull = {{type = "box", size = [20.0, 16.0, 6.0]}}
mass = "balance"
inertia = [4.0e8, 6.0e8, 9.0e8]
position = [22.05, 0.3, 0.0]
{body_extra}
"""

MOORING = """
[[moorings]]
body = "barge"
model = "{model}"
fairleads = [[32.05, 8.3, -3.0], [12.05, 8.3, -3.0], [12.05, -7.7, -3.0], [32.05, -7.7, -3.0]]
headings = [45.0, 135.0, 225.0, 315.0]
anchor_depth = 57.0
pretension = 20.0e3
element_length = 10.0
[[moorings.segments]]
length = 120.0
ea = 5.0e8
diameter = 0.05
wet_weight = 150.0
"""


def job_text(*, duration=0.05, series_every=50, current=0.0, drag=0.0, body_extra="", mooring=None) -> str:
    text = JOB.format(duration=duration, series_every=series_every, current=current, drag=drag,
                      body_extra=body_extra)
    return text + (MOORING.format(model=mooring) if mooring else "")


def make(text: str, tmp_path: pathlib.Path | None = None):
    return parse_job(tomllib.loads(text), source="platform.toml", text=text, base_dir=tmp_path)


def momentum(sim) -> np.ndarray:
    p, n = sim.p, sim.p.nlocal
    ice = (p.mass[:n, None] * p.v[:n]).sum(axis=0)
    b = sim.platform.bodies[0]
    return ice + (b.mass + b.added_mass[:3]) * b.v


def test_ice_and_hull_exchange_momentum_exactly():
    """No current, no drag, no damping, no lines: the horizontal momentum of ice + body is constant
    through the impact (Newton's third law; both are kicked with the same force of the same step).
    Tolerance 1e-9 of the initial momentum: the sums over particles round differently only."""
    sim = Simulation(make(job_text()))
    p0 = momentum(sim)
    sim.advance(1500)
    p1 = momentum(sim)
    assert sim.platform.bodies[0].v[0] > 1e-3, "the ice must have hit the barge"
    assert abs(p1[0] - p0[0]) < 1e-9 * abs(p0[0])
    assert abs(p1[1] - p0[1]) < 1e-9 * abs(p0[0])


def test_prescribed_body_moves_as_told():
    """A body with a prescribed constant velocity (a ship pushed at 0.5 m/s) moves x = x0 + v t
    whatever the ice does to it (within 1e-9 m over 1000 steps), and the ice load on it is reported."""
    extra = 'motion = "prescribed"\nvelocity = [[0.0, -0.5, 0.0, 0.0, 0.0, 0.0, 0.0], [10.0, -0.5, 0.0, 0.0, 0.0, 0.0, 0.0]]'
    sim = Simulation(make(job_text(body_extra=extra)))
    sim.advance(1000)
    b = sim.platform.bodies[0]
    assert np.allclose(b.x, [22.05 - 0.5 * sim.c.time, 0.3, 0.0], atol=1e-9, rtol=0)
    row = sim.series_row()
    assert row["ice_force_max"][0, 0] > 1e5  # N: the ice is pushed back by the advancing hull


@pytest.mark.parametrize("model", ["dem", "quasi_static"])
def test_restart_with_body_and_lines_is_bit_for_bit(tmp_path, model):
    """Checkpoint after 300 steps, go on 300 more; a restart from the checkpoint ends in the same
    body pose, line nodes and ice positions, bit for bit (the issue 5 contract, now with a platform)."""
    job = make(job_text(duration=0.06, current=0.5, drag=1.0, mooring=model), tmp_path)
    sim = Simulation(job)
    sim.advance(300)
    ckpt = write_checkpoint(sim, tmp_path / "c.ckpt.h5")
    sim.rebuild_for_checkpoint()
    sim.advance(300)
    again = Simulation.from_checkpoint(job, read_checkpoint(ckpt))
    again.advance(300)
    a, b = sim.platform, again.platform
    assert np.array_equal(a.bodies[0].x, b.bodies[0].x) and np.array_equal(a.bodies[0].q, b.bodies[0].q)
    assert np.array_equal(a.polylines()[0], b.polylines()[0])
    assert np.array_equal(a.fairlead_tensions(), b.fairlead_tensions())
    assert np.array_equal(sim.p.x[np.argsort(sim.p.gid)], again.p.x[np.argsort(again.p.gid)])


def test_run_file_and_vtk_carry_the_platform(tmp_path):
    """Series rows hold the pose, the ice load with its extremes between rows and the line tensions;
    the VTK hull is the body-frame mesh moved by the snapshot's pose (x = x_cg + R(q) p)."""
    path = tmp_path / "platform.toml"
    path.write_text(job_text(duration=0.1, series_every=200, mooring="dem"))
    from pice.job import load_job

    out = tmp_path / "run.h5"
    run_job(load_job(path), output=out, progress=None)
    with h5py.File(out) as f:
        s = f["series"]
        n = len(s["time"])
        assert s["body_position"].shape == (n, 1, 3) and s["fairlead_tension"].shape == (n, 4)
        assert (s["ice_force_max"][:, 0, 0] >= s["ice_force"][:, 0, 0]).all()
        assert (s["ice_force_min"][:, 0, 0] <= s["ice_force"][:, 0, 0]).all()
        assert s["ice_force_max"][:, 0, 0].max() > 1e5
        np.testing.assert_allclose(s["fairlead_tension"][0], 20.0e3, rtol=0.01)  # the pretension
        # the "balance" mass as resolved at set-up: the 20 x 16 x 3 m^3 the box displaces plus the
        # lines' vertical pull of the t = 0 row (Archimedes)
        mass = f.attrs["body_mass"]
        assert f.attrs["bodies"] == 1 and f.attrs["mooring_lines"] == 4 and mass.shape == (1,)
        np.testing.assert_allclose(mass[0], 1025.0 * 960.0 + s["mooring_force"][0, 0, 2] / 9.81, rtol=1e-12)
        last = f["snapshots"][sorted(f["snapshots"])[-1]]
        pose = last["body_pose"][0]
        v0 = f["snapshots/00000/hull0_vertices"][()]
    res = export_vtk(out, tmp_path / "vtk")
    names = sorted(p.name for p in res["files"])
    assert "bodies_00002.vtu" in names and "moorings_00002.vtu" in names
    import meshio

    hull = meshio.read(tmp_path / "vtk" / "bodies_00002.vtu")
    np.testing.assert_allclose(hull.points, v0 @ rotation_matrix(pose[3:7]).T + pose[:3], atol=1e-12)
    lines = meshio.read(tmp_path / "vtk" / "moorings_00002.vtu")
    assert len(lines.cells_dict["line"]) == 4 * 12  # 120 m lines in 10 m elements


@pytest.mark.parametrize("model", [None, "dem", "quasi_static"])
def test_balance_mass_floats_the_body_with_its_lines(model):
    """mass = "balance" (resolved before the body is built): its weight is the buoyancy of the hull at
    the given position plus the lines' vertical pull at their initial layout (Archimedes), so at
    t = 0 the net vertical load on the body vanishes (1e-12 of its weight; no ice touches it yet).
    Without lines the box barge carries what it displaces, 1025 kg/m^3 x 20 x 16 x 3 m^3 (1e-12);
    the lines pull it down, so with them it is lighter. describe() reports the resolved mass."""
    sim = Simulation(make(job_text(mooring=model)))
    b = sim.platform.bodies[0]
    assert abs(b.force[2]) < 1e-12 * b.mass * 9.81
    if model is None:
        assert b.mass == pytest.approx(1025.0 * 960.0, rel=1e-12)
    else:
        assert sim.platform.mooring_force[0, 2] < 0.0 and b.mass < 1025.0 * 960.0
        assert b.mass == pytest.approx(1025.0 * 960.0 + sim.platform.mooring_force[0, 2] / 9.81, rel=1e-12)
    assert sim.describe()["body_mass"] == [b.mass]


def test_quasi_static_lines_pull_as_the_elastic_catenary():
    """The quasi-static model's pull on a fairlead is the elastic catenary's (platform.catenary,
    Irvine 1981): horizontal tension H towards the anchor and the fairlead's vertical tension V down;
    at t = 0 each line holds the 20 kN pretension its anchor was placed for (layout solve, 1e-6)."""
    from pice.platform.catenary import Segment, solve_line

    sim = Simulation(make(job_text(mooring="quasi_static")))
    lines = sim.platform.groups[0].lines
    np.testing.assert_allclose(lines.fairlead_tensions(), 20.0e3, rtol=1e-6)
    lines.advance(0.0, 1, lines.fairlead_x + np.array([3.0, -1.0, 0.5]))  # move every fairlead
    for k in range(4):
        d = lines.fairlead_x[k] - lines.anchors_x[k]
        st = solve_line([Segment(120.0, 150.0, 5.0e8)], horizontal=float(np.hypot(d[0], d[1])),
                        vertical=float(d[2]), seabed=True)
        e = d[:2] / np.hypot(d[0], d[1])
        np.testing.assert_allclose(lines.pull[k], [-st.horizontal_tension * e[0], -st.horizontal_tension * e[1],
                                                   -st.fairlead_vertical], rtol=1e-9)
