"""The platform in waves (issue 14, item 4; seed 003 Eqs. 9-12; docs/waves.md): the hull's buoyancy
and Froude-Krylov load as one pressure integral over the wetted panels (platform.hull_waves), the
DEM mooring lines' Morison loads in the waves' particle velocity and acceleration, and the sea at
the platform's time.

References, one per test:
- the divergence theorem: in still water the pressure integral over the wetted hull is rho g V at
  the centre of buoyancy of Eq. 12's volume (hull_buoyancy), braces included;
- linear theory's long-wave limit: a free floating body heaves with the wave (RAO 1, in phase),
  and the linear heave RAO of a box in deep water, (C e^(-kT) sinc(kL/2) - A33 w^2 e^(k z_b)) /
  (C - (m + A33) w^2), C = rho g A_wp (Froude-Krylov on the bottom, Eq. 11's A a at the centre of
  buoyancy z_b);
- the Froude-Krylov force on a truncated vertical circular cylinder (radius R, draft T) in deep
  water, by integrating p = rho g a e^(kz) cos(kx - wt) over it: horizontal F_x = -2 pi R J1(kR)
  rho g a (1 - e^(-kT)) / k sin(wt), vertical (bottom) F_z = rho g a e^(-kT) pi R^2 2 J1(kR)/(kR)
  cos(wt) (e.g. Faltinsen 1990, ch. 3, for the slender limit J1(kR) -> kR/2);
- Morison's equation for a line node (the hand formula of mooring_line_kernels' docstring).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scenes import barge_job, job_from_text
from scipy.special import j1

from pice.io.checkpoint import read_checkpoint, write_checkpoint
from pice.physics.waves import Sea
from pice.platform.build import build_platform, hulls_from_job
from pice.platform.hull_waves import panel_mesh, wave_loads, wave_points
from pice.platform.hulls import box, revolved, semi_submersible, semi_submersible_braces
from pice.platform.mooring_line_kernels import node_forces
from pice.platform.mooring_lines import LINE_ELEMENT_RECORD, LineWater, MooringLines, Seabed
from pice.platform.platform import Attachment, MooringGroup, Platform
from pice.platform.rigid_body import RigidBody
from pice.platform.sea import sea_components
from pice.platform.wave_intervals import WAVE_FIELDS, WAVE_INTERVAL, blend_waves, corner_waves, node_waves
from pice.simulation import Simulation

RHO, G = 1025.0, 9.81


@pytest.mark.nojit
def test_still_water_pressure_integral_is_the_eq12_buoyancy():
    """A sea of zero height through the wave path: the pressure integral over the semi-submersible's
    wetted panels plus its sliced braces equals rho g V at the Eq. 12-14 centre of buoyancy, force and
    moment, for a heeled, shifted pose. Tolerance 1e-12 of the buoyancy (measured 5e-15: round-off of
    ~3,000 panel sums)."""
    v, t = semi_submersible()
    b = RigidBody("semi", 3.5e7, np.array([3e10, 5e10, 6e10]), v, t, braces=semi_submersible_braces())
    b.x = np.array([0.3, -0.2, -5.1])
    a = math.radians(3.0)
    b.q = np.array([math.cos(a / 2), 0.6 * math.sin(a / 2), 0.8 * math.sin(a / 2), 0.0])
    f0, m0, _ = b.hydrostatics(rho_w=RHO, g=G, level=0.0)
    f1, m1 = wave_loads(b, sea_components(Sea.regular(height=0.0, period=8.0)), 3.0, rho_w=RHO, g=G, level=0.0)
    scale = abs(f0[2])
    np.testing.assert_allclose(f1, f0, rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(m1, m0, rtol=0, atol=1e-12 * scale * 10.0)  # moments: arms of ~10 m


# -- a free box in long waves --------------------------------------------------------------------
L_BOX, DRAFT, H_BOX = 10.0, 2.0, 4.0    # [m]
WAVELENGTH, HEIGHT = 200.0, 0.5          # [m]: lambda = 20 L_box, H/draft = 1/4


def heave_rao_linear(k: float, omega: float, a33: float) -> float:
    """The linear heave RAO of the box (module docstring), deep water."""
    c = RHO * G * L_BOX ** 2
    m = RHO * L_BOX ** 2 * DRAFT
    kl = 0.5 * k * L_BOX
    return (c * math.exp(-k * DRAFT) * math.sin(kl) / kl - a33 * omega ** 2 * math.exp(-k * DRAFT / 2)) / (
        c - (m + a33) * omega ** 2)


@pytest.mark.parametrize("a33_ratio", [0.0, 1.0])
def test_free_box_heaves_with_a_long_wave(a33_ratio):
    """A 10 m box of 2 m draft, free in six degrees of freedom, in a regular deep-water wave 200 m long
    and 0.5 m high: its heave follows the wave, RAO within 5 % of 1 and phase within 3 degrees of 0
    (the long-wave limit), and within 1 % of the box's linear RAO (0.9979; 1.0000 with a heave
    added mass A33 = m, Eq. 11's A a). Started on the linear steady state (heave and surge velocity of the
    wave), run three wave periods at dt = 0.01 s (1/280 of the heave period; the platform sums the
    sea at the panel corners every 5 steps and interpolates, an error of (omega 0.05 s)^2 / 8 = 1e-4
    of the wave); the heave is fitted by least squares to the wave frequency plus the free heave
    frequency, so a start-up transient does not bias the amplitude. The 1 % allows the second-order
    terms (H k = 0.016, H/draft = 1/4) and the fit; measured: 0.99792 and 0.99998 (3e-5 and 4e-5 from
    the linear RAO), phase 0.02 degrees (0.99798 and 1.00005 with the sea summed every step)."""
    sea = Sea.regular(height=HEIGHT, period=math.sqrt(2 * math.pi * WAVELENGTH / G))
    k, w, a = float(sea.k[0]), float(sea.omega[0]), HEIGHT / 2
    v, t = box(L_BOX, L_BOX, H_BOX, (0.0, 0.0, H_BOX / 2 - DRAFT / 2))  # CG half-way down the draft
    m = RHO * L_BOX ** 2 * DRAFT
    inertia = m / 12.0 * np.array([L_BOX ** 2 + H_BOX ** 2, L_BOX ** 2 + H_BOX ** 2, 2.0 * L_BOX ** 2])
    a33 = a33_ratio * m
    body = RigidBody("box", m, inertia, v, t, added_mass=np.array([0.0, 0.0, a33, 0.0, 0.0, 0.0]),
                     panels=panel_mesh(v, t, 1.0))
    rao = heave_rao_linear(k, w, a33)
    z0 = -DRAFT / 2
    body.x = np.array([0.0, 0.0, z0 + a * rao])   # eta(0, 0) = a: a crest over the box at t = 0
    body.v = np.array([a * w * math.exp(-k * DRAFT / 2), 0.0, 0.0])  # the orbital velocity at the centre
    p = Platform([body], rho_w=RHO, g=G, level=0.0, sea=sea)
    dt, steps = 0.01, int(round(3 * 2 * math.pi / w / 0.01))
    p.loads()
    times, heave = [], []
    for _ in range(steps):
        p.kick(0.5 * dt)
        p.drift(dt)
        p.loads()
        p.kick(0.5 * dt)
        times.append(p.time)
        heave.append(body.x[2] - z0)
    times, heave = np.asarray(times), np.asarray(heave)
    wn = math.sqrt(RHO * G * L_BOX ** 2 / (m + a33))
    basis = np.column_stack([np.cos(w * times), np.sin(w * times), np.cos(wn * times), np.sin(wn * times),
                             np.ones_like(times)])
    c = np.linalg.lstsq(basis, heave, rcond=None)[0]
    amplitude = math.hypot(c[0], c[1]) / a
    phase = math.degrees(math.atan2(c[1], c[0]))  # z = A cos(w t - phase), eta at the box = a cos(w t)
    assert amplitude == pytest.approx(1.0, abs=0.05)
    assert abs(phase) < 3.0
    assert amplitude == pytest.approx(rao, rel=0.01)


# -- Froude-Krylov load on a fixed truncated cylinder ---------------------------------------------
def test_froude_krylov_force_on_a_vertical_cylinder():
    """A fixed vertical cylinder, R = 5 m, draft 20 m, in a deep-water wave 100 m long and 2 cm high
    (kR = 0.31, kT = 1.26): the wave loads less the still-water buoyancy over one period, fitted to
    cos and sin of w t, give the analytic Froude-Krylov amplitudes (module docstring) for the
    mesh's section, the inscribed 64-gon (its area is sin(2 pi/64) / (2 pi/64) = 0.99839 of the
    circle's, and for kR this small both forces scale with it), within 1e-3: panels of at most 1 m
    with p linear across them ((k * 1 m)^2 / 8 = 5e-4) and the second-order terms (a k = 6e-4).
    Measured: 1e-4 (F_x) and 1.4e-4 (F_z); against the circle's values 1.5e-3 and 1.7e-3. The
    out-of-phase parts vanish within 1e-3 too."""
    radius, draft, freeboard = 5.0, 20.0, 5.0
    profile = [(z, radius) for z in np.linspace(-draft, freeboard, 26)]
    v, t = revolved(profile, 64)
    body = RigidBody("spar", 1.0, np.ones(3), v, t, panels=panel_mesh(v, t, 1.0))
    sea = Sea.regular(height=0.02, period=math.sqrt(2 * math.pi * 100.0 / G))
    comps = sea_components(sea)
    k, w, a = float(sea.k[0]), float(sea.omega[0]), 0.01
    f0, _, _ = body.hydrostatics(rho_w=RHO, g=G, level=0.0)
    times = np.arange(16) / 16 * 2 * math.pi / w
    loads = np.array([wave_loads(body, comps, tt, rho_w=RHO, g=G, level=0.0)[0] - f0 for tt in times])
    basis = np.column_stack([np.cos(w * times), np.sin(w * times)])
    fx = np.linalg.lstsq(basis, loads[:, 0], rcond=None)[0]
    fz = np.linalg.lstsq(basis, loads[:, 2], rcond=None)[0]
    fx_ref = -2 * math.pi * radius * j1(k * radius) * RHO * G * a * (1 - math.exp(-k * draft)) / k
    fz_ref = RHO * G * a * math.exp(-k * draft) * math.pi * radius ** 2 * 2 * j1(k * radius) / (k * radius)
    polygon = math.sin(2 * math.pi / 64) / (2 * math.pi / 64)
    fx_ref, fz_ref = polygon * fx_ref, polygon * fz_ref
    assert fx[1] == pytest.approx(fx_ref, rel=1e-3)
    assert abs(fx[0]) < 1e-3 * abs(fx_ref)
    assert fz[0] == pytest.approx(fz_ref, rel=1e-3)
    assert abs(fz[1]) < 1e-3 * abs(fz_ref)
    # the wave runs along x: no sway force but for the panels, split without mirror symmetry in y
    assert np.abs(loads[:, 1]).max() < 1e-3 * abs(fx_ref)


# -- a mooring line in waves ---------------------------------------------------------------------
D, L0, WET, CDN, CDT, CA = 0.1, 10.0, 150.0, 1.2, 0.008, 1.0


def straight_line(sea, z: float) -> MooringLines:
    """Three nodes along x at height z [m], bonds exactly at their length (no tension); the middle
    node is free and stands for one element length L0 of line."""
    x = np.array([[0.0, 0.0, z], [L0, 0.0, z], [2 * L0, 0.0, z]])
    props = np.array([(1e8, L0, D, WET, CDN, CDT, CA, 0.0)] * 2, LINE_ELEMENT_RECORD)
    return MooringLines(x=x, v=np.zeros((3, 3)), mass=np.full(3, 100.0), prev=np.array([-1, 0, 1]),
                        seg=np.array([0, 0, 1]), kind=np.array([1, 0, 1]), props=props,
                        anchors=np.array([0]), fairleads=np.array([2]), water=LineWater(RHO, 0.0),
                        current=np.array([0.3, -0.1, 0.0]),
                        seabed=Seabed(-math.inf, 0.0, 0.5, 0.5, 0.01), sea=sea_components(sea))


def morison_by_hand(sea, point, velocity, current, t):
    """Weight and Morison load [N] on a node of length L0 with tangent x (module docstring)."""
    u, acc, _ = sea.kinematics(np.asarray(point, float)[None, :], t)
    r = current + u[0] - velocity
    r_t = np.array([r[0], 0.0, 0.0])
    r_n = r - r_t
    a_n = acc[0] - np.array([acc[0, 0], 0.0, 0.0])
    vol = math.pi * D ** 2 / 4 * L0
    drag = 0.5 * RHO * CDN * D * L0 * np.linalg.norm(r_n) * r_n + 0.5 * RHO * CDT * math.pi * D * L0 * abs(r[0]) * r_t
    return np.array([0.0, 0.0, -WET * L0]) + drag + RHO * vol * (acc[0] + CA * a_n)


@pytest.mark.nojit
def test_line_node_morison_load_in_waves():
    """The middle node of a horizontal line 3 m under a 4 m, 7 s wave with a 0.3 m/s current: its
    load is the hand formula (weight, normal and tangential drag on the current plus the wave's
    particle velocity relative to the node, Froude-Krylov and added mass on the particle
    acceleration) to 1e-10; moving with the water (node velocity = current + particle velocity) the
    drag vanishes and weight and inertia are left. Sea from physics.waves.Sea.kinematics, the array
    kernel, independent of the point kernel the lines use."""
    sea = Sea.regular(height=4.0, period=7.0, direction_deg=30.0)
    t = 2.3
    line = straight_line(sea, -3.0)
    line.time = t
    current = line.current.copy()
    u, acc, _ = sea.kinematics(line.x[1][None, :], t)
    for velocity in (np.array([0.2, 0.5, -0.4]), current + u[0]):  # the second: carried by the water
        line.v[1] = velocity
        line._forces()
        ref = morison_by_hand(sea, line.x[1], velocity, current, t)
        np.testing.assert_allclose(line.force[1], ref, rtol=1e-10, atol=1e-10 * np.abs(ref).max())
    a_n = acc[0] * np.array([0.0, 1.0, 1.0])
    weight_and_inertia = np.array([0.0, 0.0, -WET * L0]) + RHO * math.pi * D ** 2 / 4 * L0 * (acc[0] + CA * a_n)
    np.testing.assert_allclose(line.force[1], weight_and_inertia, rtol=1e-10)  # no drag left


@pytest.mark.nojit
def test_line_node_above_the_wave_surface_is_dry():
    """A node 1 m above the still level under a trough (eta = -2 m) carries its weight only; under
    the crest half a period later (eta = +2 m) it is wet and feels the waves' Morison load."""
    sea = Sea.regular(height=4.0, period=7.0)
    line = straight_line(sea, 1.0)
    # x = 10 m: eta = 2 cos(k 10 - w t) = -2 at w t = k 10 - pi
    line.time = (float(sea.k[0]) * L0 - math.pi) / float(sea.omega[0]) + 7.0
    line._forces()
    np.testing.assert_allclose(line.force[1], [0.0, 0.0, -WET * L0], atol=1e-9)
    line.time += 3.5
    line._forces()
    ref = morison_by_hand(sea, line.x[1], np.zeros(3), line.current, line.time)
    np.testing.assert_allclose(line.force[1], ref, rtol=1e-10)


def buoy_and_line(sea, panel):
    """(Platform, its 4 m box buoy (panels of at most ``panel`` [m]; None: the hull mesh), the
    three-node ``straight_line`` 3 m down whose middle node is held and whose fairlead the box carries)."""
    line = straight_line(sea, -3.0)
    line.kind[1] = 1
    v, t = box(4.0, 4.0, 4.0)
    body = RigidBody("buoy", RHO * 32.0, np.full(3, 1e5), v, t, panels=panel_mesh(v, t, panel) if panel else None)
    return Platform([body], rho_w=RHO, g=G, level=0.0, sea=sea,
                    groups=[MooringGroup(line, [Attachment(0, 0, np.array([2 * L0, 0.0, -3.0]))])]), body, line


@pytest.mark.nojit
def test_platform_steps_its_lines_on_its_own_clock():
    """After Platform.drift from t = 5 s the lines' clock is the platform's, and the forces they hold
    are those of the sea at that time (1e-12), not at the start of the step: each sub-step's forces
    are taken at its end time, the last at t + dt. The middle node is held (kind fixed) so that its
    velocity, and with it the drag, is the same for both evaluations, and so that the waves the
    lines take at the nodes' places at the interval's start are those at its end position. dt =
    0.05 s = WAVE_INTERVAL: the interval is this one step, the last sub-step's interpolation weight
    is exactly 1, and what is left is the round-off of the phase turned by omega dt in node_waves
    (~1e-15). Shorter steps: test_platform_interpolates_the_sea_within_its_bound."""
    sea = Sea.regular(height=4.0, period=7.0)
    p, body, line = buoy_and_line(sea, None)
    line.time = 0.0
    p.time = 5.0
    body.x = np.zeros(3)
    p.drift(0.05)
    assert line.time == pytest.approx(p.time, abs=1e-12)
    held = line.force.copy()
    line._forces()
    np.testing.assert_allclose(held[1], line.force[1], rtol=1e-12)
    line.time = 5.0
    line._forces()
    assert np.abs(held[1] - line.force[1]).max() > 1.0  # [N]: the sea at the start differs


@pytest.mark.nojit
def test_line_waves_taken_at_two_times_and_interpolated():
    """The sea at the line nodes at the two ends of an interval of h (node_waves, one pass over the
    components; corner_waves: eta and p_d at the hull's panel corners), interpolated linearly in time
    (blend_waves). Against Sea.elevation and Sea.kinematics (the array kernels), a 4 m, 7 s wave in 30 m
    of water, at nodes above, in and below the water and under the seabed (clipped): at both ends to
    1e-12 of each field's largest amplitude (round-off); at a = k/8 within linear interpolation's
    bound for a harmonic, (omega h)^2 / 8 of the amplitude (h = 0.05 s = WAVE_INTERVAL: 2.5e-4;
    docs/waves.md, Cost). Amplitude of a field f: hypot(f(t), f(t + T/4))."""
    period, h, t0, depth = 7.0, 0.05, 2.3, 30.0
    sea = Sea.regular(height=4.0, period=period, direction_deg=30.0, depth=depth)
    comps = sea_components(sea)
    x = np.array([[0.0, 0.0, 1.0], [13.0, -4.0, -0.5], [-20.0, 7.0, -12.0], [5.0, 30.0, -29.0],
                  [40.0, 2.0, -31.0]])
    level = 0.5  # the lines' water level [m]; z from it
    wave0, wave1, blend, corner0, corner1 = (np.empty((len(x), f)) for f in (WAVE_FIELDS,) * 3 + (2, 2))
    node_waves(comps, x, level, t0, t0 + h, wave0, wave1)
    pts = x - np.array([0.0, 0.0, level])
    corner_waves(comps, x, level, t0, t0 + h, corner0, corner1)
    for fields, ends in ((WAVE_FIELDS, (wave0, wave1)), (2, (corner0, corner1))):
        scale = 1e-12 * np.hypot(_sea_at(sea, pts, t0, fields), _sea_at(sea, pts, t0 + period / 4, fields)).max(axis=0)
        for end, t in zip(ends, (t0, t0 + h)):  # per field (u_z and a_z vanish at the seabed)
            assert (np.abs(end - _sea_at(sea, pts, t, fields)) <= scale).all()
    amplitude = np.hypot(_sea_at(sea, pts, t0, WAVE_FIELDS), _sea_at(sea, pts, t0 + period / 4, WAVE_FIELDS))
    round_off = 1e-12 * amplitude.max(axis=0)
    bound = (2 * math.pi / period * h) ** 2 / 8
    worst = 0.0
    for k in range(1, 8):
        blend_waves(wave0, wave1, k / 8, blend)
        error = np.abs(blend - _sea_at(sea, pts, t0 + k / 8 * h, WAVE_FIELDS))
        assert (error <= bound * amplitude + round_off).all()
        worst = max(worst, float((error / np.maximum(amplitude, round_off)).max()))
    assert worst > 0.1 * bound  # the bound is the error's scale, not far above it


def _sea_at(sea, pts, t, fields):
    """The sea at points (n, 3) [m] at t [s] by Sea.elevation and Sea.kinematics: (n, 2) eta [m], p_d
    [Pa] (panel corners); (n, 7) eta, u [m/s], a [m/s^2] (line nodes)."""
    u, acc, pd = sea.kinematics(pts, t)
    eta = sea.elevation(pts[:, 0], pts[:, 1], t)
    return np.column_stack([eta, pd]) if fields == 2 else np.column_stack([eta, u, acc])


@pytest.mark.nojit
def test_platform_interpolates_the_sea_within_its_bound():
    """The platform sums the sea at its points (hull panel corners, line nodes) at the two ends of
    intervals of N = WAVE_INTERVAL / dt steps, at their places at the interval's start, and
    interpolates it linearly in time (platform.wave_intervals). The buoy (1 m panels) set drifting at
    1 m/s and heaving at 0.3 m/s with its line, in a 4 m, 7 s deep-water wave; dt = 0.05 s / 8 (N = 8),
    24 steps: three intervals. After every step, per field (eta, p_d at the corners; eta, u, a at the
    nodes), against Sea.elevation and Sea.kinematics (the array kernels):
    - at the points' places at the interval's start: within (omega T)^2 / 8 of the field's amplitude
      there (T = 0.05 s: 2.5e-4) plus round-off (1e-12 of its largest amplitude); the sea itself to
      round-off at the interval's end;
    - where the points are now: within that plus the place error k (|d_h| + |d_z|) (phase and depth
      factor; d the displacement since the interval's start; 1 % for its second order) of the larger
      of the amplitudes there and at the start;
    - the held node carries the forces of the interpolated sea at the step's end (1e-12).
    The time error reaches more than a tenth of its bound: the bound is its scale."""
    period, dt, every = 7.0, WAVE_INTERVAL / 8, 8
    sea = Sea.regular(height=4.0, period=period)
    k, time_bound = float(sea.k[0]), (2 * math.pi / period * WAVE_INTERVAL) ** 2 / 8
    p, body, line = buoy_and_line(sea, 1.0)
    p.loads()
    body.v, worst = np.array([1.0, 0.0, 0.3]), 0.0
    for step in range(3 * every):
        if step % every == 0:  # the step that starts an interval: the points' places now
            start = {"corners": wave_points(body)["corners"][0].copy(), "group0": line.x.copy()}
        for call, arg in ((p.kick, 0.5 * dt), (p.drift, dt), (p.loads, None), (p.kick, 0.5 * dt)):
            call(arg)
        assert p.wave_intervals.index == step // every and p.wave_intervals.every == every
        now = {"corners": wave_points(body)["corners"][0], "group0": line.x}
        interpolated = {"corners": p.body_waves(0)["corners"], "group0": p.wave_intervals.at("group0", step + 1)}
        for name, fields in (("corners", 2), ("group0", WAVE_FIELDS)):
            amp0, amp1 = (np.hypot(_sea_at(sea, q, p.time, fields), _sea_at(sea, q, p.time + period / 4, fields))
                          for q in (start[name], now[name]))
            round_off = 1e-12 * np.maximum(amp0, amp1).max(axis=0)
            error = np.abs(interpolated[name] - _sea_at(sea, start[name], p.time, fields))
            assert (error <= time_bound * amp0 + round_off).all(), name
            if (step + 1) % every == 0:
                assert (error <= round_off).all(), name
            worst = max(worst, float(np.divide(error, amp0, out=np.zeros_like(error), where=amp0 > round_off).max()))
            d = now[name] - start[name]
            place = 1.01 * k * (np.hypot(d[:, 0], d[:, 1]) + np.abs(d[:, 2]))
            error = np.abs(interpolated[name] - _sea_at(sea, now[name], p.time, fields))
            assert (error <= (time_bound + place[:, None]) * np.maximum(amp0, amp1) + round_off).all(), name
        force = np.zeros((3, 3))
        node_forces(line.x, line.v, line.mass, line.prev, line.seg, line.props, line.constants, line.kind, line.water,
                    line.current, line.seabed, interpolated["group0"], force, np.zeros(3), np.zeros(3), np.zeros((3, 3)))
        np.testing.assert_allclose(line.force[1], force[1], rtol=1e-12)
    assert worst > 0.1 * time_bound
    assert np.linalg.norm(body.x) > 0.1  # [m]: the box moved, the place error was tested


def test_restart_in_waves_is_bit_for_bit(tmp_path):
    """The barge and its DEM lines in a 2 m, 8 s wave, dt = 1e-4 s (the sea summed every 500 steps): a
    checkpoint at step 450, mid-interval, keeps the platform's step count, the interval and its ends
    ("waves/..."); restarted from it, the run reaches step 650, past the next interval's start, with
    the body pose, line nodes and tensions of the run that went on, bit for bit."""
    waves = '\n[waves]\nspectrum = "regular"\nheight = 2.0\nperiod = 8.0\n'
    job = job_from_text(barge_job(duration=0.07, current=0.5, drag=1.0, mooring="dem") + waves, base_dir=tmp_path)
    sim = Simulation(job)
    sim.advance(450)
    ckpt = write_checkpoint(sim, tmp_path / "w.ckpt.h5")
    state = read_checkpoint(ckpt)["platform"]
    assert int(state["waves/interval"]) == 0 and int(state["waves/every"]) == 500 and int(state["waves/step"]) == 450
    assert state["waves/ends/group0"].shape == (2, len(sim.platform.groups[0].lines.x), WAVE_FIELDS)
    sim.rebuild_for_checkpoint()
    sim.advance(200)
    again = Simulation.from_checkpoint(job, read_checkpoint(ckpt))
    again.advance(200)
    a, b = sim.platform, again.platform
    assert a.wave_intervals.index == b.wave_intervals.index == 1
    for got, want in ((a.bodies[0].x, b.bodies[0].x), (a.bodies[0].q, b.bodies[0].q),
                      (a.polylines()[0], b.polylines()[0]), (a.fairlead_tensions(), b.fairlead_tensions())):
        assert np.array_equal(got, want)


def test_build_platform_floats_the_bodies_in_the_jobs_sea():
    """A job with [waves] and [[bodies]]: build_platform gives the platform, its DEM lines and its
    body the job's sea (panels no longer than a tenth of the 100 m wavelength), and the loads at
    t = 0 carry the wave (its pressure on the barge at x = 22 m: 5.3e5 N up, more than 1e5 N); the
    same job without [waves] builds the still-water platform (no sea, no panels) whose net load at
    rest vanishes (the "balance" mass; 1e-6 of the weight)."""
    waves = '\n[waves]\nspectrum = "regular"\nheight = 2.0\nperiod = 8.0\n'
    job = job_from_text(barge_job(mooring="dem") + waves)
    hulls = hulls_from_job(job, default_kn=1e8, reach=1.0)
    p = build_platform(job, hulls)
    assert p.sea is not None and p.groups[0].lines.sea is p.sea
    wavelength = 2 * math.pi / float(p.sea.k[0])
    pv, pt = p.bodies[0].panels
    edges = np.linalg.norm(pv[pt] - pv[np.roll(pt, 1, axis=1)], axis=2)
    assert edges.max() <= wavelength / 10 * (1 + 1e-9)
    still = build_platform(job_from_text(barge_job(mooring="dem")), hulls)
    assert still.sea is None and still.bodies[0].panels is None and still.groups[0].lines.sea.amplitude.size == 0
    weight = still.bodies[0].mass * G
    assert np.abs(still.bodies[0].force).max() < 1e-6 * weight
    assert abs(p.bodies[0].force[2]) > 1e5
