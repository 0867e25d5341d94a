"""The exact stability limit by Bloch waves (pice/physics/lattice_modes.py) against two references.

1. Analytic: with dashpots proportional to the springs (C = alpha K) every mode of the lattice is a
   damped oscillator with c = alpha omega^2, and the step's limit is that of the stiffest mode,
   omega^2 h^2 / 4 + alpha omega^2 h / 2 = 1 (the module docstring's one-mode condition), solved for h.
2. Direct: a periodic patch of the lattice (8 x 4 cells, 64 elements, 384 degrees of freedom) is
   assembled link by link in real space, independently of the Bloch matrices, and stepped with the
   integrator's scheme (w' = w - h M^-1 (K x + C w), x' = x + h w') from a random state. At 0.98 of
   the limit every mode stays bounded; at 1.02 the unstable mode grows. The patch's wave vectors
   are a subset of the Bloch grid, so its limit is at least the Bloch one: it must not blow up
   below it. Above, growth is checked after 4000 steps: a mode with |lambda| >= 1.001 grows by
   e^4 = 55 at least; the bounded runs stay within 10x their start (the energy of a stable damped
   Verlet mode stays within 1 / (1 - (omega h / 2)^2) of its start, < 10 for omega h <= 1.9).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from pice.physics.lattice_modes import cell_links, exact_limit, link_stiffness_matrix, unit_cell

M, INERTIA, D = 796.7, 0.4 * 796.7 * 0.25, 1.0            # the reference ice's 1 m cell element
SPRINGS = (8.248e8, 4.124e8, 5.287e6, 6.873e7)               # bond k_n, contact k_t, bond twist, bend
DASHPOTS = (4.08e5, 3.6e4, 1.0e2, 1.0e3)                     # contact normal (zeta 0.36), bond dashpots


def test_proportional_damping_matches_the_one_mode_formula():
    alpha = 1.0e-4  # [s]: C = alpha K (zeta 0.2 at the highest mode)
    springs = SPRINGS
    limit, undamped = exact_limit(mass=M, inertia=INERTIA, d=D, n_layers=1, springs=springs,
                                  dashpots=tuple(alpha * k for k in springs))
    omega = 2.0 / undamped
    c = alpha * omega ** 2
    # omega^2 h^2 / 4 + c h / 2 = 1  ->  h = 2 / omega (sqrt(1 + zeta^2) - zeta), zeta = c / (2 omega)
    zeta = c / (2.0 * omega)
    expected = 2.0 / omega * (math.sqrt(1.0 + zeta ** 2) - zeta)
    assert limit == pytest.approx(expected, rel=2e-6)  # the bisection's 2^-20 of the bracket
    assert limit < 0.9 * undamped                      # the case is not trivially undamped


def _patch(nx=8, ny=4):
    """K and C (mass-normalised, 6 N x 6 N) of a periodic nx x ny-cell patch, assembled in real space."""
    basis, cell = unit_cell(d=D, n_layers=1)
    pos = np.array([b + np.array([i * cell[0], j * cell[1], 0.0])
                    for i in range(nx) for j in range(ny) for b in basis])
    box = np.array([nx * cell[0], ny * cell[1]])
    n = len(pos)
    K, C = np.zeros((6 * n, 6 * n)), np.zeros((6 * n, 6 * n))
    for a in range(n):
        for b in range(a + 1, n):
            r = pos[b] - pos[a]
            r[:2] -= box * np.round(r[:2] / box)
            L = np.linalg.norm(r)
            if L > D * (1 + 1e-6):
                continue
            idx = np.r_[6 * a:6 * a + 6, 6 * b:6 * b + 6]
            K[np.ix_(idx, idx)] += link_stiffness_matrix(r / L, 0.5 * L, 0.5 * L, *SPRINGS)
            C[np.ix_(idx, idx)] += link_stiffness_matrix(r / L, 0.5 * L, 0.5 * L, *DASHPOTS)
    minv = 1.0 / np.tile(np.r_[np.full(3, M), np.full(3, INERTIA)], n)
    return minv[:, None] * K, minv[:, None] * C


def _growth(MK, MC, h, steps=4000):
    rng = np.random.default_rng(7)
    x, w = rng.normal(size=MK.shape[0]) * 1e-3, np.zeros(MK.shape[0])
    start = np.linalg.norm(x)
    for _ in range(steps):
        w = w - h * (MK @ x + MC @ w)
        x = x + h * w
    return np.linalg.norm(x) / start


def test_the_patch_is_stable_below_and_grows_above_the_limit():
    limit, _ = exact_limit(mass=M, inertia=INERTIA, d=D, n_layers=1, springs=SPRINGS, dashpots=DASHPOTS)
    MK, MC = _patch()
    assert _growth(MK, MC, 0.98 * limit) < 10.0
    assert _growth(MK, MC, 1.02 * limit) > 55.0


def test_the_cell_holds_the_lattice_neighbours():
    """Each element of one layer has its 6 in-plane neighbours; of two layers, 9 (6 + 3 across)."""
    for layers, per_element in ((1, 6), (2, 9)):
        basis, cell = unit_cell(d=D, n_layers=layers)
        links = cell_links(basis, cell, D)
        assert len(links) == per_element * len(basis)
