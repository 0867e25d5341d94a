"""A floating body in the time loop (issue 4): ice-hull contact on every rank, the body on rank 0.

References: Newton's third law (the ice load on the hull is the negative of the hull's push on the
ice, so ice + body momentum is conserved where no other horizontal force acts), kinematics of a
prescribed velocity, Archimedes (the "balance" mass) and the elastic catenary (the quasi-static
lines' pull). The scene: tests/scenes.py, barge_job. The platform in the run file, the VTK export
and a checkpoint: tests/io/test_platform_output.py.
"""

from __future__ import annotations

import numpy as np
import pytest
from scenes import barge_job, job_from_text

from pice.platform.catenary import Segment, solve_line
from pice.simulation import Simulation


def momentum(sim) -> np.ndarray:
    p, n = sim.p, sim.p.nlocal
    ice = (p.mass[:n, None] * p.v[:n]).sum(axis=0)
    b = sim.platform.bodies[0]
    return ice + (b.mass + b.added_mass[:3]) * b.v


def test_ice_and_hull_exchange_momentum_exactly():
    """No current, no drag, no damping, no lines: the horizontal momentum of ice + body is constant
    through the impact (Newton's third law; both are kicked with the same force of the same step).
    Tolerance 1e-9 of the initial momentum: the sums over particles round differently only."""
    sim = Simulation(job_from_text(barge_job()))
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
    sim = Simulation(job_from_text(barge_job(body_extra=extra)))
    sim.advance(1000)
    b = sim.platform.bodies[0]
    assert np.allclose(b.x, [22.05 - 0.5 * sim.c.time, 0.3, 0.0], atol=1e-9, rtol=0)
    row = sim.series_row()
    assert row["ice_force_max"][0, 0] > 1e5  # N: the ice is pushed back by the advancing hull


@pytest.mark.parametrize("model", [None, "dem", "quasi_static"])
def test_balance_mass_floats_the_body_with_its_lines(model):
    """mass = "balance" (resolved before the body is built): its weight is the buoyancy of the hull at
    the given position plus the lines' vertical pull at their initial layout (Archimedes), so at
    t = 0 the net vertical load on the body vanishes (1e-12 of its weight; no ice touches it yet).
    Without lines the box barge carries what it displaces, 1025 kg/m^3 x 20 x 16 x 3 m^3 (1e-12);
    the lines pull it down, so with them it is lighter. describe() reports the resolved mass."""
    sim = Simulation(job_from_text(barge_job(mooring=model)))
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
    sim = Simulation(job_from_text(barge_job(mooring="quasi_static")))
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
