"""The contact neighbour list (kernels/pair_list.py) and the term that keeps it (physics/contact.py).

References: brute force over all pairs (the list must hold exactly the unbonded pairs within
r_i + r_j + skin, each once, in gid order), and bit-for-bit agreement of the contact forces whether
the list was built now or half a skin of motion ago (the module's claim that the order of the sums
does not depend on when the list was built, which the bit-for-bit restart relies on).
"""

from __future__ import annotations

import numpy as np

from pice.kernels.contacts import contact_forces
from pice.kernels.pair_list import build_pair_list, moved_beyond
from pice.physics.contact import ContactLaw
from pice.state import MAX_BONDS, MAX_CONTACTS


def _cloud(seed=3, n=400, nlocal=300):
    rng = np.random.default_rng(seed)
    x = rng.uniform(0.0, 8.0, (n, 3))
    x[:, 2] *= 0.2
    radius = rng.uniform(0.3, 0.5, n)
    gid = rng.permutation(10 * n)[:n].astype(np.int64)
    bond_j = np.full((n, MAX_BONDS), -1, dtype=np.int32)
    for i in range(nlocal):  # bond a few near pairs (both ends when both are owned)
        d = np.linalg.norm(x - x[i], axis=1)
        d[i] = np.inf
        j = int(np.argmin(d))
        if j < nlocal and (bond_j[i] == j).any():
            continue
        si = int(np.argmax(bond_j[i] < 0))
        bond_j[i, si] = j
        if j < nlocal:
            bond_j[j, int(np.argmax(bond_j[j] < 0))] = i
    return gid, x, radius, bond_j, nlocal


def _brute(gid, x, radius, bond_j, nlocal, skin):
    out = []
    for i in range(nlocal):
        row = []
        for j in range(len(x)):
            if j == i or (j < nlocal and gid[j] < gid[i]) or (bond_j[i] == j).any():
                continue
            if np.sum((x[j] - x[i]) ** 2) < (radius[i] + radius[j] + skin) ** 2:
                row.append(j)
        out.append(sorted(row, key=lambda j: gid[j]))
    return out


def test_list_holds_exactly_the_unbonded_pairs_within_reach_in_gid_order():
    gid, x, radius, bond_j, nlocal = _cloud()
    for skin in (0.0, 0.3):
        start, partners = build_pair_list(nlocal, len(x), gid, x, radius, bond_j, skin)
        expected = _brute(gid, x, radius, bond_j, nlocal, skin)
        assert sum(len(r) for r in expected) > 100  # a non-trivial cloud
        for i in range(nlocal):
            assert list(partners[start[i]:start[i + 1]]) == expected[i]


def test_forces_do_not_depend_on_when_the_list_was_built():
    gid, x, radius, bond_j, nlocal = _cloud(seed=5)
    n = len(x)
    rng = np.random.default_rng(1)
    v, w = rng.normal(0, 0.1, (n, 3)), rng.normal(0, 0.1, (n, 3))
    mass = np.full(n, 300.0)
    law = ContactLaw(kn=1e7, kt=4e6, zeta=0.3, mu=0.3, crushing_pressure=2.5e6)
    skin = 0.3
    old = build_pair_list(nlocal, n, gid, x, radius, bond_j, skin)
    x_new = x + rng.uniform(-1, 1, x.shape) * 0.49 * skin / np.sqrt(3)  # each moves < skin / 2
    assert not moved_beyond(n, x_new, x, 0.5 * skin)
    fresh = build_pair_list(nlocal, n, gid, x_new, radius, bond_j, skin)
    results = []
    for start, partners in (old, fresh):
        force, torque = np.zeros((n, 3)), np.zeros((n, 3))
        cgid = np.full((n, MAX_CONTACTS), -1, dtype=np.int64)
        stamp = np.full((n, MAX_CONTACTS), -10, dtype=np.int64)
        chist = np.zeros((n, MAX_CONTACTS, 4))
        out = contact_forces(nlocal, gid, x_new, v, w, radius, mass, np.zeros(n), np.full(n, 0.5), start, partners,
                             cgid, stamp, chist, law, 1e-4, 1, force, torque)
        results.append((out, force, torque, chist))
    assert results[0][0][0] > 20  # contacts
    assert results[0][0] == results[1][0]
    for a, b in zip(results[0][1:], results[1][1:]):
        np.testing.assert_array_equal(a, b)


def test_moved_beyond_catches_a_non_finite_position():
    x = np.zeros((3, 3))
    y = x.copy()
    y[1, 0] = np.nan
    assert moved_beyond(3, y, x, 0.1)
    assert not moved_beyond(3, x, x, 0.1)


def test_a_broken_bond_is_inserted_as_a_fresh_build_would_list_it():
    """insert_pairs after bonds are removed gives exactly the list a fresh build gives (reference:
    build_pair_list, itself checked against brute force above), for pairs with an owned and a ghost
    end, twice-logged pairs, and a pair already listed."""
    from pice.kernels.pair_list import insert_pairs

    gid, x, radius, bond_j, nlocal = _cloud(seed=7)
    skin = 0.3
    start, partners = build_pair_list(nlocal, len(x), gid, x, radius, bond_j, skin)
    pairs = []
    for i in range(nlocal):  # remove every third bond, logged in the list's convention
        for s in range(MAX_BONDS):
            j = bond_j[i, s]
            if j < 0 or (j < nlocal and gid[j] < gid[i]) or (i + s) % 3:
                continue
            bond_j[i, s] = -1
            if j < nlocal:
                bond_j[j, int(np.flatnonzero(bond_j[j] == i)[0])] = -1
            pairs.append((i, j))
    assert len(pairs) > 30 and any(j >= nlocal for _, j in pairs)
    pairs += pairs[:3]  # logged twice
    listed = (0, int(partners[start[0]]))  # already a candidate
    logged = np.array(pairs + [listed], dtype=np.int64)
    new_start, new_partners = insert_pairs(start, partners, gid, logged)
    fresh_start, fresh_partners = build_pair_list(nlocal, len(x), gid, x, radius, bond_j, skin)
    np.testing.assert_array_equal(new_start, fresh_start)
    np.testing.assert_array_equal(new_partners, fresh_partners)


def test_the_contact_term_inserts_logged_removals_and_rebuilds_for_unlogged_ones():
    """IceContactTerm: a bond removal logged in p.unbonded is inserted (no rebuild), one that is not
    (p.topology raised alone) rebuilds the list; both give the fresh build's list."""
    from types import SimpleNamespace

    from pice.physics.contact import IceContactTerm

    gid, x, radius, bond_j, nlocal = _cloud(seed=9)
    p = SimpleNamespace(gid=gid, x=x, radius=radius, bond_j=bond_j, nlocal=nlocal, n=len(x), topology=0,
                        unbonded=None)
    term = IceContactTerm(ContactLaw(kn=1e7, kt=4e6, zeta=0.3, mu=0.3, crushing_pressure=2.5e6), skin=0.3)
    term._list(p)
    assert (term.builds, term.inserts, p.unbonded) == (1, 0, [])

    def remove(i):
        s = int(np.flatnonzero(bond_j[i] >= 0)[0])
        j = int(bond_j[i, s])
        bond_j[i, s] = -1
        if j < nlocal:
            bond_j[j, int(np.flatnonzero(bond_j[j] == i)[0])] = -1
        p.topology += 1
        return (i, j) if j >= nlocal or gid[i] < gid[j] else (j, i)

    rows = [i for i in range(nlocal) if (bond_j[i] >= 0).any()]
    for i in rows[:4]:
        p.unbonded.append(np.array([remove(i)], dtype=np.int64))
    start, partners = term._list(p)
    assert (term.builds, term.inserts, p.unbonded) == (1, 1, [])
    fresh = build_pair_list(nlocal, len(x), gid, x, radius, bond_j, 0.3)
    np.testing.assert_array_equal(partners, fresh[1])
    remove(rows[5])  # not logged: a rebuild
    start, partners = term._list(p)
    assert (term.builds, term.inserts) == (2, 1)
    np.testing.assert_array_equal(partners, build_pair_list(nlocal, len(x), gid, x, radius, bond_j, 0.3)[1])
