"""The modelled work of each element for the load balance by work (physics/work.py).

Reference: brute force over all pairs (an element's contacts are the unbonded partners it touches,
counted at the end the contact kernel computes them from: the lower gid when both are owned, the
owned one otherwise), and the claim that the work is a function of the state alone: the same for
every element whatever the order of the rows, in whole numbers (so the ranks' sums are exact).
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from pice.physics.work import CONTACT, ELEMENT, HULL, element_work
from pice.state import MAX_BONDS


def _cloud(order, seed=4, n=300, nlocal=220):
    rng = np.random.default_rng(seed)
    x = rng.uniform(0.0, 7.0, (n, 3))
    x[:, 2] *= 0.2
    radius = rng.uniform(0.3, 0.5, n)
    gid = rng.permutation(5 * n)[:n].astype(np.int64)
    bonded = {(int(gid[i]), int(gid[i + 1])) for i in range(0, n - 1, 3)}  # some pairs bonded
    hull = rng.random(n) < 0.05
    owned, ghosts = order[order < nlocal], order[order >= nlocal]
    rows = np.concatenate([owned, ghosts])
    where = np.empty(n, dtype=np.int64)
    where[rows] = np.arange(n)
    bond_j = np.full((n, MAX_BONDS), -1, dtype=np.int32)
    for a, b in bonded:
        for g, h in ((a, b), (b, a)):
            i, j = where[np.flatnonzero(gid == g)[0]], where[np.flatnonzero(gid == h)[0]]
            bond_j[i, int(np.argmax(bond_j[i] < 0))] = j
    hull_hist = np.zeros((n, 1, 4))
    hull_hist[where[hull], 0, 1] = 2.5
    return SimpleNamespace(gid=gid[rows], x=x[rows], radius=radius[rows], bond_j=bond_j, nlocal=nlocal, n=n,
                           hull_hist=hull_hist)


def test_work_counts_each_contact_at_its_computing_end_and_hull_contacts():
    p = _cloud(np.arange(300))
    expected = np.full(p.nlocal, float(ELEMENT))
    for i in range(p.nlocal):
        for j in range(p.n):
            if j == i or (j < p.nlocal and p.gid[j] < p.gid[i]) or (p.bond_j[i] == j).any():
                continue
            if np.sum((p.x[j] - p.x[i]) ** 2) < (p.radius[i] + p.radius[j]) ** 2:
                expected[i] += CONTACT
        expected[i] += HULL * bool(p.hull_hist[i].any())
    work = element_work(p)
    assert (expected > ELEMENT + CONTACT).sum() > 20 and (expected >= HULL).sum() > 3  # a non-trivial cloud
    np.testing.assert_array_equal(work, expected)


def test_work_is_a_function_of_the_state_not_of_the_row_order():
    a = _cloud(np.arange(300))
    b = _cloud(np.random.default_rng(0).permutation(300))
    wa = dict(zip(a.gid[:a.nlocal].tolist(), element_work(a)))
    wb = dict(zip(b.gid[:b.nlocal].tolist(), element_work(b)))
    assert wa == wb
    assert all(float(w).is_integer() for w in wa.values())
