"""The force-term protocol, with the worked example of docs/architecture.md (a uniform wind stress).

Reference: Newton's second law for the whole sheet. Bonds and contacts are internal forces (equal
and opposite on the two ends, kernels/bonds.py and contacts.py), so the sheet's total momentum
changes only by the external forces: with gravity off and no water, by the wind alone,
d(sum m v)/dt = sum f_wind.
"""

import numpy as np
import pytest

from pice.job import parse_job
from pice.simulation import Simulation

JOB = {
    "run": {"duration": 0.05, "dt": "auto"},
    "gravity": 0.0,
    "ice": {"length": 6.0, "width": 4.0, "thickness": 1.0, "element_diameter": 1.0,
            "element_volume": "cell", "youngs_modulus": 1.0e9},
    "bond": {"normal_strength": 1.5e6, "friction": 0.3},
}


class WindStressTerm:
    """Uniform wind stress on the ice: f = tau * footprint area [N] on every owned element."""

    name = "wind"

    def __init__(self, stress_x: float, stress_y: float):
        self.stress = (stress_x, stress_y)  # [Pa]

    def add_forces(self, p, c, dt):
        n = p.nlocal
        area = np.where(p.cell_area[:n] > 0.0, p.cell_area[:n], np.pi * p.radius[:n] ** 2)  # [m^2]
        p.force[:n, 0] += self.stress[0] * area
        p.force[:n, 1] += self.stress[1] * area


def test_the_step_applies_exactly_the_terms_the_job_declares():
    """No water and no gravity: bonds and ice contacts only; water adds the water term (which
    carries gravity), a spring boundary its own term."""
    sim = Simulation(parse_job(JOB))
    assert [t.name for t in sim.terms] == ["bonds", "ice contacts"]
    job = dict(JOB, gravity=9.81, water={"density": 1025.0},
               ice=dict(JOB["ice"], push={"speed": 1.0, "stiffness": 1e6}))
    assert [t.name for t in Simulation(parse_job(job)).terms] == ["bonds", "ice contacts", "water",
                                                                   "spring boundary"]


def test_wind_stress_term_changes_the_momentum_by_its_impulse():
    """The sheet's momentum after N steps equals N dt times the total wind force, to round-off
    (1e-9 relative: the bond forces cancel pairwise to ~1e-16 of their size per step)."""
    sim = Simulation(parse_job(JOB))
    tau = (0.8, -0.3)  # [Pa], a strong wind
    sim.terms.append(WindStressTerm(*tau))
    sim.compute_forces()  # F(t = 0) with the new term, as set-up would have done
    p = sim.p
    area = p.cell_area[:p.nlocal]
    total = np.array([tau[0] * area.sum(), tau[1] * area.sum(), 0.0])  # [N]
    steps = 200
    sim.advance(steps)
    momentum = (p.mass[:p.nlocal, None] * p.v[:p.nlocal]).sum(axis=0)
    assert momentum == pytest.approx(total * steps * sim.dt, rel=1e-9, abs=1e-9 * np.abs(total).max() * steps * sim.dt)


def test_the_hull_term_waits_for_the_poses_after_the_bonds():
    """Rank 0 posts the ghosts' update before it steps the platform, and the poses' broadcast after
    it, received only after the bonds and contacts: the other ranks compute their bonds while rank 0
    steps the platform. Recorded on the moored barge (tests/scenes.py): within a step, the ghosts'
    update posted, the platform's kick and drift, start of the broadcast, then the bonds, then its
    wait, then the hull term, and last the platform's loads and closing kick with the ice loads."""
    from scenes import barge_job, job_from_text

    sim = Simulation(job_from_text(barge_job(mooring="dem")))
    calls = []
    comm = sim.comm
    start, finish = comm.start_bcast_array, comm.finish_bcast_array

    class Spy:
        def __init__(self, term):
            self.term, self.name = term, term.name
            self.reads_poses = getattr(term, "reads_poses", False)

        def add_forces(self, p, c, dt):
            calls.append(self.name)
            self.term.add_forces(p, c, dt)

    sim.terms = [Spy(t) for t in sim.terms]
    sim.comm = type("Recording", (), {"__getattr__": lambda _, k: getattr(comm, k),
                                      "start_bcast_array": lambda _, a: calls.append("post poses") or start(a),
                                      "finish_bcast_array": lambda _, q: calls.append("wait poses") or finish(q)})()
    exchange, begin, finish_step = sim.domain.exchange, sim.platform.begin_step, sim.platform.finish_step
    sim.domain.exchange = lambda *a, **k: calls.append("post ghosts") or exchange(*a, **k)
    sim.platform.begin_step = lambda *a, **k: calls.append("platform drift") or begin(*a, **k)
    sim.platform.finish_step = lambda *a, **k: calls.append("platform loads") or finish_step(*a, **k)
    sim.advance(1)
    # the ghosts' update does not wait for rank 0's platform: it carries the ice's drift only
    assert calls.index("post ghosts") < calls.index("platform drift") < calls.index("post poses")
    assert calls.index("post poses") < calls.index("bonds") < calls.index("wait poses") < calls.index("hull contact")
    assert calls.index("hull contact") < calls.index("platform loads") and calls.count("platform loads") == 1
    assert "hull contact" in [t.name for t in sim.terms] and calls.count("hull contact") == 1
