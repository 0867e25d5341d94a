"""Rubble for a ridge keel (issue 15; seed 002, Gong, Polojärvi & Tuhkuri 2017): the blocks, their
release under the cover, the keel's shape and its porosity (pice/scenes/rubble.py, physics/keel.py).

References: Archimedes (a block floats at the draft rho_i / rho_w of its thickness; seed 002, Table 1:
920 and 1010 kg/m^3, 0.3 m); the keel's trapezoid (seed 002, Fig. 2: depth 5 m, pile angle 30 deg,
a triangle at w = 17.3 m); the volume of a box inside the keel (Monte Carlo porosity).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from pice.job import parse_job
from pice.physics.keel import blocks_as_floes, keel_law, keel_step, keel_water
from pice.scenes.rubble import half_width, inside_keel, keel_volume, porosity, release_blocks


def _job(width=17.3, length=4.0, depth=5.0, **keel):
    return parse_job({"run": {"duration": 1.0, "dt": 1e-3}, "water": {"density": 1010.0},
                      "keel": {"width": width, "length": length, "depth": depth, "seed": 3, **keel}})


def test_a_block_floats_at_its_archimedes_draft():
    """One 1 m x 0.615 m x 0.3 m block released 5 cm too high in still water comes to rest at the draft
    0.3 x 920 / 1010 = 0.2733 m (0.5 %, the issue's bound; the heave damping of the rigid pieces, 0.1
    of critical, settles it within 20 s)."""
    job = _job()
    kl = job.keel
    rect = np.array([[[-0.5, -0.3075], [0.5, -0.3075], [0.5, 0.3075], [-0.5, 0.3075]]])
    draft = 0.3 * 920.0 / 1010.0
    floes = blocks_as_floes(kl, rect, np.array([[0.0, 0.0, 0.15 - draft + 0.05]]), np.array([[1.0, 0, 0, 0]]),
                            keel_law(kl), keel_water(job))
    dt = 1e-3
    floes.compute_forces(dt)
    for _ in range(int(20.0 / dt)):
        floes.step(dt)
    bottom = floes.x[0, 2] - 0.15
    assert -bottom == pytest.approx(draft, rel=5e-3)
    assert abs(floes.v[0, 2]) < 1e-4


def test_released_blocks_are_apart_under_the_cover_in_the_keels_box():
    """The release (scenes/rubble.release_blocks): no two blocks overlap at t = 0 (the contact search
    finds no pair), every block is wholly below the cover and inside the keel's box, and there is
    enough ice to fill the keel at porosity 0.3."""
    job = _job()
    kl = job.keel
    rect, x, q = release_blocks(kl)
    floes = blocks_as_floes(kl, rect, x, q, keel_law(kl), keel_water(job))
    pts, counts = floes.world()
    _, npair, _, _ = floes.pair_records(0, len(x), pts, counts, floes.omega, 1e-3)
    assert npair == 0
    corners = pts[counts > 0]
    assert corners[..., 2].max() < kl.cover
    assert corners[..., 0].min() >= kl.x - 0.5 * kl.width - 1e-9 and corners[..., 0].max() <= kl.x + 0.5 * kl.width + 1e-9
    assert corners[..., 1].min() >= kl.y0 - 1e-9 and corners[..., 1].max() <= kl.y0 + kl.length + 1e-9
    assert floes.mass.sum() / 920.0 >= 0.7 * keel_volume(kl)


def test_the_keel_is_seed_002s_triangle_and_trapezoids():
    """Fig. 2: at w = 17.3 m the 30 deg slopes meet 5 m down (a triangle, 43.3 m^2 a metre); at
    w = 40 m the bottom is 22.68 m wide."""
    tri = _job(17.32).keel
    assert keel_volume(tri) == pytest.approx(0.5 * 17.32 * 5.0 * 4.0, rel=1e-3)
    assert half_width(tri, -5.0) == pytest.approx(0.0, abs=0.01)
    trap = _job(40.0).keel
    assert 2 * half_width(trap, -5.0) == pytest.approx(40.0 - 10.0 / math.tan(math.radians(30.0)), rel=1e-12)
    pts = np.array([[0.0, 1.0, -4.9], [11.3, 1.0, -4.9], [19.8, 1.0, -0.1], [0.0, 1.0, -5.1], [0.0, 4.1, -1.0]])
    assert inside_keel(trap, pts).tolist() == [True, True, True, False, False]
    assert keel_volume(_job(17.3).keel) == pytest.approx(0.5 * 17.3 * 5.0 * 4.0, rel=1e-3)  # the seed's rounding
    with pytest.raises(Exception, match="meet above the keel's depth"):
        _job(15.0)


def test_porosity_of_one_block_in_a_small_keel():
    """A keel 2 m wide, 1 m deep and 1 m long (pile angle 80 deg: 1.647 m^3) holding one 1 x 0.6 x 0.3
    m block turned 30 deg about z: porosity 1 - 0.18 / 1.647, within 4 standard errors of the Monte
    Carlo (200,000 points)."""
    kl = _job(2.0, 1.0, 1.0, pile_angle=80.0).keel
    rect = np.array([[[-0.5, -0.3], [0.5, -0.3], [0.5, 0.3], [-0.5, 0.3]]])
    a = math.radians(15.0)
    q = np.array([[math.cos(a), 0.0, 0.0, math.sin(a)]])
    p = porosity(kl, np.array([[0.0, 0.5, -0.5]]), q, rect, 0.3)
    exact = 1.0 - 0.18 / keel_volume(kl)
    assert abs(p - exact) < 4.0 * math.sqrt(exact * (1 - exact) / 200_000)


def test_points_in_boxes_agrees_with_every_box_tested_against_every_point():
    """The binned kernel behind the porosity (kernels/geometry.points_in_boxes) against the direct
    test of each point in each box's own frame (|R^T (p - c)| <= half on every axis): the same bool for
    each of 20,000 points among 300 turned boxes of mixed sizes, exactly (the same arithmetic, in a
    different order of boxes, can differ only on a face, which random points do not hit); and sparse
    points over a kilometre, where the grid is coarsened (the chance that one of 2,000 random points
    falls in one of 50 boxes of at most 0.1 m across in that 10^7 m^3 is below 1e-5; the seed is fixed)."""
    from pice.kernels.geometry import points_in_boxes, rotation_matrix
    from pice.scenes.rubble import random_attitudes

    rng = np.random.default_rng(7)
    m = 300
    centres = rng.uniform([0.0, 0.0, -5.0], [20.0, 10.0, 0.0], (m, 3))
    half = rng.uniform(0.05, 0.8, (m, 3))
    q = random_attitudes(m, rng)
    pts = rng.uniform([-1.0, -1.0, -6.0], [21.0, 11.0, 1.0], (20_000, 3))
    direct = np.zeros(len(pts), dtype=bool)
    for k in range(m):
        local = (pts - centres[k]) @ rotation_matrix(q[k])
        direct |= np.all(np.abs(local) <= half[k], axis=1)
    assert 0 < direct.sum() < len(pts)
    np.testing.assert_array_equal(points_in_boxes(pts, centres, q, half), direct)
    # sparse points over a wide region (1 km, boxes of 10 cm: the grid coarsened, not 10^10 cells);
    # the boxes' centres among the points, so that some are inside
    small = rng.uniform(0.02, 0.05, (50, 3))
    far = rng.uniform([0.0, 0.0, -10.0], [1000.0, 1000.0, 0.0], (50, 3))
    pts = np.vstack([rng.uniform([0.0, 0.0, -10.0], [1000.0, 1000.0, 0.0], (2000, 3)), far])
    got = points_in_boxes(pts, far, q[:50], small)
    assert got[-50:].all() and not got[:2000].any()


def test_the_table_2_jobs_and_a_friction_study_share_one_keel(tmp_path):
    """jobs/gong_2017_keel_*.toml are seed 002's Table 2, its ten rows (half models at w = 17.3-80 m with
    l_h = 30 m; at w = 17.3 m the half models at l_h = 40 and 50 m and the full models at l_f = 60, 80 and
    100 m, the full ones' rubble from y = -l_f / 2); a study over mu_i (Table 2: 0.3, 0.6) keeps each variant on the job's
    one keel file (the friction is not a generation key: io/keel_file.RUN_KEYS)."""
    import pathlib

    from pice.io.keel_file import RUN_KEYS, keel_path
    from pice.job import load_job
    from pice.study.variants import make_variants

    jobs = pathlib.Path(__file__).resolve().parents[2] / "jobs"
    found = {}
    for path in sorted(jobs.glob("gong_2017_keel_*.toml")):
        job = load_job(path)
        half = job.bodies[0].hull.half
        assert job.keel.y0 == (0.0 if half else -job.keel.length / 2), path
        found[path.stem] = (job.keel.width, job.keel.length, half)
    assert found == {"gong_2017_keel_w17_3": (17.3, 30.0, True), "gong_2017_keel_w30": (30.0, 30.0, True),
                     "gong_2017_keel_w40": (40.0, 30.0, True), "gong_2017_keel_w60": (60.0, 30.0, True),
                     "gong_2017_keel_w80": (80.0, 30.0, True), "gong_2017_keel_w17_3_full": (17.3, 60.0, False),
                     "gong_2017_keel_w17_3_l40": (17.3, 40.0, True), "gong_2017_keel_w17_3_l50": (17.3, 50.0, True),
                     "gong_2017_keel_w17_3_full_l80": (17.3, 80.0, False),
                     "gong_2017_keel_w17_3_full_l100": (17.3, 100.0, False)}
    # one file each: a length series keel is never read as another's
    assert len({keel_path(load_job(p), jobs).resolve() for p in jobs.glob("gong_2017_keel_*.toml")}) == len(found)
    assert "contact" in RUN_KEYS
    base = jobs / "gong_2017_keel_w30.toml"
    variants = make_variants(base, ["keel.contact.friction=0.3,0.6"], out_dir=tmp_path)
    files = {v.job.keel.file for v in variants}
    assert files == {str(keel_path(load_job(base), base.parent).resolve())}
    assert [v.job.keel.contact.friction for v in variants] == [0.3, 0.6]
    # the blocks' form drag is the ship run's water, not the generation's result: one keel file too, and
    # each variant's water has its C_d (a study of the drag's share of R: docs/ridge_keel.md)
    assert "form_drag_coefficient" in RUN_KEYS
    variants = make_variants(base, ["keel.form_drag_coefficient=0,1"], out_dir=tmp_path / "drag")
    assert {v.job.keel.file for v in variants} == files
    assert [keel_water(v.job).form for v in variants] == [0.0, 1.0]


def test_the_wider_table_2_keels_are_trimmed_from_the_80_m_keels_generation():
    """jobs/gong_2017_keel_w{30,40,60}.toml take their keels from the 80 m job's keel file
    (keel.trim_from; docs/ridge_keel.md "One generation"): the file named is the one `pice keel` writes
    for the 80 m job, and the jobs' generation keys are its keys but for TRIM_KEYS, so the trim that
    follows a generation of hours is not refused."""
    import pathlib

    from pice.io.keel_file import TRIM_KEYS, _generation_keys, keel_path
    from pice.job import load_job

    jobs = pathlib.Path(__file__).resolve().parents[2] / "jobs"
    wide = load_job(jobs / "gong_2017_keel_w80.toml")
    assert wide.keel.trim_from is None
    made = _generation_keys(wide.keel)
    for w in ("30", "40", "60"):
        job = load_job(jobs / f"gong_2017_keel_w{w}.toml")
        assert (jobs / job.keel.trim_from).resolve() == keel_path(wide, jobs).resolve()
        want = _generation_keys(job.keel)
        assert {k for k in set(made) | set(want) if made.get(k) != want.get(k)} <= set(TRIM_KEYS)
        assert job.keel.width < wide.keel.width


def test_the_keels_dashpot_is_a_ratio_and_sets_the_step():
    """[keel.contact] keeps the keel's defaults when only some keys are given (k_n 1e7 N/m, ratio 0.3;
    docs/ridge_keel.md "Contact"); a damping c_n given alone replaces the ratio. The step is
    keel.step_fraction of the lightest pair's m_eff / c_n, with c_n = 2 zeta sqrt(m_eff k_n) (by hand:
    the 0.6 m block, 0.6 x 0.369 x 0.3 x 920 = 61.1 kg, m_eff 30.6 kg, c_n 1.05e4 N s/m: 2.92e-4 s)."""
    job = _job(contact={"friction": 0.6})
    c = job.keel.contact
    assert (c.normal_stiffness, c.damping_ratio, c.tangential_stiffness, c.friction) == (1.0e7, 0.3, 0.6e7, 0.6)
    assert _job(contact={"damping": 1.75e4}).keel.contact.damping_ratio is None
    keel = job.keel
    rects, x, q = release_blocks(keel)
    floes = blocks_as_floes(keel, rects, x, q, keel_law(keel), keel_water(job))
    m_eff = 0.5 * floes.mass.min()
    assert m_eff == pytest.approx(0.5 * 0.6 * 0.369 * 0.3 * 920.0, rel=0.01)  # a block near the shortest length
    expected = 0.1 * m_eff / (2.0 * 0.3 * math.sqrt(m_eff * 1.0e7))
    assert keel_step(keel, floes) == pytest.approx(expected, rel=1e-12)
    assert expected == pytest.approx(2.92e-4, rel=0.02)


def test_the_blocks_settle_with_their_own_friction():
    """keel.settle_friction (docs/ridge_keel.md "Porosity"), when given, is the friction of the settling
    (physics/keel.settling_law), keel.contact.friction the ship run's; by default the settling has the
    contact's (seed 002's procedure). The settling friction is a generation key (a keel file settled
    with another is refused: io/keel_file.RUN_KEYS)."""
    from pice.io.keel_file import _generation_keys
    from pice.physics.keel import settling_law

    keel = _job(contact={"friction": 0.6}).keel
    assert keel.settle_friction is None and settling_law(keel).mu == 0.6
    keel = _job(contact={"friction": 0.6}, settle_friction=0.0).keel
    assert settling_law(keel).mu == 0.0 and keel_law(keel).mu == 0.6
    assert settling_law(keel).kn == keel_law(keel).kn and settling_law(keel).zeta == keel_law(keel).zeta
    assert _generation_keys(keel)["settle_friction"] == 0.0
    assert "settle_friction" not in _generation_keys(_job().keel)  # unset: files from before it still match
    keel = _job(settle_friction=0.0, lock_speed=0.02).keel  # the staged settling's speed is a generation key too
    assert _generation_keys(keel)["lock_speed"] == 0.02 and "lock_speed" not in _generation_keys(_job().keel)
