"""The spring boundary ([ice.push] with a stiffness): edge rows tied to anchors moving at the drive speed.

Reference: statics of springs in parallel. A sheet held back by a constant load F and dragged by N
springs whose anchors move at u reaches the drive speed u with the springs stretched so that they
carry F: the boundary force equals F and every tied element lags its anchor by F / (N k).
"""

import numpy as np
import pytest
from scenes import job_from_text

from pice.simulation import Simulation

JOB = """
gravity = 0.0
[run]
duration = 1.0
dt = 2.0e-4
[ice]
thickness = 1.0
element_diameter = 1.0
length = 8.0
width = 4.0
youngs_modulus = 1.0e9
[ice.push]
speed = 0.5
rows = 1
stiffness = 2.0e6
damping_ratio = 1.0
[bond]
breakable = false
damping_ratio = 0.1
[[loads]]
force = [-3.0e4, 0.0, 0.0]
[loads.region]
"""


def test_spring_boundary_carries_the_load_at_the_drive_speed():
    job = job_from_text(JOB, source="spring.toml")
    sim = Simulation(job)
    tied = sim.p.anchor_k[:, 0] > 0
    n_tied = int(tied.sum())
    assert n_tied >= 2 and not sim.p.fix_mask.any()  # springs, not a prescribed velocity
    sim.advance(int(round(1.5 / sim.dt)))  # ~20 time constants of the stiff, critically damped system
    row = sim.series_row()
    np.testing.assert_allclose(row["boundary_force"], 3.0e4, rtol=1e-3)  # statics, round-off + decay
    np.testing.assert_allclose(sim.p.v[:, 0], 0.5, atol=1e-4)
    lag = sim.p.anchor[tied, 0] + 0.5 * sim.c.time - sim.p.x[tied, 0]
    np.testing.assert_allclose(lag.mean(), 3.0e4 / (n_tied * 2.0e6), rtol=1e-2)


def test_side_springs_hold_the_sheet_in_y():
    """[ice.push] side_stiffness: the outermost elements of the side edges are tied in y only. A
    lateral load F on the unbreakable sheet is carried, once settled, by the y springs of the rear row
    (k in every direction) and of the sides (k_side): sum k_y dy = F (statics of the sheet; 1e-3),
    the sides carrying their share."""
    text = JOB.replace("damping_ratio = 1.0\n[bond]", "damping_ratio = 1.0\nside_stiffness = 5.0e5\n[bond]")
    text = text.replace("force = [-3.0e4, 0.0, 0.0]", "force = [0.0, 2.0e4, 0.0]")
    sim = Simulation(job_from_text(text, source="side.toml"))
    k = sim.p.anchor_k
    rear, side = k[:, 0] > 0, (k[:, 1] > 0) & (k[:, 0] == 0)
    assert rear.any() and side.sum() >= 4 and np.all(k[side, 1] == 5.0e5) and not k[side][:, [0, 2]].any()
    sim.advance(int(round(1.0 / sim.dt)))
    dy = sim.p.x[:, 1] - sim.p.anchor[:, 1]
    np.testing.assert_allclose((k[:, 1] * dy).sum(), 2.0e4, rtol=1e-3)
    assert (k[side, 1] * dy[side]).sum() > 0.1 * 2.0e4


FINITE = JOB.replace("damping_ratio = 1.0\n[bond]", "damping_ratio = 1.0\nfar_field_length = 100.0\n[bond]")


def test_a_finite_far_field_conserves_momentum_with_the_sheet():
    """ice.push.far_field_length: the anchors are a free mass M = rho_i h W L (920 x 1 x 4 x 100 m =
    368 t) starting at the push speed, slowed by the sheet it pushes. With the load F the only force
    from outside (no gravity, no water), the momentum of far field and sheet changes by F t (Newton).
    The far field's speed is known at the half steps (leapfrog), the sheet's at the steps: the bound
    is the far field's push over one step, |F_b| dt, and round-off."""
    sim = Simulation(job_from_text(FINITE, source="finite.toml"))
    term = sim.boundary_term
    assert term.far_mass == 920.0 * 1.0 * 4.0 * 100.0
    p0 = term.far_mass * 0.5 + float((sim.p.mass[:sim.p.nlocal] * sim.p.v[:sim.p.nlocal, 0]).sum())
    n = int(round(1.5 / sim.dt))
    sim.advance(n)
    row = sim.series_row()
    p1 = term.far_mass * term.velocity[0] + float((sim.p.mass[:sim.p.nlocal] * sim.p.v[:sim.p.nlocal, 0]).sum())
    assert p1 - p0 == pytest.approx(-3.0e4 * n * sim.dt, abs=abs(row["boundary_force"]) * sim.dt + 1e-6 * p0)
    assert row["far_field_speed"] == term.velocity[0] < 0.5  # slowed, and in the series


def test_a_finite_far_field_restarts_exactly(tmp_path):
    """Its shift and speed are in the checkpoint: a run continued from a checkpoint joins the one that
    went on, bit for bit (one rank)."""
    from pice.io.checkpoint import read_checkpoint, write_checkpoint

    job = job_from_text(FINITE, source="finite.toml")
    sim = Simulation(job)
    sim.advance(500)
    sim.rebuild_for_checkpoint()
    path = write_checkpoint(sim, tmp_path / "ff.ckpt.h5")
    again = Simulation.from_checkpoint(job, read_checkpoint(path))
    sim.advance(500)
    again.advance(500)
    assert again.boundary_term.velocity[0] == sim.boundary_term.velocity[0] < 0.5
    assert np.array_equal(again.p.x[:again.p.nlocal], sim.p.x[:sim.p.nlocal])


def test_far_field_length_needs_the_springs():
    from pice.errors import JobError

    text = FINITE.replace("stiffness = 2.0e6\n", "")
    with pytest.raises(JobError, match="ice.push.far_field_length = 100.0: the far field moves the anchors"):
        job_from_text(text, source="nostiff.toml")
