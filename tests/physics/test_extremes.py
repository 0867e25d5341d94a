"""Numerical stability at the extremes of the reference scene's parameters (issue 6), and bounds on
what users read from such runs: the peak ice load on the body and its offset.

The scene: the moored box barge of tests/scenes.py (barge_job: a 12 m x 10 m sheet of n = 127
"cell" elements moving at the current's speed u, its front 0.05 m from the barge's flat face, four
DEM lines; no current drag or damping on the barge), pushed to the corners: ice 0.3 to 3 m thick,
current 0.05 to 3 m/s, time steps from 0.1 to 0.95 of the stability limit, stiff and slack
moorings; 1,500 steps, a duration D = 1,500 dt. Every run must finish without the runaway check
firing, and:

* no energy is created: the ice's kinetic energy stays below that of the whole sheet at twice the
  drive speed u, and no element moves faster than 2u (a blow-up exceeds both by orders of
  magnitude; measured 1.2u);
* contact happens when it must and only then: the sheet drifts with the current (no net drag, every
  element at its rest elevation), so its front advances u D; if u D < 0.05 m (u = 0.05 m/s, and
  dt = 0.1 of the limit: D = 0.044 s) the barge feels no load at all and stays where its lines hold
  it (within 1e-5 m; measured 1e-7 m, the DEM lines' residual against the catenary layout);
* the peak ice load stays below what the energy in the scene can press into the contacts
  (``load_bound``; measured 1/21 to 1/17 of it, the same for every case: load and bound both grow
  as u sqrt(k m), the impedance of the contact);
* the barge's offset stays below what the momentum the ice can hand over moves it in D
  (``offset_bound``; measured 1/10 to 1/3 of it).

The energy available, E_in: the ice starts at rest elevation with unstressed bonds, the barge at its
"balance" equilibrium with its lines laid out by the catenary solve, so no potential energy can be
released; the only sources are the ice's initial kinetic energy and the current's drag. The drag on
an element is 1/2 rho_w C_d d^2 |w| w (frac <= 1 submerged, relative velocity w = u - v); its power
on the element, |w| w.v, is at most (4/27) u^3 1/2 rho_w C_d d^2 (largest at w = 2u/3 along u), so
E_in = 1/2 sum m v0^2 + n (4/27) u^3 1/2 rho_w C_d d^2 D. Dashpots, heave damping and friction only
take energy away.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from scenes import barge_job, job_from_text

from pice.errors import JobError
from pice.simulation import Simulation

pytestmark = pytest.mark.slow

STEPS = 1500
GAP = 0.05  # [m] from the sheet's front to the barge's face at t = 0 (barge_job)


def scene(*, thickness=1.0, current=1.0, safety=0.5, pretension=20.0e3, element_length=10.0):
    text = barge_job(duration=1.0, current=current, drag=1.0, mooring="dem")
    edits = (("dt = 1.0e-4", f'dt = "auto"\ndt_safety = {safety}'),
             ("thickness = 1.0", f"thickness = {thickness}\nelement_volume = \"cell\""),
             ("velocity = [1.0, 0.0]", f"velocity = [{current}, 0.0]"),
             ("pretension = 20.0e3", f"pretension = {pretension}"),
             ("element_length = 10.0", f"element_length = {element_length}"))
    for old, new in edits:
        assert old in text, old
        text = text.replace(old, new, 1)
    return job_from_text(text, source="platform.toml")


class Run:
    """The scene run for STEPS steps; every 100 steps the largest energies, speeds and offset so far;
    at the end the extremes of the ice load on the barge over every step (the series' peaks)."""

    def __init__(self, job):
        self.job = job
        self.sim = sim = Simulation(job)
        p, n = sim.p, sim.p.nlocal
        body = sim.platform.bodies[0]
        self.u = max(abs(job.water.current[0]), abs(job.ice.velocity[0]))  # the drive speed [m/s]
        self.duration = STEPS * sim.dt  # [s]
        self.ice_mass = float(p.mass[:n].sum())  # [kg]
        self.ke0 = 0.5 * float(np.sum(p.mass[:n] * np.einsum("ij,ij->i", p.v[:n], p.v[:n])))  # [J]
        self.ke_bound = 0.5 * self.ice_mass * (2.0 * self.u) ** 2  # [J]
        self.speed_bound = 2.0 * self.u + 0.5  # [m/s] for the body
        reach = float(np.linalg.norm(sim.hulls[0].vertices, axis=1).max())  # [m] CG to the farthest hull point
        x0 = body.x.copy()
        self.ke_max = self.body_speed_max = self.ice_speed_max = self.hull_speed_max = self.offset_max = 0.0
        self.finite = True
        sim.peaks.take()  # the extremes from here on
        for _ in range(STEPS // 100):
            sim.advance(100)  # raises InstabilityError on a runaway element
            v = p.v[:n]
            self.finite &= bool(np.isfinite(v).all() and np.isfinite(body.x).all())
            self.ke_max = max(self.ke_max, 0.5 * float(np.sum(p.mass[:n] * np.einsum("ij,ij->i", v, v))))
            self.ice_speed_max = max(self.ice_speed_max, float(np.linalg.norm(v, axis=1).max()))
            self.body_speed_max = max(self.body_speed_max, float(np.linalg.norm(body.v)))
            self.hull_speed_max = max(self.hull_speed_max,
                                      float(np.linalg.norm(body.v) + np.linalg.norm(body.omega) * reach))
            self.offset_max = max(self.offset_max, float(np.hypot(*(body.x[:2] - x0[:2]))))
        peaks = sim.peaks.take()
        self.peak_load = float(np.linalg.norm(np.maximum(peaks["ice_max"][0], -peaks["ice_min"][0])))  # [N]

    def energy_in(self) -> float:
        """E_in [J]: the ice's initial kinetic energy and the most the current's drag can add in D
        (module docstring)."""
        w = self.job.water
        drag = 0.5 * w.density * w.drag_coefficient * self.element_diameter() ** 2  # [N s^2/m^2]
        return self.ke0 + self.sim.p.nlocal * 4.0 / 27.0 * self.u ** 3 * drag * self.duration

    def element_diameter(self) -> float:
        return 2.0 * float(self.sim.p.radius[:self.sim.p.nlocal].max())

    def load_bound(self) -> float:
        """The largest ice load [N] the contact law can give with E_in in the scene.

        Each of the N <= n elements touching the hull pushes with F_n = k delta - c u_n (>= 0) along
        the normal, c = 2 zeta sqrt(m k), plus a tangential force capped at mu F_n: |F_i| <=
        sqrt(1 + mu^2) (k delta_i + c |u_n,i|). With E_el = sum k delta_i^2 / 2 and
        E_kin >= sum m_i u_i^2 / 2 (velocities relative to the hull, which moves at most at the
        recorded V), Cauchy-Schwarz gives sum k delta_i <= sqrt(2 N k E_el) and
        sum c |u_n,i| <= 2 zeta sqrt(2 N k) (sqrt(E_kin) + sqrt(M / 2) V); E_el + E_kin <= E_in, so
        sqrt(E_el) + 2 zeta sqrt(E_kin) <= sqrt(1 + 4 zeta^2) sqrt(E_in).
        """
        law = self.sim.hulls[0].law
        n = self.sim.p.nlocal
        hull = 2.0 * law.zeta * math.sqrt(0.5 * self.ice_mass) * self.hull_speed_max
        return math.sqrt(1.0 + law.mu ** 2) * math.sqrt(2.0 * n * law.kn) * (
            math.sqrt(1.0 + 4.0 * law.zeta ** 2) * math.sqrt(self.energy_in()) + hull)

    def offset_bound(self) -> float:
        """The largest horizontal offset [m] of the barge in D from the momentum the ice can hand over.

        Only the ice pushes the barge (no current drag or damping on it; buoyancy is vertical; its
        lines start balanced and pull it back). The ice's horizontal momentum goes from M u to no
        less than -sqrt(2 M E_in) (its kinetic energy stays below E_in), and the current adds at most
        n 1/2 rho_w C_d d^2 (3u)^2 D (relative speed <= 3u for elements no faster than 2u, checked).
        So the barge of mass M_b (its added mass left out, which only slows it) moves no faster than
        J / M_b and no farther than D J / M_b.
        """
        w = self.job.water
        drag = 0.5 * w.density * w.drag_coefficient * self.element_diameter() ** 2
        impulse = (self.ice_mass * self.u + math.sqrt(2.0 * self.ice_mass * self.energy_in())
                   + self.sim.p.nlocal * drag * (3.0 * self.u) ** 2 * self.duration)  # [N s]
        return self.duration * impulse / self.sim.platform.bodies[0].mass

    def check(self) -> None:
        assert self.sim.c.step == STEPS
        assert self.finite
        assert self.ke_max <= self.ke_bound, f"ice kinetic energy {self.ke_max:.3g} J above {self.ke_bound:.3g} J"
        assert self.ice_speed_max <= 2.0 * self.u, f"an element at {self.ice_speed_max:.3g} m/s"
        assert self.body_speed_max < self.speed_bound
        if self.u * self.duration < GAP:  # the front cannot reach the barge
            assert self.peak_load == 0.0
            assert self.offset_max < 1e-5
        else:
            assert 0.0 < self.peak_load <= self.load_bound(), (self.peak_load, self.load_bound())
            assert self.offset_max <= self.offset_bound(), (self.offset_max, self.offset_bound())


@pytest.mark.parametrize("thickness", [0.3, 3.0])
def test_thin_and_thick_ice(thickness):
    run = Run(scene(thickness=thickness))
    run.check()
    assert run.ke_max > 0.0 and run.peak_load > 0.0


@pytest.mark.parametrize("current", [0.05, 3.0])
def test_slow_and_fast_current(current):
    run = Run(scene(current=current))
    run.check()
    assert run.ke_max > 0.0
    assert (run.peak_load > 0.0) == (current == 3.0)  # at 0.05 m/s the front moves 0.011 m of the 0.05 m


@pytest.mark.parametrize("safety", [0.1, 0.95])
def test_time_step_from_a_tenth_to_nearly_the_limit(safety):
    run = Run(scene(safety=safety))
    run.check()
    assert run.sim.dt == pytest.approx(safety * run.sim.limit.stable, rel=1e-12)


@pytest.mark.parametrize("pretension,element_length", [(80.0e3, 5.0), (10.0e3, 20.0)], ids=["stiff", "slack"])
def test_stiff_and_slack_moorings(pretension, element_length):
    run = Run(scene(pretension=pretension, element_length=element_length))
    run.check()
    assert (run.sim.platform.fairlead_tensions() > 0).all()


def test_past_the_limit_is_refused_with_the_limit():
    limit = Simulation(scene()).limit.stable
    with pytest.raises(JobError, match=re.escape(f"{limit:.4g}")):
        Simulation(scene(safety=1.0).model_copy(update={"run": scene().run.model_copy(update={"dt": 1.2 * limit})}))
