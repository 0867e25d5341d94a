"""Single parallel bonds: failure in tension, shear and bending (the kernel's invariants and Eqs. 6-7
by hand: tests/unit/test_bond_kernel.py).

Reference: Zhu & Ji (2022), ../shared/seeds/000_d6dfa5ea71378166.txt, section 2.1-2.2:

    Eq. 1   dF_n = k_n A dU_n,  dF_s = -k_s A dU_s
    Eq. 2   dM_t = -k_s J dtheta_n,  dM_b = -k_n I dtheta_s
    Eq. 3   sigma_max = -F_n/A + |M_b| R / I      (here tension T = -F_n > 0)
    Eq. 4   tau_max = |F_s|/A + |M_t| R / J
    Eq. 5   tau_c = mu sigma_max + sigma_s        (as printed: bond.shear_strength_law = "zhu_ji_2022_eq5")
            tau_c = sigma_s - mu T / A            (Mohr-Coulomb, compression raises it: the default;
                                                   Potyondy & Cundall 2004, Itasca's parallel bond)
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

import numpy as np
import pytest

from pice.job import parse_job
from pice.simulation import Simulation

pytestmark = pytest.mark.nojit  # each test runs in a few seconds with NUMBA_DISABLE_JIT=1

SIGMA_N = 1.5e6      # normal strength [Pa]
SIGMA_S = 1.2e6      # shear (cohesive) strength sigma_s of Eq. 5 [Pa]
MU = 0.3             # inner friction of Eq. 5
K = 1.72e9           # normal and shear spring [N/m]; stiff so the shear test's geometric
                     # stretch (k dy^2 / 2 L) stays ~1e-3 of the strengths
RATE = 5e-5          # change of the breaking quantity per step, as a fraction of its critical value
HUGE_INERTIA = 1e30  # [kg m^2]: angular velocity stays exactly as prescribed


def _pair(shear_stiffness=K, normal_stiffness=K, shear_law="mohr_coulomb", compressive_strength=None):
    job = parse_job({
        "run": {"duration": 1.0}, "gravity": 0.0,
        "ice": {"length": 2.0, "width": 1.0, "density": 920.0},
        "bond": {"normal_stiffness": normal_stiffness, "shear_stiffness": shear_stiffness,
                 "normal_strength": SIGMA_N, "shear_strength": SIGMA_S, "friction": MU,
                 "shear_strength_law": shear_law,
                 **({"compressive_strength": compressive_strength} if compressive_strength else {})},
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
    sigma = h[7] / b.area + np.linalg.norm(h[4:7]) * b.bend_fiber / b.inertia
    tau = np.linalg.norm(h[0:3]) / b.area + abs(h[3]) * b.twist_fiber / b.polar
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


def _shear_strength(law, sigma_n, sigma_max):
    """tau_c [Pa]: Mohr-Coulomb on the normal stress T/A (compression raises it), or Eq. 5 as printed."""
    return SIGMA_S - MU * sigma_n if law == "mohr_coulomb" else MU * sigma_max + SIGMA_S


def test_pushed_pair_fails_at_the_compressive_cap():
    """Pure compression with bond.compressive_strength = 0.8 sigma_n (the optional cap): the bond
    breaks (mode 3) when -T/A reaches it; without the cap the same push never breaks it. Tolerance 1 %
    as above (the drive overshoots by <= 5e-5 of the cap)."""
    cap = 0.8 * SIGMA_N
    sim = _pair(compressive_strength=cap)
    b = sim.bond
    F_c = cap * b.area
    u = -RATE * F_c / (b.kn * sim.dt)
    h, prev, steps = _drive(sim, velocity1=(u, 0.0, 0.0))
    assert sim.c.events[-1][2:] == (0, 1, 3), sim.c.events
    assert -prev[7] < F_c <= -h[7]
    assert -h[7] == pytest.approx(F_c, rel=1e-2)
    free = _pair()
    _drive(free, velocity1=(u, 0.0, 0.0), nsteps=int(1.5 * steps), stop_on_break=False)
    assert not free.c.events and free.p.bond_count() == 1


@pytest.mark.parametrize("law", ["mohr_coulomb", "zhu_ji_2022_eq5"])
@pytest.mark.parametrize("preload", [0.0, 0.5, -0.5])
def test_sheared_pair_fails_at_its_shear_strength(preload, law):
    """Shear (after an optional normal preload of +-0.5 sigma_n A): breaks (mode 2) at tau_c.

    The element is first pulled (or pushed) quasi-statically to T = preload sigma_n A, then moved
    sideways with rotations held at zero. Reference: tau_max = |F_s|/A (Eq. 4, M_t = 0) reaches
    tau_c: with Mohr-Coulomb (the default) tau_c = sigma_s - mu T/A, so compression (preload < 0)
    raises the strength and tension lowers it; with the paper's Eq. 5 as printed, tau_c = mu sigma_max
    + sigma_s, the opposite. sigma_max and T/A are computed from the recorded T and M_b at failure
    exactly as Eq. 3. Tolerance 1 % (the issue); the drive overshoots by <= 5e-5 tau_c. The shear
    force also equals k_s times the sideways displacement (Eq. 1) to 1e-3: the contact plane turns by
    dy/L ~ 4e-4 rad, which changes the projected displacement by O(angle^2) only.
    """
    sim = _pair(shear_law=law)
    b = sim.bond
    if preload:
        target = preload * SIGMA_N * b.area
        nsteps = 2000
        u = target / b.kn / (nsteps * sim.dt)
        h, _, _ = _drive(sim, velocity1=(u, 0.0, 0.0), nsteps=nsteps, stop_on_break=False)
        assert not sim.c.events
        assert h[7] == pytest.approx(target, rel=1e-6)
    tau_c0 = _shear_strength(law, preload * SIGMA_N, preload * SIGMA_N)
    u = RATE * tau_c0 * b.area / (b.ks * sim.dt)
    y0 = sim.p.x[1, 1]
    h, prev, steps = _drive(sim, velocity1=(0.0, u, 0.0))
    assert sim.c.events[-1][2:] == (0, 1, 2), sim.c.events
    sigma, tau = _stresses(h, b)
    sigma_prev, tau_prev = _stresses(prev, b)
    sigma_n, sigma_n_prev = h[7] / b.area, prev[7] / b.area
    tau_c = _shear_strength(law, sigma_n, sigma)   # with the recorded stresses at failure
    assert sigma < SIGMA_N                  # it did not fail in tension
    assert tau >= tau_c and tau_prev < _shear_strength(law, sigma_n_prev, sigma_prev)
    assert tau == pytest.approx(tau_c, rel=1e-2)
    assert np.linalg.norm(h[0:3]) == pytest.approx(tau_c * b.area, rel=1e-2)
    assert sigma == pytest.approx(preload * SIGMA_N, abs=2e-3 * SIGMA_N)
    if preload < 0:  # compression: Mohr-Coulomb raises the strength, the printed Eq. 5 lowers it
        assert (tau_c > SIGMA_S) == (law == "mohr_coulomb")
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
    M_c = SIGMA_N * b.inertia / b.bend_fiber
    omega = RATE * M_c / (b.kb * sim.dt)
    h, prev, steps = _drive(sim, w0=(0.0, 0.0, -0.5 * omega), w1=(0.0, 0.0, 0.5 * omega))
    assert sim.c.events[-1][2:] == (0, 1, 1), sim.c.events
    # first step at which Eq. 3 exceeds the strength, accumulating dM_b as the kernel does
    mb, expected = 0.0, 0
    while True:
        expected += 1
        mb += b.kb * omega * sim.dt
        if abs(mb) * b.bend_fiber / b.inertia >= SIGMA_N:
            break
    assert steps == expected
    mb_fail = np.linalg.norm(h[4:7])
    assert mb_fail == pytest.approx(M_c, rel=1e-2)
    assert np.linalg.norm(prev[4:7]) < M_c <= mb_fail
    # pure bending: no tension, shear or twist
    assert abs(h[7]) < 1e-9 * SIGMA_N * b.area
    assert np.linalg.norm(h[0:4]) < 1e-9 * SIGMA_N * b.area
