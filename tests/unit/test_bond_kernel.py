"""The parallel-bond kernel's invariants and the bond strengths of Eqs. 6-7 by hand.

Reference: Zhu & Ji (2022), ../shared/seeds/000_d6dfa5ea71378166.txt, section 2.1-2.2 (the equations
are listed in tests/physics/test_bond_failure.py, which checks the failure of single bonds):
Newton's third law and the balance of moments, frame independence (the canonical orientation),
independence of the local storage order, Eq. 6 (sigma_b from sigma_f and L/D) and Eq. 7 (mu).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from pice.job import parse_job
from pice.kernels.bonds import bond_forces, sync_leaving_history, sync_mate_history
from pice.kernels.bonds import MOHR_COULOMB, ZHU_JI_EQ5
from pice.physics.bond import BondLaw
from pice.physics.bond_calibration import bond_params_from_job, eq6_bond_strength, eq7_bond_friction
from pice.state import BOND_HIST, MAX_BONDS

pytestmark = pytest.mark.nojit  # each test runs in a second with NUMBA_DISABLE_JIT=1


def _kernel_params(*, damping=True):
    R = 0.45
    A, I, J = math.pi * R**2, math.pi * R**4 / 4, math.pi * R**4 / 2
    kn, ks = 2.0e8, 7.0e7
    d = (3.0e4, 1.1e4, 2.0e3, 1.5e3) if damping else (0.0, 0.0, 0.0, 0.0)
    return BondLaw(kn=kn, ks=ks, kt=ks / A * J, kb=kn / A * I, area=A, inertia=I, polar=J, bend_fiber=R,
                   twist_fiber=R, normal_strength=math.inf, shear_strength=math.inf, compressive_strength=math.inf,
                   friction=0.3, shear_law=MOHR_COULOMB, cn=d[0], cs=d[1], ct=d[2], cb=d[3])


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


def _pair_forces(gid, x, v, w, radius, hist, *, L0=0.95, dt=1e-4):
    """bond_forces on two owned elements (rows 0 and 1, gids ``gid``) bonded in slot 0, both copies of
    the history set to ``hist``: (force, torque, the lower-gid end's history after the step)."""
    bond_j = np.full((2, MAX_BONDS), -1, dtype=np.int64)
    bond_gid = np.full((2, MAX_BONDS), -1, dtype=np.int64)
    bond_mate = np.full((2, MAX_BONDS), -1, dtype=np.int64)
    bond_L0 = np.zeros((2, MAX_BONDS))
    bond_hist = np.zeros((2, MAX_BONDS, BOND_HIST))
    for i in range(2):
        bond_j[i, 0], bond_gid[i, 0], bond_mate[i, 0], bond_L0[i, 0] = 1 - i, gid[1 - i], 0, L0
        bond_hist[i, 0] = hist
    force, torque = np.zeros((2, 3)), np.zeros((2, 3))
    events = np.zeros((4, 3), dtype=np.int64)
    assert bond_forces(2, np.asarray(gid, np.int64), x, v, w, radius, bond_j, bond_mate, bond_gid, bond_L0,
                       bond_hist, _kernel_params(), dt, force, torque, events, events[:, :2].copy()) == (0, 0)
    return force, torque, bond_hist[int(np.argmin(gid)), 0].copy()


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_kernel_newtons_third_law_and_moment_balance(seed):
    """bond_forces: end b gets -F and the moments balance: x_a x F + x_b x (-F) + M_a + M_b = 0.

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
    events = np.zeros((4, 3), dtype=np.int64)
    nb = bond_forces(2, gid, x, v, w, radius, bond_j, bond_mate, bond_gid, bond_L0, bond_hist, params, 1e-4,
                     force, torque, events, events[:, :2].copy())
    assert nb == (0, 0)
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


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_kernel_canonical_orientation_mirrors(seed):
    """Swapping which end is the lower gid mirrors the result (frame independence of Eqs. 1-5).

    With the gids of the two elements swapped (so the canonical end a becomes the other element) and
    the history given in the mirrored orientation (shear force and bending moment negated, twist and
    tension unchanged), each element gets the same force and moment as before, and the updated
    history is the mirror of the original one. The arithmetic differs only in operand order, so the
    tolerance is roundoff: 1e-12 relative to the largest magnitude.
    """
    rng = np.random.default_rng(100 + seed)
    x, v, w, radius, hist = _random_state(rng)
    f, m, h = _pair_forces([0, 1], x, v, w, radius, hist)
    f2, m2, h2 = _pair_forces([1, 0], x, v, w, radius, _mirror(hist))
    np.testing.assert_allclose(f2, f, rtol=0, atol=1e-12 * np.abs(f).max())
    np.testing.assert_allclose(m2, m, rtol=0, atol=1e-12 * np.abs(m).max())
    np.testing.assert_allclose(h2, _mirror(h), rtol=0, atol=1e-12 * np.abs(h).max())


def test_bond_forces_independent_of_local_order():
    """The canonical orientation makes bond_forces bit-identical whatever the local index order.

    The same two physical elements (same gids) stored in either local order must get exactly the same
    forces, torques and history: this is what lets two ranks agree to the last bit on a shared bond.
    """
    rng = np.random.default_rng(7)
    x, v, w, radius, hist = _random_state(rng)
    out = []
    for order in ([0, 1], [1, 0]):
        o = np.array(order)
        force, torque, h = _pair_forces(np.array([3, 8])[o], x[o].copy(), v[o].copy(), w[o].copy(),
                                        radius[o].copy(), hist)
        back = np.argsort(o)  # rows in physical order
        out.append((force[back], torque[back], h))
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
    """A job with the paper's springs (bond.normal_stiffness), ice.flexural_strength and
    ice.compressive_strength (and no explicit bond strengths) gets sigma_n = sigma_s = Eq. 6 and
    mu = Eq. 7 (same hand values as above, 1e-6)."""
    job = parse_job({"ice": {"length": 3.0, "width": 2.0, "flexural_strength": 0.5e6, "compressive_strength": 2.0e6},
                     "bond": {"normal_stiffness": 1.72e7}})
    b = bond_params_from_job(job, n_layers=1, spacing=1.0)
    assert b.calibration == "springs"
    assert b.normal_strength == pytest.approx(1.657409e6, rel=1e-6)
    assert b.shear_strength == pytest.approx(1.657409e6, rel=1e-6)
    assert b.friction == pytest.approx(0.42, rel=1e-12)


def test_plate_calibrated_strength_is_the_flexural_strength_over_one_minus_nu():
    """From E (one layer): sigma_n = sigma_f / (1 - nu), the bond stress of a beam bent along a bond
    at the beam's fibre stress sigma_f (physics/bond_calibration.py); mu still from Eq. 7."""
    job = parse_job({"ice": {"length": 3.0, "width": 2.0, "youngs_modulus": 1e9, "poissons_ratio": 0.3,
                             "flexural_strength": 0.5e6, "compressive_strength": 2.0e6}})
    b = bond_params_from_job(job, n_layers=1, spacing=1.0)
    assert b.calibration == "plate"
    assert b.normal_strength == pytest.approx(0.5e6 / 0.7, rel=1e-12)
    assert b.friction == pytest.approx(0.42, rel=1e-12)


@pytest.mark.parametrize("shear_law", [MOHR_COULOMB, ZHU_JI_EQ5])
def test_squared_criteria_decide_as_the_stated_ones(shear_law):
    """failure_mode_squared (the kernel's) against failure_mode (the criteria as the module states
    them, with the square roots) on 20,000 random stress states around the strengths, compressive
    cap included. Reference: the two are the same inequalities; states within 1e-9 of a threshold,
    where round-off may decide either way, are skipped (none in practice)."""
    from pice.kernels.bonds import failure_mode, failure_mode_squared

    rng = np.random.default_rng(11)
    law = _kernel_params()._replace(normal_strength=0.8e6, shear_strength=0.7e6, compressive_strength=2.0e6,
                                    shear_law=shear_law)
    A, cb, ct = law.area, law.bend_fiber / law.inertia, law.twist_fiber / law.polar
    agree = 0
    modes = set()
    for _ in range(20_000):
        sigma_n = rng.normal(0.0, 1.0e6)
        mb, fs, mt = (abs(rng.normal(0.0, s)) for s in (0.6e6 / cb, 0.5e6 * A, 0.3e6 / ct))
        sigma_b, tau = mb * cb, fs / A + mt * ct
        margins = [law.normal_strength - sigma_n - sigma_b, law.compressive_strength - sigma_b + sigma_n]
        if min(abs(m) for m in margins) < 1e-9 * law.normal_strength:
            continue
        expected = failure_mode(sigma_n, sigma_b, tau, law)
        assert failure_mode_squared(sigma_n, mb * mb, fs * fs, mt, law) == expected
        modes.add(expected)
        agree += 1
    assert agree > 19_000 and modes == {0, 1, 2, 3}  # every outcome was exercised


def test_turned_history_keeps_its_length_and_leaves_the_plane():
    """_turned: the history loses its component along n and keeps its length, to round-off, on both of
    its branches (the series for a small turn, the exact square root for a large one)."""
    from pice.kernels.bonds import _turned

    rng = np.random.default_rng(5)
    for tilt in (1e-6, 1e-4, 1e-3, 0.3):  # x = tilt^2 either side of the 1e-6 switch
        for _ in range(200):
            n = rng.normal(size=3)
            n /= np.linalg.norm(n)
            t = np.cross(n, rng.normal(size=3))
            a = (t / np.linalg.norm(t) + tilt * n) * rng.uniform(1e2, 1e6)
            b = np.array(_turned(*a, *n))
            assert abs(b @ n) <= 1e-12 * np.linalg.norm(a)
            assert np.linalg.norm(b) == pytest.approx(np.linalg.norm(a), rel=4e-16 * 8)


def test_a_migration_syncs_the_bonds_of_the_leaving_rows_from_their_lower_gid_ends():
    """parallel/halo.py syncs before a migration only the bonds of the rows that leave
    (sync_leaving_history): both ends of each such bond get the lower-gid end's history, the one the
    bond kernel advances while both ends are owned; bonds between rows that stay, and bonds to ghosts,
    are left as they are. Owned rows 0-3 (gids 10, 5, 7, 20) in a chain 0-1-2-3, row 4 a ghost bonded
    to row 3; row 1 leaves."""
    gid = np.array([10, 5, 7, 20, 3])
    nlocal = 4
    bond_j = np.full((5, MAX_BONDS), -1, np.int32)
    bond_mate = np.full((5, MAX_BONDS), -1, np.int32)
    links = [(0, 0, 1, 0), (1, 1, 2, 0), (2, 1, 3, 0), (3, 1, 4, 0)]  # (i, slot, j, slot)
    for i, si, j, sj in links:
        bond_j[i, si], bond_j[j, sj] = j, i
        bond_mate[i, si], bond_mate[j, sj] = sj, si
    rng = np.random.default_rng(0)
    hist = rng.normal(size=(5, MAX_BONDS, BOND_HIST))
    before = hist.copy()
    sync_leaving_history(np.array([1]), nlocal, gid, bond_j, bond_mate, hist)
    # 0-1: gid 10 against 5, so row 1's copy goes to row 0; 1-2: gid 5 against 7, row 1's to row 2
    assert np.array_equal(hist[0, 0], before[1, 0]) and np.array_equal(hist[1, 0], before[1, 0])
    assert np.array_equal(hist[2, 0], before[1, 1]) and np.array_equal(hist[1, 1], before[1, 1])
    # 2-3 stay (both owned, neither leaves) and 3-4 (a ghost): untouched
    for row, slot in ((2, 1), (3, 0), (3, 1), (4, 0)):
        assert np.array_equal(hist[row, slot], before[row, slot])
    # what the full sync would give on the leaving row's bonds
    full = before.copy()
    sync_mate_history(nlocal, gid, bond_j, bond_mate, full)
    for row, slot in ((0, 0), (1, 0), (1, 1), (2, 0)):
        assert np.array_equal(hist[row, slot], full[row, slot])
