"""The moored buoy of Cai (2018, seed 004) as a job: the "buoy" hull, the steel shell's mass and inertia
(mass = "shell") and the start "afloat" (issue 16).

References: Table 4-2 (the pre-designed buoy: surface area 154.66 m^2, 73.28 m^3 displacing 7.51e4 kg
at the 2.24 m draft, equivalent thickness 0.0619 m, which is 75,112 / (7,850 x 154.66) = 0.06187 m
rounded), Table 6-10 (the optimised design, D_max 7.5 m at 65 deg: D_min 5.63 m, theta 28.20 deg,
S 126.09 m^2) and Table 6-9 (its weight 61.27 t with the rounded 0.0619 m). The job's hand-computed
numbers before it used the buoy hull (commit 47bf6a0): mass 75112 kg, inertia [4.72e5, 4.72e5,
7.75e5] kg m^2, the centre 1.83 m above the keel.
"""

from __future__ import annotations

import logging
import math

import numpy as np
import pytest
from scenes import REPO, tomllib

from pice.errors import JobError
from pice.job import load_job, parse_job
from pice.platform.body_setup import body_profile, mass_and_inertia
from pice.platform.build import hull_mesh, initial_poses
from pice.platform.hulls import buoy_design_profile, revolved
from pice.platform.shell import mesh_shell, revolved_shell

JOB = REPO / "jobs" / "cai_2018_buoy.toml"
STEEL = 7850.0


def test_revolved_shell_against_the_meshed_shell_and_a_closed_cylinder():
    """The exact shell of revolution against the triangles of a 4096-gon (within 1e-5), and a thin closed
    cylinder (R, L: I_zz = m_side R^2 + m_disk R^2, I_xx = m_side (R^2/2 + L^2/12) + 2 m_disk (R^2/4 + L^2/4))."""
    prof = buoy_design_profile(d_max=9.0, alpha_deg=45.0)
    mass, centre, inertia = revolved_shell(prof, areal_density=100.0)
    m2, c2, i2 = mesh_shell(*revolved(prof, 4096), areal_density=100.0)
    assert mass == pytest.approx(m2, rel=1e-5) and centre[2] == pytest.approx(c2[2], rel=1e-5)
    np.testing.assert_allclose(inertia, np.diag(i2), rtol=1e-5)
    R, L = 2.0, 3.0
    mass, centre, inertia = revolved_shell([(0.0, R), (L, R)], areal_density=1.0)
    m_side, m_disk = 2 * math.pi * R * L, math.pi * R * R
    assert mass == pytest.approx(m_side + 2 * m_disk, rel=1e-12) and centre[2] == pytest.approx(L / 2, rel=1e-12)
    ixx = m_side * (R * R / 2 + L * L / 12) + 2 * m_disk * (R * R / 4 + L * L / 4)
    np.testing.assert_allclose(inertia, [ixx, ixx, m_side * R * R + m_disk * R * R], rtol=1e-12)


def test_designs_of_tables_4_2_and_6_10():
    prof = buoy_design_profile(d_max=9.0, alpha_deg=45.0)   # Table 4-2
    np.testing.assert_allclose(prof, [[0.0, 2.5], [0.5, 2.5], [2.5, 4.5], [3.0, 2.5]], atol=1e-12)
    assert revolved_shell(prof, areal_density=1.0)[0] == pytest.approx(154.66, abs=0.005)
    prof = buoy_design_profile(d_max=7.5, alpha_deg=65.0)   # Table 6-10
    assert 2 * prof[0, 1] == pytest.approx(5.63, abs=0.005)
    theta = math.degrees(math.atan2(prof[3, 0] - prof[2, 0], prof[2, 1] - prof[3, 1]))
    assert theta == pytest.approx(28.20, abs=0.005)
    area = revolved_shell(prof, areal_density=1.0)[0]
    assert area == pytest.approx(126.09, abs=0.005)
    assert STEEL * 0.0619 * area / 1e3 == pytest.approx(61.27, abs=0.005)  # Table 6-9 [t]


@pytest.mark.parametrize("d_max, alpha, tonnes", [(7.5, 65.0, 61.27), (8.0, 60.0, 66.34), (9.0, 60.0, 82.00),
                                                  (10.0, 60.0, 99.19), (10.5, 55.0, 105.69)])
def test_shell_weights_of_table_6_9(d_max, alpha, tonnes):
    """Every weight of Table 6-9 (the thesis's qualified designs) from the shell of 0.0619 m steel, to the
    table's two decimals (0.005 t: its rounding)."""
    area = revolved_shell(buoy_design_profile(d_max=d_max, alpha_deg=alpha), areal_density=1.0)[0]
    assert STEEL * 0.0619 * area / 1e3 == pytest.approx(tonnes, abs=0.005)


def test_the_job_reproduces_its_hand_computed_buoy():
    job = load_job(JOB)
    v, t = hull_mesh(job, 0)
    mass, inertia = mass_and_inertia(job, 0, v, t)
    assert round(mass / 1e4, 2) == 7.51 and mass == pytest.approx(75112.0, rel=1e-4)
    assert mass / job.water.density == pytest.approx(73.28, abs=0.005)
    np.testing.assert_allclose(np.round(inertia / 1e5, 2), [4.72, 4.72, 7.75])
    prof = body_profile(job.bodies[0].hull)
    assert round(-prof[0, 0], 2) == 1.83                      # the centre above the keel [m]
    np.testing.assert_allclose(prof[:, 1], [2.5, 2.5, 4.5, 2.5], atol=1e-12)
    z = initial_poses(job)[0, :3]
    assert z[0] == 0.0 and z[1] == 0.0
    keel = -(z[2] + v[:, 2].min())
    data = tomllib.loads(job.text)
    del data["moorings"]
    alone = -(initial_poses(parse_job(data, source="no chain"))[0, 2] + v[:, 2].min())
    assert round(alone, 2) == 2.24                             # Table 4-2's draft
    # section 4.3.2: the chains "pull the buoy down with approximately 6-8 cm" (their 2 x 20.5 kN)
    assert 0.06 <= keel - alone <= 0.08


def test_the_buoy_hull_is_varied_like_any_key(tmp_path):
    from pice.study.variants import make_variants

    variants = make_variants(JOB, ["bodies[0].hull.d_max=7.5,10.5", "bodies[0].hull.alpha=30,65"], out_dir=tmp_path)
    assert [(v.job.bodies[0].hull.d_max, v.job.bodies[0].hull.alpha) for v in variants] == \
        [(7.5, 30), (7.5, 65), (10.5, 30), (10.5, 65)]
    for v in variants:  # every variant builds its hull; at 30 deg the closed hull of D_max 7.5 m sinks
        verts, tris = hull_mesh(v.job, 0)
        assert np.ptp(verts[:, 0]) == pytest.approx(v.job.bodies[0].hull.d_max, rel=1e-9)
        if v.index == 0:  # Table 6-2: 2.78 m, above its widest section: the thesis's cone ran on past D_max
            with pytest.raises(JobError, match="the hull cannot float"):
                initial_poses(v.job)
        else:
            assert initial_poses(v.job)[0, 2] < 0.0


@pytest.mark.parametrize("d_max, alpha", [(9.0, 45.0), (10.5, 70.0), (7.0, 60.0)])
def test_each_design_has_its_fairlead_on_its_keel_and_its_anchor_on_the_seabed(d_max, alpha):
    """Table 4-3 and Eq. 4-32 for every design: the fairleads 0.5 m in from the keel's edge (d_m,f) on
    the keel, one upstream and one downstream; the anchors on the seabed, so the fairleads lie d_w - d_s
    above them, d_s the design's draft with its chains. The draft is the fixed point of floating with the
    chains' pull at that draft: weight = buoyancy + pull, to 1e-9 m of height (the iteration's tolerance)."""
    from pice.platform.build import _layout_pull_z, build_platform, hulls_from_job
    from pice.platform.body_setup import afloat_position
    from pice.platform.hull_buoyancy import BRACE_RECORD

    data = tomllib.loads(JOB.read_text())
    data["bodies"][0]["hull"].update(d_max=d_max, alpha=alpha)
    data["moorings"][0]["model"] = "quasi_static"
    job = parse_job(data, source="design")
    v, t = hull_mesh(job, 0)
    pose = initial_poses(job)[0]
    keel_z, keel_r = body_profile(job.bodies[0].hull)[0]
    draft = -(pose[2] + keel_z)
    lines = build_platform(job, hulls_from_job(job, default_kn=1e8, reach=0.5)).groups[0].lines
    for k, side in enumerate((-1.0, 1.0)):  # upstream, downstream
        fairlead, anchor = lines.fairlead_x[k], lines.anchors_x[k]
        np.testing.assert_allclose(fairlead, [side * (keel_r - 0.5), 0.0, -draft], atol=1e-9)
        assert anchor[2] == pytest.approx(-30.0, abs=1e-9) and side * anchor[0] > side * fairlead[0]  # on the seabed
        assert fairlead[2] - anchor[2] == pytest.approx(30.0 - draft, abs=1e-9)         # Eq. 4-32
    again = afloat_position(job, 0, v, t, np.zeros(0, BRACE_RECORD), pose[3:7], mass=mass_and_inertia(job, 0, v, t)[0], pull_z=_layout_pull_z(job, 0, pose))
    assert again[2] == pytest.approx(pose[2], abs=1e-8)


def test_one_chain_leaves_the_buoy_out_of_balance_and_is_warned_of(caplog):
    """Two opposed chains (the thesis's model, section 3.3.2: the restoring force F_x1 + F_x2) hold the
    buoy at rest: their horizontal pulls cancel to round-off (1e-6 of the 25.4 kN pretension). One
    chain alone pulls it sideways by its horizontal tension, which nothing balances; the set-up warns
    (build.UNBALANCED_PULL) and names the fix."""
    from pice.platform.build import build_platform, hulls_from_job

    def platform(headings):
        data = tomllib.loads(JOB.read_text())
        data["moorings"][0].update(model="quasi_static", headings=headings)
        job = parse_job(data, source="buoy")
        caplog.clear()
        return build_platform(job, hulls_from_job(job, default_kn=1e8, reach=0.5))

    log = logging.getLogger("pice")  # it may not propagate to the root logger (pice.log.configure)
    log.addHandler(caplog.handler)
    try:
        two = platform([180.0, 0.0])
        assert abs(two.mooring_force[0, 0]) < 1e-6 * 2.54e4 and "sideways" not in caplog.text
        one = platform([180.0])
        assert one.mooring_force[0, 0] < -1e4  # [N] towards the anchor upstream: the catenary's H (~15 kN)
        assert "bodies[0] (buoy): its lines pull it" in caplog.text and "moorings.headings" in caplog.text
    finally:
        log.removeHandler(caplog.handler)


# Seed 004, Table 6-2: the stationary draft [m] of each design (rows: alpha [deg]; columns: D_max 7-10.5 m).
# The text of the seed lists the rows 30-65 (the 70 deg row is lost in its extraction).
TABLE_6_2 = {30: [2.81, 2.78, 2.74, 2.70, 2.66, 2.61, 2.57, 2.52], 35: [2.73, 2.68, 2.63, 2.57, 2.52, 2.46, 2.41, 2.36],
             40: [2.63, 2.56, 2.50, 2.44, 2.38, 2.32, 2.26, 2.21], 45: [2.51, 2.44, 2.37, 2.30, 2.24, 2.18, 2.13, 2.07],
             50: [2.39, 2.32, 2.25, 2.18, 2.12, 2.06, 2.01, 1.96], 55: [2.28, 2.20, 2.13, 2.06, 2.00, 1.95, 1.90, 1.85],
             60: [2.17, 2.09, 2.02, 1.96, 1.91, 1.86, 1.81, 1.77], 65: [2.07, 2.00, 1.93, 1.87, 1.82, 1.77, 1.73, 1.69]}
D_MAX = [7.0, 7.5, 8.0, 8.5, 9.0, 9.5, 10.0, 10.5]


def _draft_alone(d_max: float, alpha: float) -> float | None:
    """The design's stationary draft [m] from the mesh's buoyancy, without the chain (as Table 6-2),
    with the sweep's 0.0619 m shell; None when the closed hull cannot float."""
    data = tomllib.loads(JOB.read_text())
    del data["moorings"]
    data["bodies"][0]["hull"].update(d_max=d_max, alpha=alpha)
    data["bodies"][0]["shell_thickness"] = 0.0619
    job = parse_job(data, source=f"D_max {d_max} m, alpha {alpha} deg")
    v, _ = hull_mesh(job, 0)
    try:
        return -(initial_poses(job)[0, 2] + v[:, 2].min())
    except JobError as exc:
        assert "the hull cannot float" in str(exc)
        return None


def test_stationary_drafts_of_table_6_2():
    """Issue 16's hydrostatics check. Where Table 6-2's draft lies below the widest section (2.5 m above
    the keel) the thesis's hull and ours are the same solid: within 3 % (measured: 0.4 % at most; the
    64-gon holds 0.16 % less volume than the circle, and the table has 2 decimals). Above it the thesis
    let the lower cone run on past D_max, while the real hull narrows into its upper cone: a real
    design floats deeper than the table (less volume per metre above 2.5 m) or sinks (all 3 m under
    water hold less than its mass), never shallower (to the table's 0.005 m rounding). Criterion (3) (a draft in [0.6, 2.4] m) keeps the
    same designs either way: the thesis's 51 with the 70 deg row, which floats shallowest."""
    kept = 0
    for alpha, row in TABLE_6_2.items():
        for d_max, table in zip(D_MAX, row):
            ours = _draft_alone(d_max, float(alpha))
            if table < 2.5:
                assert ours == pytest.approx(table, rel=0.03), (d_max, alpha)
            else:
                assert ours is None or ours > table - 0.005, (d_max, alpha, ours)  # the table's rounding
            assert (ours is not None and 0.6 <= ours <= 2.4) == (0.6 <= table <= 2.4), (d_max, alpha)
            kept += ours is not None and 0.6 <= ours <= 2.4
    kept += sum(0.6 <= (_draft_alone(d, 70.0) or 99.0) <= 2.4 for d in D_MAX)
    assert kept == 51  # seed 004, section 6.2.1: "in total 51 combinations ... satisfy ... criterion (3)"


def test_the_design_sweep_file_builds_every_design_of_every_phase(tmp_path):
    """jobs/cai_2018_buoy_sweep.toml: Table 6-1's 72 designs, each valid in each of the three phases,
    with the phase's own values (the extreme phase's 0.2 m/s)."""
    from pice.study.sweep import _phase_specs, load_sweep
    from pice.study.variants import make_variants

    path = REPO / "jobs" / "cai_2018_buoy_sweep.toml"
    study = load_sweep(path)
    assert [p.name for p in study.phases] == ["draft", "normal", "extreme"]
    for phase in study.phases:
        variants = make_variants(path.parent / study.job, _phase_specs(study, phase), out_dir=tmp_path)
        assert len(variants) == 72
        ice = variants[-1].job.ice
        assert ice.velocity[0] == (0.2 if phase.name == "extreme" else 0.1) and ice.element_diameter == 1.0
