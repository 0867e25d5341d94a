"""Single parallel bonds: failure in tension, shear and bending, and the bond kernel's invariants.

Reference: Zhu & Ji (2022), ../shared/seeds/000_d6dfa5ea71378166.txt, section 2.1-2.2:

    Eq. 1   dF_n = k_n A dU_n,  dF_s = -k_s A dU_s
    Eq. 2   dM_t = -k_s J dtheta_n,  dM_b = -k_n I dtheta_s
    Eq. 3   sigma_max = -F_n/A + |M_b| R / I      (here tension T = -F_n > 0)
    Eq. 4   tau_max = |F_s|/A + |M_t| R / J
    Eq. 5   tau_c = mu sigma_max + sigma_s
    Eq. 6   sigma_b = sigma_f / (1.77 - 1.81 exp(-(L/D)/4.78))
    Eq. 7   mu = 0.23 sigma_c / sigma_f - 0.5

The pair tests drive a bonded pair (no gravity, no water) quasi-statically: every velocity is
prescribed (translations through fix_mask/fix_velocity; rotations by giving the elements an
enormous moment of inertia so the bond's own torque cannot change the angular velocity we set),
at a rate chosen so the breaking quantity changes by 5e-5 of its critical value per step. The
value recorded at the breaking step therefore overshoots the strength by at most 5e-5, far inside
the 1 % the issue asks for; the tests also require the step before to be below the criterion.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from pice.job import parse_job
from pice.kernels.bonds import sync_mate_history, bond_forces, bond_update
from pice.physics.bond import BondLaw, bond_params_from_job, eq6_bond_strength, eq7_bond_friction
from pice.simulation import Simulation
from pice.state import BOND_HIST, MAX_BONDS

pytestmark = pytest.mark.nojit  # each test runs in a few seconds with NUMBA_DISABLE_JIT=1

SIGMA_N = 1.5e6      # normal strength [Pa]
SIGMA_S = 1.2e6      # shear (cohesive) strength sigma_s of Eq. 5 [Pa]
MU = 0.3             # inner friction of Eq. 5
K = 1.72e9           # normal and shear spring [N/m]; stiff so the shear test's geometric
                     # stretch (k dy^2 / 2 L) stays ~1e-3 of the strengths
RATE = 5e-5          # change of the breaking quantity per step, as a fraction of its critical value
HUGE_INERTIA = 1e30  # [kg m^2]: angular velocity stays exactly as prescribed


def _pair(shear_stiffness=K, normal_stiffness=K):
    job = parse_job({
        "run": {"duration": 1.0}, "gravity": 0.0,
        "ice": {"length": 2.0, "width": 1.0, "density": 920.0},
        "bond": {"normal_stiffness": normal_stiffness, "shear_stiffness": shear_stiffness,
                 "normal_strength": SIGMA_N, "shear_strength": SIGMA_S, "friction": MU},
    })
    sim = Simulation(job)
    p = sim.p
    assert p.n == 2 and p.bond_gid[0, 0] == 1 and p.bond_gid[1, 0] == 0
    np.testing.assert_allclose(p.x[1] - p.x[0], [1.0, 0.0, 0.0])
    p.inertia[:] = HUGE_INERTIA
    p.fix_mask[:] = True
    p.fix_velocity[:] = 0.0
    p.v[:] = 0.0
    p.w[:] = 0.0
    return sim


def _drive(sim, velocity1=(0.0, 0.0, 0.0), w0=(0.0, 0.0, 0.0), w1=(0.0, 0.0, 0.0), max_steps=100_000,
           stop_on_break=True, nsteps=None):
    """Prescribe element 1's velocity and both angular velocities; step until the bond breaks.

    Returns (history at the breaking step, history one step before, steps taken).
    """
    p = sim.p
    p.fix_velocity[1] = velocity1
    p.v[1] = velocity1
    p.fix_velocity[0] = 0.0
    p.v[0] = 0.0
    p.w[0], p.w[1] = w0, w1
    prev = p.bond_hist[0, 0].copy()
    nev = len(sim.c.events)
    for k in range(nsteps if nsteps is not None else max_steps):
        prev = p.bond_hist[0, 0].copy()
        sim.step()
        p.w[0], p.w[1] = w0, w1  # already unchanged (huge inertia); keep them exact regardless
        if stop_on_break and len(sim.c.events) > nev:
            return p.bond_hist[0, 0].copy(), prev, k + 1
    if nsteps is None:
        raise AssertionError(f"the bond did not break in {max_steps} steps")
    return p.bond_hist[0, 0].copy(), prev, nsteps


def _stresses(h, b):
    """(sigma_max of Eq. 3, tau_max of Eq. 4) [Pa] of a history row h for bond parameters b."""
    sigma = h[7] / b.area + np.linalg.norm(h[4:7]) * b.disk_radius / b.inertia
    tau = np.linalg.norm(h[0:3]) / b.area + abs(h[3]) * b.disk_radius / b.polar
    return sigma, tau


def test_pulled_pair_fails_at_normal_strength():
    """Pure tension: the bond breaks (mode 1) when T/A reaches the normal strength (Eq. 3 with M_b = 0).

    Analytic: T = k_n (L - L0) (integral of Eq. 1) and failure at T = sigma_n A. Tolerance 1 % (the
    issue); the quasi-static drive makes the overshoot at most RATE = 5e-5 of sigma_n A.
    """
    sim = _pair()
    b = sim.bond
    F_c = SIGMA_N * b.area
    u = RATE * F_c / (b.kn * sim.dt)
    h, prev, steps = _drive(sim, velocity1=(u, 0.0, 0.0))
    assert sim.c.events[-1][2:] == (0, 1, 1), sim.c.events
    assert prev[7] < F_c <= h[7]
    assert h[7] == pytest.approx(F_c, rel=1e-2)
    # the tension is Eq. 1 integrated over the prescribed stretch
    stretch = sim.p.x[1, 0] - sim.p.x[0, 0] - 1.0
    assert h[7] == pytest.approx(b.kn * stretch, rel=1e-9)
    assert steps == pytest.approx(1.0 / RATE, abs=2)
    # no shear, twist or bending built up
    assert np.abs(h[0:7]).max() < 1e-9 * F_c
    assert sim.p.bond_count() == 0


@pytest.mark.parametrize("preload", [0.0, 0.5, -0.5])
def test_sheared_pair_fails_at_mohr_coulomb_strength(preload):
    """Shear (after an optional normal preload of +-0.5 sigma_n A): breaks (mode 2) at tau_c of Eq. 5.

    The element is first pulled (or pushed) quasi-statically to T = preload sigma_n A, then moved
    sideways with rotations held at zero. Reference: tau_max = |F_s|/A (Eq. 4, M_t = 0) reaches
    tau_c = mu sigma_max + sigma_s (Eq. 5), with sigma_max computed from the recorded T and M_b at
    failure exactly as Eq. 3. Tolerance 1 % (the issue); the drive overshoots by <= 5e-5 tau_c. The
    shear force also equals k_s times the sideways displacement (Eq. 1) to 1e-3: the contact plane
    turns by dy/L ~ 4e-4 rad, which changes the projected displacement by O(angle^2) only.
    """
    sim = _pair()
    b = sim.bond
    if preload:
        target = preload * SIGMA_N * b.area
        nsteps = 2000
        u = target / b.kn / (nsteps * sim.dt)
        h, _, _ = _drive(sim, velocity1=(u, 0.0, 0.0), nsteps=nsteps, stop_on_break=False)
        assert not sim.c.events
        assert h[7] == pytest.approx(target, rel=1e-6)
    tau_c0 = MU * preload * SIGMA_N + SIGMA_S
    u = RATE * tau_c0 * b.area / (b.ks * sim.dt)
    y0 = sim.p.x[1, 1]
    h, prev, steps = _drive(sim, velocity1=(0.0, u, 0.0))
    assert sim.c.events[-1][2:] == (0, 1, 2), sim.c.events
    sigma, tau = _stresses(h, b)
    sigma_prev, tau_prev = _stresses(prev, b)
    tau_c = MU * sigma + SIGMA_S            # Eq. 5 with the recorded sigma_max at failure
    assert sigma < SIGMA_N                  # it did not fail in tension
    assert tau >= tau_c and tau_prev < MU * sigma_prev + SIGMA_S
    assert tau == pytest.approx(tau_c, rel=1e-2)
    assert np.linalg.norm(h[0:3]) == pytest.approx(tau_c * b.area, rel=1e-2)
    assert sigma == pytest.approx(preload * SIGMA_N, abs=2e-3 * SIGMA_N)
    dy = sim.p.x[1, 1] - y0
    assert np.linalg.norm(h[0:3]) == pytest.approx(b.ks * dy, rel=1e-3)
    assert abs(h[3]) < 1e-9 * tau_c * b.area and np.linalg.norm(h[4:7]) < 1e-9 * tau_c * b.area


def test_bent_pair_fails_when_eq3_says_so():
    """Pure bending: rotating the elements in opposite senses about z breaks the bond (mode 1) at the
    first step where Eq. 3, sigma_max = |M_b| R / I, reaches the normal strength.

    Equal and opposite angular velocities +-Omega/2 leave the contact point still (no shear) and give
    dM_b = k_b Omega dt per step (Eq. 2, k_b = k_n I). The expected breaking step is found by
    repeating that increment in the test; the measured |M_b| at failure must equal sigma_n I / R
    within 1 % (the issue; the drive overshoots by <= 5e-5).
    """
    sim = _pair()
    b = sim.bond
    M_c = SIGMA_N * b.inertia / b.disk_radius
    omega = RATE * M_c / (b.kb * sim.dt)
    h, prev, steps = _drive(sim, w0=(0.0, 0.0, -0.5 * omega), w1=(0.0, 0.0, 0.5 * omega))
    assert sim.c.events[-1][2:] == (0, 1, 1), sim.c.events
    # first step at which Eq. 3 exceeds the strength, accumulating dM_b as the kernel does
    mb, expected = 0.0, 0
    while True:
        expected += 1
        mb += b.kb * omega * sim.dt
        if abs(mb) * b.disk_radius / b.inertia >= SIGMA_N:
            break
    assert steps == expected
    mb_fail = np.linalg.norm(h[4:7])
    assert mb_fail == pytest.approx(M_c, rel=1e-2)
    assert np.linalg.norm(prev[4:7]) < M_c <= mb_fail
    # pure bending: no tension, shear or twist
    assert abs(h[7]) < 1e-9 * SIGMA_N * b.area
    assert np.linalg.norm(h[0:4]) < 1e-9 * SIGMA_N * b.area


# -- the pure kernel -------------------------------------------------------------------------------

def _kernel_params(*, damping=True):
    R = 0.45
    A, I, J = math.pi * R**2, math.pi * R**4 / 4, math.pi * R**4 / 2
    kn, ks = 2.0e8, 7.0e7
    d = (3.0e4, 1.1e4, 2.0e3, 1.5e3) if damping else (0.0, 0.0, 0.0, 0.0)
    return BondLaw(kn, ks, ks / A * J, kn / A * I, A, I, J, R, math.inf, math.inf, 0.3, *d)


def _random_state(rng):
    x = np.array([[0.1, -0.2, 0.3], [0.1 + 0.93, -0.2 + 0.21, 0.3 - 0.17]]) + rng.normal(0, 1e-3, (2, 3))
    v = rng.normal(0, 0.3, (2, 3))
    w = rng.normal(0, 0.5, (2, 3))
    radius = np.array([0.5, 0.47])
    hist = np.concatenate([rng.normal(0, 2e4, 3), [rng.normal(0, 3e3)], rng.normal(0, 4e3, 3), [0.0]])
    return x, v, w, radius, hist


def _mirror(h):
    """History seen from the other end: shear force and bending moment flip, twist and tension do not."""
    m = h.copy()
    m[0:3] *= -1
    m[4:7] *= -1
    return m


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_kernel_newtons_third_law_and_moment_balance(seed):
    """bond_update: end b gets -F and the moments balance: x_a x F + x_b x (-F) + M_a + M_b = 0.

    Conservation of linear and angular momentum of the isolated pair (Newton's third law, and the
    force acting at the contact point between the centres, Fig. 1). Checked through bond_forces so
    the assembly into per-particle arrays is tested too, about the origin with the pair ~1 m from
    it. Tolerance 1e-9 relative to |x| |F| + |M| (roundoff is ~1e-15).
    """
    rng = np.random.default_rng(seed)
    x, v, w, radius, hist = _random_state(rng)
    params = _kernel_params()
    L0 = 0.95
    gid = np.array([0, 1], dtype=np.int64)
    bond_j = np.full((2, MAX_BONDS), -1, dtype=np.int64)
    bond_gid = np.full((2, MAX_BONDS), -1, dtype=np.int64)
    bond_mate = np.full((2, MAX_BONDS), -1, dtype=np.int64)
    bond_L0 = np.zeros((2, MAX_BONDS))
    bond_hist = np.zeros((2, MAX_BONDS, BOND_HIST))
    bond_j[0, 0], bond_j[1, 2] = 1, 0
    bond_gid[0, 0], bond_gid[1, 2] = 1, 0
    bond_mate[0, 0], bond_mate[1, 2] = 2, 0
    bond_L0[0, 0] = bond_L0[1, 2] = L0
    bond_hist[0, 0] = bond_hist[1, 2] = hist
    force, torque = np.zeros((2, 3)), np.zeros((2, 3))
    events = np.zeros((4, 4), dtype=np.int64)
    nb = bond_forces(2, gid, x, v, w, radius, bond_j, bond_mate, bond_gid, bond_L0, bond_hist, params, 1e-4,
                     force, torque, events, 4)
    assert nb == 0
    F = force[0]
    assert np.linalg.norm(F) > 1e3 and np.linalg.norm(torque[0]) > 1e2  # a non-trivial state
    np.testing.assert_array_equal(force[1], -force[0])
    total_moment = np.cross(x[0], force[0]) + np.cross(x[1], force[1]) + torque[0] + torque[1]
    scale = np.linalg.norm(x, axis=1).max() * np.linalg.norm(F) + np.abs(torque).max()
    assert np.linalg.norm(total_moment) <= 1e-9 * scale
    # only the lower-gid copy advances in the step; sync_mate_history makes both copies agree
    assert not np.array_equal(bond_hist[0, 0], bond_hist[1, 2])
    sync_mate_history(2, gid, bond_j, bond_mate, bond_hist)
    np.testing.assert_array_equal(bond_hist[0, 0], bond_hist[1, 2])
    # and the same through the bare kernel
    f, ma, mb = np.zeros(3), np.zeros(3), np.zeros(3)
    h = hist.copy()
    assert bond_update(0, 1, x, v, w, radius, L0, h, params, 1e-4, f, ma, mb) == 0
    np.testing.assert_array_equal(f, F)
    m = np.cross(x[0], f) + np.cross(x[1], -f) + ma + mb
    assert np.linalg.norm(m) <= 1e-9 * (np.linalg.norm(x, axis=1).max() * np.linalg.norm(f) + np.abs(ma).max())


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_kernel_canonical_orientation_mirrors(seed):
    """Swapping which end is the lower gid mirrors the result (frame independence of Eqs. 1-5).

    With a <-> b and the history given in the mirrored orientation (shear force and bending moment
    negated, twist and tension unchanged), the force on the new a equals the old force on b, the
    moments swap, and the updated history is the mirror of the original one. The arithmetic differs
    only in operand order, so the tolerance is roundoff: 1e-12 relative to the largest magnitude.
    """
    rng = np.random.default_rng(100 + seed)
    x, v, w, radius, hist = _random_state(rng)
    params = _kernel_params()
    L0, dt = 0.95, 1e-4
    f, ma, mb = np.zeros(3), np.zeros(3), np.zeros(3)
    h = hist.copy()
    assert bond_update(0, 1, x, v, w, radius, L0, h, params, dt, f, ma, mb) == 0
    f2, ma2, mb2 = np.zeros(3), np.zeros(3), np.zeros(3)
    h2 = _mirror(hist)
    assert bond_update(1, 0, x, v, w, radius, L0, h2, params, dt, f2, ma2, mb2) == 0
    fs = np.abs(f).max()
    ms = max(np.abs(ma).max(), np.abs(mb).max())
    np.testing.assert_allclose(f2, -f, rtol=0, atol=1e-12 * fs)
    np.testing.assert_allclose(ma2, mb, rtol=0, atol=1e-12 * ms)
    np.testing.assert_allclose(mb2, ma, rtol=0, atol=1e-12 * ms)
    np.testing.assert_allclose(h2, _mirror(h), rtol=0, atol=1e-12 * np.abs(h).max())


def test_bond_forces_independent_of_local_order():
    """The canonical orientation makes bond_forces bit-identical whatever the local index order.

    The same two physical elements (same gids) stored in either local order must get exactly the same
    forces, torques and history: this is what lets two ranks agree to the last bit on a shared bond.
    """
    rng = np.random.default_rng(7)
    x, v, w, radius, hist = _random_state(rng)
    params = _kernel_params()
    out = []
    for order in ([0, 1], [1, 0]):
        o = np.array(order)
        gid = np.array([3, 8], dtype=np.int64)[o]
        i_low = int(np.argmin(gid))
        bond_j = np.full((2, MAX_BONDS), -1, dtype=np.int64)
        bond_gid = np.full((2, MAX_BONDS), -1, dtype=np.int64)
        bond_mate = np.full((2, MAX_BONDS), -1, dtype=np.int64)
        bond_L0 = np.zeros((2, MAX_BONDS))
        bond_hist = np.zeros((2, MAX_BONDS, BOND_HIST))
        for i in range(2):
            bond_j[i, 0], bond_gid[i, 0], bond_mate[i, 0], bond_L0[i, 0] = 1 - i, gid[1 - i], 0, 0.95
            bond_hist[i, 0] = hist
        force, torque = np.zeros((2, 3)), np.zeros((2, 3))
        events = np.zeros((4, 4), dtype=np.int64)
        bond_forces(2, gid, x[o].copy(), v[o].copy(), w[o].copy(), radius[o].copy(), bond_j, bond_mate,
                    bond_gid, bond_L0, bond_hist, params, 1e-4, force, torque, events, 4)
        back = np.argsort(o)  # rows in physical order
        out.append((force[back], torque[back], bond_hist[i_low, 0].copy()))
    for a, b in zip(out[0], out[1]):
        np.testing.assert_array_equal(a, b)


# -- Eqs. 6-7 --------------------------------------------------------------------------------------

def test_eq6_bond_strength_hand_values():
    """Eq. 6 by hand: exp(-1/4.78) = 0.8112289, 1.77 - 1.81 * 0.8112289 = 0.3016757, so with
    sigma_f = 0.5 MPa and L/D = 1, sigma_b = 0.5e6 / 0.3016757 = 1.657409 MPa; for L/D = 2,
    exp(-2/4.78) = 0.6580923, denominator 0.5788529, sigma_b = 0.863777 MPa. Tolerance 1e-6 relative
    (the hand values carry 7 digits)."""
    assert eq6_bond_strength(flexural_strength=0.5e6, thickness=1.0, element_diameter=1.0) == \
        pytest.approx(1.657409e6, rel=1e-6)
    assert eq6_bond_strength(flexural_strength=0.5e6, thickness=1.0, element_diameter=1.0) == \
        pytest.approx(0.5e6 / (1.77 - 1.81 * math.exp(-1.0 / 4.78)), rel=1e-14)
    assert eq6_bond_strength(flexural_strength=0.5e6, thickness=2.0, element_diameter=1.0) == \
        pytest.approx(0.863777e6, rel=1e-6)
    # only the ratio L/D matters
    assert eq6_bond_strength(flexural_strength=0.5e6, thickness=0.4, element_diameter=0.2) == \
        pytest.approx(0.863777e6, rel=1e-6)


def test_eq7_bond_friction_hand_values():
    """Eq. 7 by hand: sigma_c = 2.0 MPa, sigma_f = 0.5 MPa: mu = 0.23 * 4 - 0.5 = 0.42;
    sigma_c/sigma_f = 3: mu = 0.69 - 0.5 = 0.19. Exact to roundoff (1e-12)."""
    assert eq7_bond_friction(compressive_strength=2.0e6, flexural_strength=0.5e6) == pytest.approx(0.42, rel=1e-12)
    assert eq7_bond_friction(compressive_strength=1.5e6, flexural_strength=0.5e6) == pytest.approx(0.19, rel=1e-12)


def test_job_strengths_come_from_eqs_6_and_7():
    """A job with ice.flexural_strength and ice.compressive_strength (and no explicit bond strengths)
    gets sigma_n = sigma_s = Eq. 6 and mu = Eq. 7 (same hand values as above, 1e-6)."""
    job = parse_job({"ice": {"length": 3.0, "width": 2.0, "youngs_modulus": 1e9, "flexural_strength": 0.5e6,
                             "compressive_strength": 2.0e6}})
    b = bond_params_from_job(job, n_layers=1, spacing=1.0)
    assert b.normal_strength == pytest.approx(1.657409e6, rel=1e-6)
    assert b.shear_strength == pytest.approx(1.657409e6, rel=1e-6)
    assert b.friction == pytest.approx(0.42, rel=1e-12)
