"""Rank 0's platform: fairleads carried by the hull, the mooring pull on the body, rest equilibrium, the
energies of bodies and lines."""

import math

import numpy as np
import pytest

from pice.kernels.geometry import rotation_matrix
from pice.platform.catenary import Segment, solve_line, strain_energy
from pice.platform.hulls import box, semi_submersible, semi_submersible_braces
from pice.platform.layout import spread_mooring, zhu_ji_fairleads
from pice.platform.mooring_lines import LINE_ELEMENT_RECORD, LineWater, MooringLines, Seabed, build_lines
from pice.platform.platform import Attachment, MooringGroup, Platform
from pice.platform.quasi_static import QuasiStaticLines
from pice.platform.rigid_body import RigidBody, heading_quaternion

CG = np.array([0.0, 0.0, -14.0 + 8.9])  # Table 3: CG 8.9 m above the keel, draft 14 m


def moored_semi():
    v, t = semi_submersible()
    fl, headings = zhu_ji_fairleads()
    lines, _, _ = spread_mooring(fairleads_body=fl, bundle_headings_deg=headings)
    ml = build_lines(lines, element_length=20.0, water_density=1025.0, water_level=0.0, seabed_z=-400.0,
                     bond_damping=0.3)
    ml.relax(tol=1.0)
    pull_down = -ml.reactions(ml.fairleads)[:, 2].sum()
    # Table 3's displacement at 14 m carries the hull and the lines' vertical pull at pretension
    body = RigidBody("semi", 35000.5e3 - pull_down / 9.81, np.array([3.0e10, 5.0e10, 6.0e10]), v, t,
                     braces=semi_submersible_braces(),
                     damping=np.array([2e6, 2e6, 2e7, 1e12, 1e12, 1e12]))
    body.x = CG.copy()
    att = [Attachment(k, 0, lines[k][1] - CG) for k in range(len(lines))]
    return Platform([body], ml, att, rho_w=1025.0, g=9.81, level=0.0), body


def test_fairleads_follow_the_hull_pose():
    """Fairleads are body-fixed points: x_f = x_cg + R(q) p_B, v_f = v_cg + omega x (R p_B)."""
    p, b = moored_semi()
    a = math.radians(10.0)
    b.q = np.array([math.cos(a / 2), 0.0, 0.0, math.sin(a / 2)])
    b.x = CG + np.array([3.0, -2.0, 0.5])
    b.v = np.array([0.2, 0.0, 0.0])
    b.L = rotation_matrix(b.q) @ (b.effective_inertia * np.array([0.0, 0.0, 0.01]))
    x, v = p.fairlead_positions()
    for att in p.attachments:
        arm = rotation_matrix(b.q) @ att.point
        assert np.allclose(x[att.line], b.x + arm)
        assert np.allclose(v[att.line], b.v + np.cross([0.0, 0.0, 0.01], arm), atol=1e-12)


def test_moored_platform_at_rest_stays_put():
    """With the weight of the hull and the lines' pretension balanced by the buoyancy at 14 m draft,
    the coupled platform (hull + 12 DEM lines) stays within 2 cm and 0.01 degree of its start over
    60 s; the lines' horizontal pulls cancel (the spread is symmetric) and each keeps its
    pretension within 1 % (221.7 kN, Zhu & Ji 2022, section 4.1)."""
    p, b = moored_semi()
    dt = 0.05
    p.loads()
    for _ in range(int(60.0 / dt)):
        p.kick(0.5 * dt)
        p.drift(dt)
        p.loads()
        p.kick(0.5 * dt)
    assert np.linalg.norm(b.x - CG) < 0.02
    assert 2 * math.degrees(math.acos(min(1.0, abs(b.q[0])))) < 0.01
    np.testing.assert_allclose(p.fairlead_tensions(), 221.7e3, rtol=0.01)


@pytest.mark.parametrize("restart", [False, True])
def test_the_fused_step_gives_the_general_paths_bits(restart):
    """platform/fused_step.py: one free body on DEM lines in still water, stepped by two compiled
    calls (begin_step, finish_step: the simulation's way) or by the separate kick, drift, loads and
    kick, gives the general path's bits (the same arithmetic in the same order): the body, the lines,
    the lines' pull and the fairlead tensions after 300 steps of a changing ice load, also across a
    set_state halfway (a restart: it gives the body new arrays, which the fused step must notice)."""
    fused, b1 = moored_semi()
    separate, _ = moored_semi()
    general, _ = moored_semi()
    assert fused.fused is not None and separate.fused is not None
    general.fused = None
    dt, rng = 2.6e-4, np.random.default_rng(3)
    for p in (fused, separate, general):
        p.loads()
    for step in range(300):
        ice = np.concatenate([rng.normal((1e7, 0.0, 0.0), 2e6), rng.normal(0.0, 2e7, 3)]).reshape(1, 6)  # [N], [N m]
        fused.begin_step(0.5 * dt, dt)
        tensions = fused.finish_step(ice, 0.5 * dt)
        for p in (separate, general):
            p.kick(0.5 * dt)
            p.drift(dt)
            p.loads(ice)
        assert np.array_equal(tensions, general.fairlead_tensions())  # what the peaks track
        for p in (separate, general):
            p.kick(0.5 * dt)
        if restart and step == 150:
            fused.set_state(fused.state())
            separate.set_state(separate.state())
    assert np.linalg.norm(b1.x - CG) > 1e-4  # the ice moved it
    other = general.state()
    for p in (fused, separate):
        one = p.state()
        assert one.keys() == other.keys()
        for key, value in other.items():
            assert np.array_equal(one[key], value), key
        assert np.array_equal(p.mooring_force, general.mooring_force)
        assert np.array_equal(p.fairlead_tensions(), general.fairlead_tensions())
        assert np.array_equal(p.poses(), general.poses())  # what rank 0 broadcasts


def test_the_general_paths_begin_and_finish_are_its_separate_calls():
    """Where the fused step does not apply (here: the fused step switched off), begin_step and
    finish_step are kick + drift and loads + kick, bit for bit, and finish_step returns the tensions."""
    one, _ = moored_semi()
    two, _ = moored_semi()
    one.fused = two.fused = None
    dt = 2.6e-4
    ice = np.array([[5e6, 1e6, 0.0, 0.0, 0.0, 1e7]])
    for p in (one, two):
        p.loads()
    for _ in range(20):
        one.begin_step(0.5 * dt, dt)
        tensions = one.finish_step(ice, 0.5 * dt)
        two.kick(0.5 * dt)
        two.drift(dt)
        two.loads(ice)
        two.kick(0.5 * dt)
        assert np.array_equal(tensions, two.fairlead_tensions())
    for key, value in two.state().items():
        assert np.array_equal(one.state()[key], value), key


def test_the_fused_step_packs_the_body_once():
    """The fused step copies the body's state into its rows once (and again only after something gave
    the body new arrays): the body's attributes are then the rows' views themselves. A check that
    compared them with fresh views of the rows re-packed 4 times a step (15 % of a buoy design's step)."""
    p, b = moored_semi()
    packs = []
    pack = p.fused.pack
    p.fused.pack = lambda: (packs.append(1), pack())
    dt = 2.6e-4
    p.loads()
    for _ in range(10):
        p.kick(0.5 * dt)
        p.drift(dt)
        p.loads()
        p.kick(0.5 * dt)
    assert packs == []
    assert np.shares_memory(b.x, p.fused.rows["x"]) and np.shares_memory(b.q, p.fused.rows["q"])
    p.set_state(p.state())
    p.kick(0.5 * dt)
    assert packs == [1]


def test_the_fused_step_is_taken_only_where_it_applies():
    """Two bodies, a prescribed body, a body without lines or waves take the general path (Platform.fused
    is None)."""
    from pice.physics.waves import Sea

    p, b = moored_semi()
    assert p.fused is not None
    v, t = box(10.0, 8.0, 4.0)
    pushed = RigidBody("ship", 1e6, np.ones(3), v, t, prescribed=np.array([[0.0, 1.0, 0, 0, 0, 0, 0]]))
    assert Platform([pushed], rho_w=1025.0, g=9.81, level=0.0).fused is None
    assert Platform([b, pushed], rho_w=1025.0, g=9.81, level=0.0).fused is None
    assert Platform([b], rho_w=1025.0, g=9.81, level=0.0).fused is None
    assert Platform([b], rho_w=1025.0, g=9.81, level=0.0, sea=Sea.regular(height=1.0, period=10.0)).fused is None


@pytest.mark.nojit
def test_energies_of_a_spinning_body_and_a_stretched_line_element():
    """Platform.energies against a hand computation [J].

    Body: a 1 m box hull, m = 2000 kg, I = (100, 200, 300) kg m^2, added mass 500 kg in surge and
    50 kg m^2 in yaw, yawed 90 degrees (body x along space y, body y along space -x), moving at
    v = (0, 2, 0) m/s (body surge) and spinning at w = (0.3, 0, 0.5) rad/s (body -y and z), with the
    inertia its equation of motion carries:
        1/2 (2000 + 500) 2^2 + 1/2 200 0.3^2 + 1/2 (300 + 50) 0.5^2 = 5000 + 9 + 43.75 = 5052.75.
    DEM line: anchor, a taut and a slack element along x under water (rho = 1000 kg/m^3), each
    l0 = 10 m, EA = 1e6 N, D = 0.1 m, C_a = 1; the middle node (8 kg) at x = 10.05 m moves at
    (0.2, 0.3, 0.4) m/s, the end node 9 m further on (1 m slack) is at rest:
        elastic 1/2 EA/l0 0.05^2 = 125 (the slack element stores nothing);
        kinetic 1/2 8 (0.2^2 + 0.3^2 + 0.4^2) + 1/2 m_a (0.3^2 + 0.4^2) = 1.16 + 3.125 pi, the middle
        node's added mass m_a = rho C_a pi D^2/4 (2 x l0/2) = 25 pi kg acting on the velocity normal
        to the line (its tangent is x).
    A quasi-static line adds no kinetic energy and its catenary's strain energy (catenary.strain_energy).
    """
    v, t = box(1.0, 1.0, 1.0)
    body = RigidBody("box", 2000.0, np.array([100.0, 200.0, 300.0]), v, t,
                     added_mass=np.array([500.0, 0.0, 0.0, 0.0, 0.0, 50.0]))
    body.q = np.array(heading_quaternion(90.0))
    body.v = np.array([0.0, 2.0, 0.0])
    R = rotation_matrix(body.q)
    body.L = R @ (body.effective_inertia * (R.T @ np.array([0.3, 0.0, 0.5])))
    element = (1.0e6, 10.0, 0.1, 100.0, 1.2, 0.01, 1.0, 0.0)  # ea, l0, D, wet weight, C_dn, C_dt, C_a, zeta
    line = MooringLines(x=np.array([[0.0, 0.0, 0.0], [10.05, 0.0, 0.0], [19.05, 0.0, 0.0]]),
                        v=np.array([[0.0, 0.0, 0.0], [0.2, 0.3, 0.4], [0.0, 0.0, 0.0]]),
                        mass=np.array([4.0, 8.0, 4.0]), prev=np.array([-1, 0, 1]), seg=np.array([0, 0, 1]),
                        kind=np.array([1, 0, 2]), props=np.array([element, element], LINE_ELEMENT_RECORD),
                        anchors=np.array([0]), fairleads=np.array([2]), water=LineWater(density=1000.0, level=1.0),
                        current=np.zeros(3), seabed=Seabed(z=-math.inf, stiffness=0.0, damping_ratio=0.0,
                                                           friction=0.0, slip_velocity=0.01))
    catenary = [Segment(600.0, 1.0e3, 5.0e8)]
    quasi = QuasiStaticLines([[0.0, 0.0, -200.0]], [[500.0, 0.0, 0.0]], [catenary], seabed=True)
    p = Platform([body], rho_w=1000.0, g=9.81, level=1.0,
                 groups=[MooringGroup(line, []), MooringGroup(quasi, [])])
    e = p.energies()
    assert set(e) == {"body_kinetic_energy", "mooring_kinetic_energy", "mooring_elastic_energy"}
    assert e["body_kinetic_energy"] == pytest.approx(5052.75, rel=1e-12)
    assert e["mooring_kinetic_energy"] == pytest.approx(1.16 + 3.125 * math.pi, rel=1e-12)
    assert quasi.energies()[0] == 0.0
    qs_strain = strain_energy(catenary, solve_line(catenary, horizontal=500.0, vertical=200.0))
    assert qs_strain > 0.0
    assert e["mooring_elastic_energy"] == pytest.approx(125.0 + qs_strain, rel=1e-12)


def test_points_inside_a_hull():
    """hulls.inside (issue 13, case 2: the overlap check tests inside the hull too): the generalised
    winding number against the box's own bounds for 2,000 random points, whichever way the
    triangles face; the semi-submersible's ring pontoon holds points in its pontoons and columns but
    not in the open water between the columns or in its moonpool."""
    from pice.platform.hulls import inside

    rng = np.random.default_rng(13)
    v, t = box(10.0, 8.0, 4.0, centre=(1.0, -2.0, 0.5))
    pts = rng.uniform([-6.0, -8.0, -3.0], [8.0, 4.0, 4.0], size=(2000, 3))
    truth = np.all(np.abs(pts - [1.0, -2.0, 0.5]) < [5.0, 4.0, 2.0], axis=1)
    near = np.any(np.abs(np.abs(pts - [1.0, -2.0, 0.5]) - [5.0, 4.0, 2.0]) < 1e-9, axis=1)
    assert truth.sum() > 200 and not near.any()
    assert np.array_equal(inside(pts, v, t), truth)
    assert np.array_equal(inside(pts, v, t[:, ::-1]), truth)  # inside-out triangles: the same answer
    v, t = semi_submersible()
    z_pontoon, z_column = -8.9 + 4.0, 0.0
    assert inside([[0.0, 64.6 / 2 - 7.0, z_pontoon], [-(86.2 - 16.68) / 2, -(64.6 - 16.68) / 2, z_column]], v, t).all()
    assert not inside([[0.0, 0.0, z_pontoon], [0.0, 0.0, z_column], [0.0, 64.6 / 2 - 7.0, z_column]], v, t).any()


def test_peaks_between_rows_are_the_extremes_and_mean_of_every_step():
    """platform/output.Peaks (compiled): over the steps since the last row, the mean, largest and
    smallest ice load of each body and the largest tension of each line, as numpy reduces the
    whole record (sums in the same order: the same bits); a NaN load sticks, as np.maximum's does."""
    from pice.platform.output import Peaks

    rng = np.random.default_rng(7)
    loads = rng.normal(0.0, 1e6, (50, 2, 6))[:, :, :3]  # a view of (n, 6), as the simulation hands it
    tensions = rng.uniform(0.0, 5e6, (50, 12))
    peaks = Peaks()
    for f, t in zip(loads, tensions):
        peaks.track(f, t)
    d = peaks.take()
    assert d["n"] == 50 and peaks.take() is None
    total = loads[0].copy()
    for f in loads[1:]:
        total += f
    assert np.array_equal(d["ice_sum"], total)
    assert np.array_equal(d["ice_max"], loads.max(axis=0)) and np.array_equal(d["ice_min"], loads.min(axis=0))
    assert np.array_equal(d["tension_max"], tensions.max(axis=0))
    bad = loads[1].copy()
    bad[0, 0] = np.nan
    for f in (loads[0], bad, loads[2]):
        peaks.track(f, tensions[0])
    d = peaks.take()
    assert np.isnan(d["ice_max"][0, 0]) and np.isnan(d["ice_min"][0, 0]) and not np.isnan(d["ice_max"][1, 0])
