"""Numerical stability at the extremes of the reference scene's parameters (issue 6).

A moored box barge hit by a small sheet (tests/scenes.py, barge_job), pushed to the corners: ice
0.3 to 3 m thick, current 0.05 to 3 m/s, time steps from 0.1 to 0.95 of the stability limit,
stiff and slack moorings. Each run must finish without the runaway check firing, with every
element's and the body's speed bounded and no energy created: the ice's kinetic energy stays
below that of the whole sheet moving at twice the fastest driving speed (the current, or the
sheet's initial speed), a bound a blow-up exceeds by orders of magnitude. Past the limit, the job
is refused with the limit in the message.
"""

from __future__ import annotations

import re

import numpy as np
import pytest
from scenes import barge_job, job_from_text

from pice.errors import JobError
from pice.simulation import Simulation

pytestmark = pytest.mark.slow

STEPS = 1500


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
    """What a bounded run must show: the steps taken and the largest energies and speeds met."""

    def __init__(self, job):
        self.sim = sim = Simulation(job)
        n = sim.p.nlocal
        drive = max(abs(job.water.current[0]), abs(job.ice.velocity[0]))
        self.ke_bound = 0.5 * float(sim.p.mass[:n].sum()) * (2.0 * drive) ** 2  # [J]
        self.speed_bound = 2.0 * drive + 0.5  # [m/s] for the body
        self.ke_max = self.body_speed_max = 0.0
        self.finite = True
        for _ in range(STEPS // 100):
            sim.advance(100)  # raises InstabilityError on a runaway element
            v = sim.p.v[:n]
            body = sim.platform.bodies[0]
            self.finite &= bool(np.isfinite(v).all() and np.isfinite(body.x).all())
            self.ke_max = max(self.ke_max, 0.5 * float(np.sum(sim.p.mass[:n] * np.einsum("ij,ij->i", v, v))))
            self.body_speed_max = max(self.body_speed_max, float(np.linalg.norm(body.v)))

    def check(self) -> None:
        assert self.sim.c.step == STEPS
        assert self.finite
        assert self.ke_max <= self.ke_bound, f"ice kinetic energy {self.ke_max:.3g} J above {self.ke_bound:.3g} J"
        assert self.body_speed_max < self.speed_bound


@pytest.mark.parametrize("thickness", [0.3, 3.0])
def test_thin_and_thick_ice(thickness):
    run = Run(scene(thickness=thickness))
    run.check()
    assert run.ke_max > 0.0


@pytest.mark.parametrize("current", [0.05, 3.0])
def test_slow_and_fast_current(current):
    run = Run(scene(current=current))
    run.check()
    assert run.ke_max > 0.0


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
