"""Elements crushed through at a structure, and the rule that removes them.

An element pressed into a wall or a hull yields plastically (kernels/contact_law.py): its plastic
penetration grows in the contact's history. Once that penetration reaches the element's diameter,
the whole element has gone through the crushing zone at the face: it is crushed through. The rule
(docs/crushing.md):
the element is removed from the simulation, standing for ice pulverised at the face and extruded as
fines that carry no load; its bonds break, logged with the mode CRUSHED; the ice behind it then
meets the structure. Elements crushing against other ice are not removed (their plastic overlap
stays in the contact's history).
"""

from __future__ import annotations

import numpy as np

from ..kernels.bonds import CRUSHED


def structure_crush_depth(p) -> np.ndarray:
    """(nlocal,) the largest plastic penetration [m] of each owned element into a wall or a hull."""
    n = p.nlocal
    depth = np.zeros(n)
    if p.wall_hist.shape[1]:
        depth = np.maximum(depth, p.wall_hist[:n, :, 3].max(axis=1))
    if p.hull_hist.shape[1]:
        depth = np.maximum(depth, p.hull_hist[:n, :, 3].max(axis=1))
    return depth


def crush_depth(p) -> np.ndarray:
    """(nlocal,) the largest plastic penetration [m] of each owned element in any of its contacts:
    walls, hulls and other ice (the snapshots' ``crush_depth``; 0 for an element that never crushed)."""
    n = p.nlocal
    return np.maximum(structure_crush_depth(p), p.contact_hist[:n, :, 3].max(axis=1, initial=0.0))


def crushed_through(p) -> np.ndarray:
    """Indices of the owned elements whose plastic penetration into a wall or a hull reaches their diameter.

    (With one diameter, and not one radius, the staggered rows of a close-packed front overlap in
    contact with a plane face: each row's element is still crushing when the next row's arrives.)"""
    return np.nonzero(structure_crush_depth(p) >= 2.0 * p.radius[:p.nlocal])[0]


def remove_elements(p, gone: np.ndarray, *, step: int, time: float) -> list[tuple]:
    """Break every bond of the owned elements to an element of ``gone`` (gids, from every rank) and drop
    the owned rows of ``gone``; ghosts are dropped too (the caller rebuilds the halo).

    Returns the broken-bond events (step, time, gid_a, gid_b, CRUSHED), each bond logged once: on the
    rank that owns its lower-gid end, as bond breaks are counted everywhere.
    """
    n = p.nlocal
    gone = np.asarray(gone, dtype=np.int64)
    partner = p.bond_gid[:n]
    mine = np.isin(p.gid[:n], gone)
    hit = (partner >= 0) & (np.isin(partner, gone) | mine[:, None])
    rows, slots = np.nonzero(hit)
    events = [(step, time, int(p.gid[i]), int(partner[i, s]), CRUSHED) for i, s in zip(rows, slots)
              if p.gid[i] < partner[i, s]]
    p.bond_gid[:n][hit] = -1
    keep = np.nonzero(~mine)[0]
    p.replace_rows([p.rows(keep)], len(keep))
    return events
