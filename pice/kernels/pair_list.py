"""The contact candidates: a neighbour list with a skin (Verlet list), as mature particle codes keep.

For every owned element i the list holds the unbonded elements j (owned with a higher gid, or
ghosts) whose centres are nearer than r_i + r_j + skin, sorted by gid. The contact kernel then
tests only these pairs, instead of scanning the 27 cells around every element every step. The list
stays valid until some element has moved skin / 2 since it was built (two elements then cannot have
closed the skin between them) or the rows were re-indexed (migration, ghosts rebuilt, elements
removed): ``physics.contact.IceContactTerm`` watches both and rebuilds. A broken bond makes its pair
a candidate: ``insert_pairs`` adds it to the list in place of a rebuild (late in the reference scene
a bond breaks every few steps, and a rebuild of a 46,000-element rank costs some 40 ms).

Sorting each element's candidates by gid makes the order in which contacts add their forces a
function of the state alone, not of the step at which the list was built: a run restarted from a
checkpoint (which builds a fresh list) adds the same numbers in the same order as the run that went on.
"""

import numpy as np
from numba import njit

from . import JIT
from .contacts import _bonded, build_cell_list, cell_neighbourhood


@njit(**JIT)
def _candidates(i, nlocal, gid, x, radius, bond_j, skin, near, nnear, out, m):
    """Write i's candidates among near[:nnear] (the points of its cell neighbourhood) into out[m:],
    unsorted (only counted when out is None); return the new end."""
    for q in range(nnear):
        j = near[q]
        if j == i or (j < nlocal and gid[j] < gid[i]):
            continue  # listed from j's side
        d0 = x[j, 0] - x[i, 0]
        d1 = x[j, 1] - x[i, 1]
        d2 = x[j, 2] - x[i, 2]
        reach = radius[i] + radius[j] + skin
        if d0 * d0 + d1 * d1 + d2 * d2 >= reach * reach or _bonded(bond_j, i, j):
            continue
        if out is not None:
            out[m] = j
        m += 1
    return m


@njit(**JIT)
def build_pair_list(nlocal, ntotal, gid, x, radius, bond_j, skin):
    """(start (nlocal + 1,), partners (m,)) int64: owned i's candidates are partners[start[i]:start[i+1]],
    each element j once per pair (from its lower-gid end when both are owned), in increasing gid.

    skin [m]: the margin beyond contact; the cells are 2 r_max + skin wide.
    """
    rmax = 0.0
    for i in range(ntotal):
        if radius[i] > rmax:
            rmax = radius[i]
    origin, dims, cstart, order, size = build_cell_list(x, ntotal, 2.0 * rmax * 1.0001 + skin)
    start = np.zeros(nlocal + 1, dtype=np.int64)
    near = np.empty(ntotal, dtype=np.int64)
    for i in range(nlocal):  # count, then fill
        nnear = cell_neighbourhood(x[i], origin, dims, cstart, order, size, near)
        start[i + 1] = start[i] + _candidates(i, nlocal, gid, x, radius, bond_j, skin, near, nnear, None, 0)
    partners = np.empty(start[nlocal], dtype=np.int64)
    for i in range(nlocal):
        nnear = cell_neighbourhood(x[i], origin, dims, cstart, order, size, near)
        _candidates(i, nlocal, gid, x, radius, bond_j, skin, near, nnear, partners, start[i])
        for a in range(start[i] + 1, start[i + 1]):  # insertion sort by gid: a few entries
            j = partners[a]
            b = a - 1
            while b >= start[i] and gid[partners[b]] > gid[j]:
                partners[b + 1] = partners[b]
                b -= 1
            partners[b + 1] = j
    return start, partners


@njit(**JIT)
def insert_pairs(start, partners, gid, pairs):
    """(start, partners) of a list with the pairs (row i, partner j) added, each at its place in its
    row's gid order; a pair already listed is not added again. pairs: (k, 2) local indices in the
    list's convention (i owned; the lower-gid end when both are owned), as kernels.bonds.bond_forces
    logs the bonds it removes. The result is the list a fresh build would give, less or plus pairs out
    of contact reach, which the contact kernel skips: the forces are the same bits."""
    nlocal = start.shape[0] - 1
    extra = np.zeros(nlocal + 1, dtype=np.int64)
    keep = np.zeros(pairs.shape[0], dtype=np.bool_)
    for q in range(pairs.shape[0]):
        i, j = pairs[q, 0], pairs[q, 1]
        listed = False
        for a in range(start[i], start[i + 1]):
            if partners[a] == j:
                listed = True
        for r in range(q):  # the same pair twice in pairs
            if keep[r] and pairs[r, 0] == i and pairs[r, 1] == j:
                listed = True
        if not listed:
            keep[q] = True
            extra[i + 1] += 1
    new_start = np.empty(nlocal + 1, dtype=np.int64)
    new_start[0] = 0
    for i in range(nlocal):
        new_start[i + 1] = new_start[i] + (start[i + 1] - start[i]) + extra[i + 1]
    new_partners = np.empty(new_start[nlocal], dtype=np.int64)
    fill = np.empty(nlocal, dtype=np.int64)
    for i in range(nlocal):
        m = new_start[i]
        for a in range(start[i], start[i + 1]):
            new_partners[m] = partners[a]
            m += 1
        fill[i] = m
    for q in range(pairs.shape[0]):
        if keep[q]:
            i, j = pairs[q, 0], pairs[q, 1]
            b = fill[i] - 1  # insertion into the sorted row
            while b >= new_start[i] and gid[new_partners[b]] > gid[j]:
                new_partners[b + 1] = new_partners[b]
                b -= 1
            new_partners[b + 1] = j
            fill[i] += 1
    return new_start, new_partners


@njit(**JIT)
def moved_beyond(ntotal, x, x_ref, limit):
    """True when some element of the first ntotal has moved more than ``limit`` [m] from x_ref
    (or its position is not finite: the list is rebuilt, and the health check reports it)."""
    lim2 = limit * limit
    for i in range(ntotal):
        d0 = x[i, 0] - x_ref[i, 0]
        d1 = x[i, 1] - x_ref[i, 1]
        d2 = x[i, 2] - x_ref[i, 2]
        if not (d0 * d0 + d1 * d1 + d2 * d2 <= lim2):
            return True
    return False
