"""The floes of a job (pice/physics/floe_system.py): issue 14's broken ice as the Simulation steps it.

References:
- a force balance: a floe held against a confining wall by a cross current comes to rest with the
  wall's load equal to the water's drag on it, rho_w (C_w A + 1/2 C_d d b) u^2 (seed 003 Eq. 12 form
  drag on the draft d over the width b across the flow, plus skin drag on the bottom area A), within
  0.5 % (the floe settles on the overdamped contact over ~10 s; 60 s leave a residual speed below
  1e-6 m/s, and the heave settles to the Archimedes draft, which sets d);
- an identity: the owner-block record path (FloeSystem on one rank) and the one-rank Floes step
  give the same forces bit for bit, the base of the rank contract (tests/parallel/test_floes_two_ranks.py);
- a conservation law: the load on a structure is the opposite of the structure forces on the floes.
"""

from __future__ import annotations

import numpy as np

from pice.parallel.comm import SerialComm
from pice.physics.floe_system import FloeSystem
from pice.physics.floes import Floes, FloeLaw, FloeWater
from pice.platform.hulls import revolved
from pice.scenes.floe_field import floe_field

RHO_W, RHO_I, H, SIDE = 1025.0, 920.0, 2.6, 30.0


def _square(cx, cy, side=SIDE):
    h = 0.5 * side
    return np.array([[cx - h, cy - h], [cx + h, cy - h], [cx + h, cy + h], [cx - h, cy + h]])


def _step(system, k, dt, poses=np.zeros((0, 13))):
    """Step k -> k + 1 of dt [s] as the Simulation takes it: half kick, drift, forces, half kick."""
    system.kick(0.5 * dt)
    system.drift(dt)
    system.compute_forces(poses, (k + 1) * dt, dt)
    system.kick(0.5 * dt)


def test_a_floe_pressed_on_a_wall_by_the_current_carries_its_drag():
    u = 0.4
    water = FloeWater(density=RHO_W, current=(0.0, u), skin=0.0055, form=1.0, damping_ratio=0.3)
    draft = H * RHO_I / RHO_W
    floes = Floes([_square(0.0, 50.0 - 0.5 * SIDE - 0.01)], [H], density=RHO_I, base=[-draft], water=water,
                  law=FloeLaw())
    floes.add_wall((0.0, 1.0, 0.0), 50.0)  # y >= 50 m is wall
    system = FloeSystem(floes, SerialComm(), [])
    dt = 0.01
    system.compute_forces(np.zeros((0, 13)), 0.0, dt)
    for k in range(6000):
        _step(system, k, dt)
    assert np.abs(floes.v).max() < 1e-6
    d = -floes.x[0, 2] + 0.5 * H  # the draft where it floats
    drag = RHO_W * (0.0055 * SIDE * SIDE + 0.5 * 1.0 * d * SIDE) * u * u
    wall = system.wall_loads()[0]
    assert abs(wall[1] - drag) <= 0.005 * drag, (wall[1], drag)
    assert abs(d - draft) < 1e-3 * draft


def _field_with_cone():
    field = floe_field(area=(-140.0, -50.0, -38.0, 50.0), size=(20.0, 30.0), concentration=0.85, seed=3)
    thickness = np.asarray(field.thickness)

    def make():
        floes = Floes(field.polygons, thickness, density=RHO_I, base=-thickness * RHO_I / RHO_W,
                      water=FloeWater(density=RHO_W, current=(0.4, 0.0)), law=FloeLaw())
        v, t = revolved([[-12.5, 31.0], [0.0, 35.0]], 24)
        floes.add_structure(v, t, centre=np.zeros(3))
        floes.move_structure(0, x=[0.0, 0.0, 0.0], q=[1.0, 0.0, 0.0, 0.0], v=[-2.0, 0.0, 0.0], w=[0.0, 0.0, 0.0])
        floes.add_wall((0.0, -1.0, 0.0), 50.0)
        floes.add_wall((0.0, 1.0, 0.0), 50.0)
        return floes
    return make


def _cone_at(floes, k, dt):
    """The cone ploughing into the field at 2 m/s: its pose at step k (set by hand, as the body's)."""
    floes.move_structure(0, x=[-2.0 * k * dt, 0.0, 0.0], q=[1.0, 0.0, 0.0, 0.0], v=[-2.0, 0.0, 0.0], w=[0.0, 0.0, 0.0])


def test_the_record_path_matches_the_one_rank_step_bit_for_bit():
    make = _field_with_cone()
    alone, blocks = make(), make()
    system = FloeSystem(blocks, SerialComm(), [])
    dt, no_bodies = 0.005, np.zeros((0, 13))
    alone.compute_forces(dt)
    system.compute_forces(no_bodies, 0.0, dt)
    for k in range(1200):
        _cone_at(alone, k + 1, dt)
        _cone_at(blocks, k + 1, dt)
        alone.step(dt)  # Floes.step: kick, drift, forces of the whole field at once, kick
        _step(system, k, dt, no_bodies)
    assert system.contacts > 0 and system.structure_contacts > 0, "the floes must meet each other and the cone"
    for name in ("x", "v", "q", "L", "force", "torque", "structure_load"):
        assert np.array_equal(getattr(alone, name), getattr(blocks, name)), name


def test_the_structures_take_what_the_floes_lose():
    """Pair forces cancel: the floes' total force less the water's is minus the loads on the cone and
    the walls, to round-off of the largest contact force; the water's (with gravity) is the series'
    floe_water_force, bit for bit on one rank."""
    make = _field_with_cone()
    floes = make()
    system = FloeSystem(floes, SerialComm(), [[0]])
    dt = 0.005
    pose = np.zeros((1, 13))
    pose[0, 3], pose[0, 7] = 1.0, -2.0
    system.compute_forces(pose, 0.0, dt)
    checked = 0
    for k in range(1000):
        pose[0, 0] = -2.0 * (k + 1) * dt
        system.kick(0.5 * dt)
        system.drift(dt)
        system.compute_forces(pose, (k + 1) * dt, dt)
        if k % 100 == 99 and system.structure_contacts:  # at the state the forces were computed for
            total = floes.force.sum(axis=0)
            saved = floes.force.copy(), floes.torque.copy()
            floes.force[:], floes.torque[:] = 0.0, 0.0
            pts, counts = floes.world()
            floes.water_loads(0, system.n, pts, counts, floes.omega, dt)
            water = floes.force.sum(axis=0)
            floes.force[:], floes.torque[:] = saved
            # the series' floe_water_force is that sum: the rubble's force balance in the run file
            assert np.array_equal(system.series_entries()["floe_water_force"], water)
            structures = system.body_loads[0, :3] + system.wall_loads()[:, :3].sum(axis=0)
            scale = np.abs(structures).max()
            assert scale > 1e4
            assert np.allclose(total - water, -structures, rtol=0, atol=1e-9 * scale), (total - water, structures)
            checked += 1
        system.kick(0.5 * dt)
    assert checked >= 3


def test_added_mass_lengthens_the_heave_period():
    """A 30 m square floe with the plate added mass (physics/floes.plate_added_mass) heaves at
    T = 2 pi sqrt((m + A_33) / (rho_w g A)), A_33 = (4/3) rho_w a^3 for the disk of the same area:
    the free oscillation's period within 1 % (light damping, 0.02, lengthens it by 0.02 %)."""
    import math

    from pice.physics.floes import plate_added_mass

    water = FloeWater(density=RHO_W, damping_ratio=0.02)
    draft = H * RHO_I / RHO_W
    floes = Floes([_square(0.0, 0.0)], [H], density=RHO_I, base=[-draft + 0.2], water=water, added_mass=True)
    added, _ = plate_added_mass([SIDE * SIDE], [draft], RHO_W)
    assert floes.added[0, 2] == added[0, 2] > 0.5 * floes.mass[0]  # a thin floe: added mass of its own order
    system = FloeSystem(floes, SerialComm(), [])
    dt, z, t = 0.005, [], []
    system.compute_forces(np.zeros((0, 13)), 0.0, dt)
    for k in range(4000):
        _step(system, k, dt)
        z.append(floes.x[0, 2])
        t.append((k + 1) * dt)
    z = np.asarray(z) - np.mean(z)
    ups = [t[i] for i in range(1, len(z)) if z[i - 1] < 0.0 <= z[i]]
    period = np.mean(np.diff(ups))
    expected = 2.0 * math.pi * math.sqrt((floes.mass[0] + added[0, 2]) / (RHO_W * 9.81 * SIDE * SIDE))
    assert abs(period - expected) <= 0.01 * expected, (period, expected)


def test_a_runaway_or_broken_floe_stops_the_run_naming_it():
    """The health check (Simulation.check_health calls FloeSystem.check): a floe with a NaN, or moving a
    tenth of its size in one step, raises InstabilityError naming the floe and the likely cause."""
    import pytest

    from pice.errors import InstabilityError

    floes = _field_with_cone()()
    system = FloeSystem(floes, SerialComm(), [])
    system.check(10, 0.05)  # at rest in the current: fine
    floes.v[3, 0] = 0.2 * floes.bound[3] / 0.005  # 0.2 of its size in one step of 5 ms
    with pytest.raises(InstabilityError, match=r"floe 3 .* shows a speed of .* likely cause: floes started"):
        system.check(10, 0.05)
    floes.v[3, 0] = 0.0
    floes.x[5, 1] = np.nan
    with pytest.raises(InstabilityError, match=r"floe 5 .* non-finite"):
        system.check(10, 0.05)


def test_the_peak_load_of_a_floe_on_the_cone_hardly_depends_on_the_step():
    """The default floes.step_fraction (0.1 of the shortest pair contact's m_eff / c_n, i.e. 0.05 of a
    floe's own m / c_n against a structure) against 0.01 of it: a 20 m square floe of 2.6 m hitting
    the Kulluk's cone at 0.4 m/s (seed 003 Table 3's law) loads it within 2 % of the fine step's peak
    (measured: -0.5 %; at 0.1 of m / c_n, -2 %; docs/broken_ice.md, "The time step"). The dashpot sees
    the half-step velocity, so the error is first order in c dt / m, but the peak comes from the spring
    and the plastic cap, which the step does not bias."""
    from pice.physics.floes import FloeLaw as Law

    cone = revolved([[-6.553, 31.0], [0.0, 35.0], [9.01, 40.5]], 24)

    def peak(fraction):
        floes = Floes([_square(-35.0 - 10.0 - 0.2, 0.0, side=20.0)], [2.6], density=RHO_I, base=[-2.33], law=Law())
        floes.add_structure(*cone, centre=np.zeros(3))
        floes.v[0, 0] = 0.4
        dt = fraction * floes.mass[0] / Law().cn
        floes.compute_forces(dt)
        top = 0.0
        for _ in range(int(8.0 / dt)):
            floes.step(dt)
            top = max(top, abs(floes.structure_load[0, 0]))
        return top

    fine, default = peak(0.01), peak(0.05)
    assert fine > 1e5
    assert abs(default - fine) <= 0.02 * fine, (default, fine)


def test_a_floe_wholly_under_water_floats_on_its_whole_volume():
    """A keel's block under the cover is wholly submerged: kernels/floe_hydro.floe_water takes its
    buoyancy as rho_w g V at its centre without clipping it at the surface. Reference: Archimedes, and
    the clipped part (kernels/polyhedron_contact.part_inside, the path a floe at the surface takes) of
    the same tilted block cut by a plane above it, whose volume and centre must be the whole block's
    (to 1e-12: round-off of sums over 6 faces); at rest the net vertical force is (rho_w V - m) g and
    the torque zero (1e-9 of the buoyancy times the block's size)."""
    from pice.kernels.geometry import quat_mul
    from pice.kernels.polyhedron_contact import part_inside

    rect = np.array([[-0.5, -0.31], [0.5, -0.31], [0.5, 0.31], [-0.5, 0.31]])
    water = FloeWater(density=1010.0, level=0.0, gravity=9.81, current=(0.0, 0.0), sea=None)
    floes = Floes([rect + [3.0, 1.0]], np.array([0.3]), density=920.0, base=np.array([-4.0]), law=FloeLaw(),
                  water=water)
    tilt = np.array([np.cos(0.2), np.sin(0.2) * 0.6, np.sin(0.2) * 0.8, 0.0])  # 23 deg about a horizontal axis
    floes.q[0] = quat_mul(tilt, floes.q[0])
    pts, counts = floes.world()
    assert pts[0, ..., 2][np.arange(pts.shape[2])[None, :] < counts[0][:, None]].max() < -3.0  # under water
    volume = floes.area[0] * 0.3
    floes.force[:], floes.torque[:] = 0.0, 0.0
    floes.water_loads(0, 1, pts, counts, floes.omega, 1e-3)
    g, fb = 9.81, 1010.0 * 9.81 * volume
    assert abs(floes.force[0, 2] - (fb - floes.mass[0] * g)) <= 1e-12 * fb
    assert np.abs(floes.torque[0]).max() <= 1e-9 * fb
    vol, centre, *_ = part_inside(pts[0], counts[0], 0.0, 0.0, 1.0, 10.0, np.empty((2, pts.shape[2] + 2, 3)))
    assert abs(vol - volume) <= 1e-12 * volume
    assert np.abs(centre - floes.x[0]).max() <= 1e-12 * 4.0


def test_a_block_under_water_drags_on_its_own_faces_not_on_the_water_above_it():
    """A keel's block wholly under the surface meets the water on its faces only: form drag
    1/2 rho_w C_d h b |u| u across its height h = 0.3 m (not the depth of its bottom, which would
    count the water column above it), skin drag rho_w C_w A |u| u, and vertically
    1/2 rho_w C_d A |w| w on its plan area A; it has no water plane, so no heave, roll or pitch
    damping (kernels/floe_hydro.py). References: the form drag's definition (seed 003 Eq. 12 on the
    projected area) and Archimedes; to 1e-12 (round-off of sums over the block's faces). The same
    block 1 m and 4 m deep feels the same loads."""
    rect = np.array([[-0.5, -0.31], [0.5, -0.31], [0.5, 0.31], [-0.5, 0.31]])
    water = FloeWater(density=1010.0, level=0.0, gravity=9.81, current=(0.0, 0.0), sea=None)
    u, w = 0.8, -0.5  # [m/s] ploughed ahead and pushed down
    loads = []
    for depth in (1.0, 4.0):
        floes = Floes([rect], np.array([0.3]), density=920.0, base=np.array([-depth]), law=FloeLaw(),
                      water=water, velocity=(u, 0.0, w))
        floes.L[0] = [3.0, -2.0, 1.0]  # turning: no roll or pitch damping may act on it
        pts, counts = floes.world()
        floes.force[:], floes.torque[:] = 0.0, 0.0
        floes.water_loads(0, 1, pts, counts, floes.omega, 1e-3)
        loads.append((floes.force[0].copy(), floes.torque[0].copy(), floes.mass[0]))
    area = 1.0 * 0.62
    for force, torque, mass in loads:
        drag_x = 1010.0 * (water.skin * area + 0.5 * water.form * 0.3 * 0.62) * u * u
        assert abs(force[0] + drag_x) <= 1e-12 * drag_x, (force[0], drag_x)
        assert force[1] == 0.0
        fz = (1010.0 * area * 0.3 - mass) * 9.81 - 0.5 * 1010.0 * water.form * area * abs(w) * w
        assert abs(force[2] - fz) <= 1e-12 * abs(fz), (force[2], fz)
        assert np.abs(torque).max() <= 1e-12 * abs(fz)


def test_a_block_under_water_in_a_wave_drags_against_the_waters_vertical_motion():
    """A block wholly under the surface, at rest where the wave's water moves straight up (deep-water
    Airy wave, seed 003's linear sea: eta = a cos theta, u_x = a omega e^(kz) cos theta, u_z = a omega
    e^(kz) sin theta, a_x = a omega^2 e^(kz) sin theta, a_z = -a omega^2 e^(kz) cos theta; at theta =
    pi / 2 u_z is at its largest, and there is no horizontal velocity and no vertical acceleration),
    feels vertically Archimedes' buoyancy less its weight and the form drag of the water rising past
    it, 1/2 rho_w C_d A |u_z| u_z upwards on its plan area A (kernels/floe_hydro.py: the drag on the
    block's velocity relative to the water's), and horizontally the Froude-Krylov force (rho_w V + A_x)
    a_x (seed 003 Eq. 11). To 1e-9 (the sea's sum against the formulas here)."""
    import math

    from pice.physics.waves import Sea

    rect = np.array([[-0.5, -0.31], [0.5, -0.31], [0.5, 0.31], [-0.5, 0.31]])
    sea = Sea.regular(height=2.0, period=6.0, phase=0.5 * math.pi, density=1010.0)
    water = FloeWater(density=1010.0, level=0.0, gravity=9.81, current=(0.0, 0.0), sea=sea, skin=0.0)
    floes = Floes([rect], np.array([0.3]), density=920.0, base=np.array([-4.0]), law=FloeLaw(), water=water)
    pts, counts = floes.world()
    floes.force[:], floes.torque[:] = 0.0, 0.0
    floes.water_loads(0, 1, pts, counts, floes.omega, 1e-3)
    k, omega, a = sea.k[0], sea.omega[0], 1.0
    uz = a * omega * math.exp(k * floes.x[0, 2])  # [m/s] at the block's centre, theta = pi / 2 at x = 0, t = 0
    area = 1.0 * 0.62
    fz = (1010.0 * area * 0.3 - floes.mass[0]) * 9.81 + 0.5 * 1010.0 * water.form * area * uz * uz
    assert uz > 0.6  # the test means something: the drag is of the order of the net buoyancy (145 against 164 N)
    assert abs(floes.force[0, 2] - fz) <= 1e-9 * abs(fz), (floes.force[0, 2], fz)
    fx = (1010.0 * area * 0.3 + floes.added[0, 0]) * a * omega * omega * math.exp(k * floes.x[0, 2])
    assert abs(floes.force[0, 0] - fx) <= 1e-9 * abs(fx), (floes.force[0, 0], fx)
    assert abs(floes.force[0, 1]) <= 1e-9 * abs(fz)


def test_a_checkpoint_from_before_the_vertical_particle_velocity_sums_the_sea_again():
    """A checkpoint written before the sea at the floes kept u_z holds 6 columns; restored, it is not
    read as the 7 the kernel now takes: the next step sums the sea at the floes again, and its loads
    are those of a floe system that never stopped (the sea summed at the interval's start from the
    same places: bit for bit)."""
    import math

    from pice.physics.waves import Sea

    def system():
        sea = Sea.regular(height=2.0, period=6.0, phase=0.5 * math.pi, density=1010.0)
        water = FloeWater(density=1010.0, sea=sea)
        floes = Floes([_square(0.0, 0.0, side=1.0)], [0.3], density=920.0, base=[-4.0], law=FloeLaw(), water=water)
        return FloeSystem(floes, SerialComm(), [])

    dt = 1e-3
    fresh, restored = system(), system()
    fresh.compute_forces(np.zeros((0, 13)), 0.0, dt)
    state = fresh.state()
    old = dict(state, wave_ends=state["wave_ends"][..., :6])  # the columns an older checkpoint held
    restored.set_state(old, "old.ckpt.h5")
    assert restored.f.wave_ends is None
    restored.compute_forces(np.zeros((0, 13)), 0.0, dt)
    assert np.array_equal(restored.f.force, fresh.f.force)
    assert restored.f.wave_ends[1].shape[-1] == 7


def _glancing_block(friction):
    """A 1 m x 0.3 m block with no water, moving at 1 m/s along a wall y <= 0 and 0.2 m/s into it,
    after 2 s (the bounce takes ~15 ms)."""
    floes = Floes([_square(0.0, 0.52, side=1.0)], [0.3], density=RHO_I, base=[0.0], velocity=(1.0, -0.2, 0.0),
                  law=FloeLaw(kn=1e7, cn=0.0, kt=0.6e7, mu=0.3))
    floes.add_wall((0.0, -1.0, 0.0), 0.0, friction)
    system = FloeSystem(floes, SerialComm(), [])
    dt = 1e-4
    system.compute_forces(np.zeros((0, 13)), 0.0, dt)
    for k in range(20000):
        _step(system, k, dt)
    return floes


def test_a_symmetry_wall_is_frictionless_and_a_basin_wall_has_the_contact_friction():
    """A half model's symmetry plane carries no shear (the mirrored ice moves with the ice there), so a
    block glancing off a wall given friction 0 (physics/keel.keel_walls, symmetry) keeps its speed
    along the wall to round-off (the normal force acts through the overlap's centroid, on the
    block's face centre: no torque turns the block). With the contact's friction 0.3 (a basin wall)
    the block slides along the wall throughout the bounce, so Coulomb's law holds for the impulses:
    the loss of speed along the wall is 0.3 times the change of speed across it, within 1 % (the
    tangential spring's first steps, before it reaches the friction limit; measured 0.02 %). The
    friction also spins the block, whose corner then throws it off faster than it came."""
    free, rough = _glancing_block(0.0), _glancing_block(None)
    assert free.v[0, 1] > 0.1 and rough.v[0, 1] > 0.1  # bounced off
    assert abs(free.v[0, 0] - 1.0) < 1e-9, free.v[0]
    along, across = 1.0 - rough.v[0, 0], rough.v[0, 1] + 0.2
    assert abs(along - 0.3 * across) < 0.01 * 0.3 * across, rough.v[0]
