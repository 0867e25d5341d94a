"""Crushing: the elastic-perfectly-plastic contact law (kernels/contact_law.py).

Reference: seed 003 (Kulluk, Eqs. 1-2, Table 3) and seed 004 (Cai 2018, Eqs. 3-32..3-35): the
normal force of a contact is a spring-dashpot up to |F_n| <= sigma_c A_c, A_c the contact area.
For one layer of elements A_c is the chord of the overlap in plan times the element's height; an
element pressed into a plane wall by delta has the chord 2 sqrt(2 r delta - delta^2).
"""

import math

import numpy as np
import pytest

from scenes import crushing_face_job, job_from_text

from pice.job import parse_job
from pice.kernels.bonds import CRUSHED
from pice.kernels.contact_law import plastic_normal_force
from pice.physics.crushing import crush_depth
from pice.physics.iso19906 import crushing_load, crushing_pressure
from pice.simulation import Simulation

P_C = 1.0e6  # crushing pressure [Pa]


def _element_against_wall(structure=P_C):
    """One 1 m cell element of 1 m ice, its centre 0.5 m from a plane wall at x = 1 m, no gravity."""
    job = parse_job({
        "run": {"duration": 10.0}, "gravity": 0.0,
        "ice": {"length": 1.0, "width": 1.0, "thickness": 1.0, "element_diameter": 1.0, "element_volume": "cell",
                "youngs_modulus": 1e9, "flexural_strength": 5e5, "compressive_strength": 2.5e6},
        "crushing": {"structure": structure},
        "walls": [{"type": "plane", "point": [1.0, 0.0, 0.0], "normal": [-1.0, 0.0, 0.0], "friction": 0.0,
                   "crushing_width": 1.0}],
    })
    sim = Simulation(job)
    assert sim.p.n == 1 and sim.p.x[0, 0] == pytest.approx(0.5)
    return sim


def _push(sim, speed, steps):
    p = sim.p
    p.fix_mask[0] = True
    p.fix_velocity[0] = (speed, 0.0, 0.0)
    p.v[0] = p.fix_velocity[0]
    out = []
    for _ in range(steps):
        sim.step()
        delta = p.x[0, 0] + p.radius[0] - 1.0
        out.append((delta, sim.walls.force[0, 0], p.wall_hist[0, 0, 3]))  # the ice load on the wall along +x
    return np.array(out)


def test_plastic_normal_force_caps_and_remembers():
    """The law by hand: elastic up to the cap, then F = cap with delta_p = delta - cap/k; unloading
    is elastic from the plastic set; cap = inf is the elastic law."""
    kn = 1e8
    f, dp = plastic_normal_force(kn, 0.0, 1.0, 1e-3, 0.0, 0.0, 5e4)
    assert (f, dp) == (5e4, pytest.approx(1e-3 - 5e-4))
    f, dp2 = plastic_normal_force(kn, 0.0, 1.0, 0.8e-3, dp, 0.0, 5e4)
    assert f == pytest.approx(kn * (0.8e-3 - dp)) and dp2 == dp
    assert plastic_normal_force(kn, 0.0, 1.0, 0.4e-3, dp, 0.0, 5e4) == (0.0, dp)
    assert plastic_normal_force(kn, 0.0, 1.0, 1e-3, 0.0, 0.0, math.inf) == (kn * 1e-3, 0.0)


def test_wall_load_follows_crushing_pressure_times_contact_area():
    """An element driven slowly into a wall: once yielding, the wall load is p_c 2 sqrt(2 r delta -
    delta^2) h at every step to 1 % (the elastic part k (delta - delta_p) is held at the cap and the
    total, dashpot included, never exceeds it), and the plastic penetration is delta - F/k."""
    sim = _element_against_wall()
    speed = 1e-2
    steps = int(0.1 / (speed * sim.dt))
    rec = _push(sim, speed, steps)
    delta, load, dp = rec.T
    touching = delta > 0.01
    chord = 2.0 * np.sqrt(2 * 0.5 * delta - delta**2)
    np.testing.assert_allclose(load[touching], P_C * chord[touching] * 1.0, rtol=1e-2)
    kn = sim.walls.params["kn"][0]
    np.testing.assert_allclose(dp[touching], delta[touching] - load[touching] / kn, rtol=1e-6, atol=1e-9)
    assert sim.walls.crushing == 1  # the wall term counts the contact in plastic flow
    assert list(sim.series_row()["crushing_contacts"]) == [0.0, 1.0]  # ice-ice, ice-structure


def test_no_crushing_section_means_elastic_contacts():
    """Without [crushing] the same push gives the elastic load k delta (cap = inf, no plastic set), to
    1 % once delta > 1 mm (the dashpot's c v, 5.8 kN at 1 cm/s, is then under 0.7 % of k delta)."""
    job_text = dict(run={"duration": 1.0}, gravity=0.0,
                    ice={"length": 1.0, "width": 1.0, "thickness": 1.0, "element_diameter": 1.0,
                         "element_volume": "cell", "youngs_modulus": 1e9, "flexural_strength": 5e5,
                         "compressive_strength": 2.5e6},
                    walls=[{"type": "plane", "point": [1.0, 0.0, 0.0], "normal": [-1.0, 0.0, 0.0], "friction": 0.0}])
    sim = Simulation(parse_job(job_text))
    rec = _push(sim, 1e-2, 2000)
    delta, load, dp = rec.T
    kn = sim.walls.params["kn"][0]
    on = delta > 1e-3
    assert on.sum() > 100
    np.testing.assert_allclose(load[on], kn * delta[on], rtol=1e-2)
    assert not dp.any()


def test_iso_pressure_is_eq15_over_the_contact_face():
    """crushing.structure = "iso19906": the wall's pressure is ISO 19906's p_G for the ice thickness and
    the wall's crushing_width: p_G h w = Eq. 15's 40.1 MN for h = 1 m, w = 50 m (seed 000)."""
    assert crushing_pressure(thickness=1.0, width=50.0) * 1.0 * 50.0 == pytest.approx(40.1e6, rel=1e-3)
    assert crushing_pressure(thickness=1.0, width=50.0) * 50.0 == pytest.approx(
        crushing_load(thickness=1.0, diameter=50.0), rel=1e-12)
    sim = _element_against_wall(structure="iso19906")
    assert sim.walls.params["crushing_pressure"][0] == pytest.approx(crushing_pressure(thickness=1.0, width=1.0))


def _face_run(*, d, h=1.0, duration=4.0, speed=0.5, length=30.0, width=50.0):
    """A sheet `width` wide, driven at the far field (rear rows on springs to anchors at `speed`)
    against a rigid vertical plane as wide as the sheet, with ISO 19906 crushing for that width.
    Returns (time [s], load on the face along x [N], crushed elements) every 0.05 s, and p_G h w [N];
    the simulation itself is ``_face_run.last``."""
    job = job_from_text(crushing_face_job(length=length, width=width, d=d, h=h, speed=speed, stiffness=2e7 * d,
                                          run=f"duration = {duration!r}\ncheck_every = 10"), source="face.toml")
    sim = Simulation(job)
    every = max(1, int(0.05 / sim.dt))
    rows = []
    while sim.c.time < duration:
        sim.advance(every)
        r = sim.series_row()
        rows.append((sim.c.time, r["wall_force"][0][0], r["crushed_elements"]))
    _face_run.last = sim
    return np.array(rows), crushing_load(thickness=h, diameter=width)


def _crushing_phase(rows, after=4.0 / 3.0):
    """The load once the front has met the face and the sheet has taken up the drive (t > 4/3 s)."""
    return rows[rows[:, 0] > after, 1]


def test_vertical_face_mean_load_is_iso19906_with_2m_elements():
    """ISO 19906 Eq. 15 (seed 000: 40.1 MN for h = 1 m, w = 50 m) on a 50 m face: the mean load over
    the crushing phase within 25 % (the issue's tolerance; measured 1-3 % at 1-2 m elements: the
    staggered fronts of the close-packed rows overlap in contact, as each element is removed only once
    crushed through a whole diameter) and elements are being crushed through and removed."""
    rows, iso = _face_run(d=2.0, duration=6.0)
    load = _crushing_phase(rows)
    assert load.mean() == pytest.approx(iso, rel=0.25)
    assert rows[-1, 2] > 0 and np.all(np.diff(rows[:, 2]) >= 0)
    # the counts by mode: every logged break is in broken_by_mode, the crushed elements' bonds as mode 4
    sim = _face_run.last
    row = sim.series_row()
    assert row["broken_by_mode"].sum() == row["broken_bonds"] == len(sim.c.events)
    assert row["broken_by_mode"][CRUSHED - 1] >= row["crushed_elements"]   # each had >= 1 bond
    # the snapshots' crush_depth: elements at the face in plastic flow, none yet through a diameter
    depth = crush_depth(sim.p)
    assert depth.max() > 0.0 and depth.max() < 2.0 * float(sim.p.radius[0])


@pytest.mark.slow
def test_vertical_face_load_converges_with_element_size_and_stays_bounded():
    """Mean and peak load at 1, 1.5 and 2 m elements agree within 15 % (the issue), each within 25 %
    of ISO 19906; over 12 s of drive the load never exceeds 1.5 x ISO (bounded however long the
    far field pushes: the ice crushes at the face); h = 1.6 m gives ISO's 60.1 MN within 25 %."""
    means, peaks = [], []
    for d in (1.0, 1.5, 2.0):
        rows, iso = _face_run(d=d, duration=12.0 if d == 2.0 else 4.0)
        load = _crushing_phase(rows)
        means.append(load.mean())
        peaks.append(load.max())
        assert load.mean() == pytest.approx(iso, rel=0.25)
        assert load.max() < 1.5 * iso
    assert max(means) / min(means) < 1.15 and max(peaks) / min(peaks) < 1.15
    rows, iso = _face_run(d=1.0, h=1.6)
    assert iso == pytest.approx(60.1e6, rel=1e-3)
    assert _crushing_phase(rows).mean() == pytest.approx(iso, rel=0.25)
