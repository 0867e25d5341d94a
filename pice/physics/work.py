"""The modelled work of each element, for the load balance by work (``[parallel] balance_by = "work"``,
parallel/domain.py).

The step's cost is not where the elements are once the ice breaks: at the hull of the reference
scene the rank holding the broken ice spends 3 ms a step on contacts and 1 ms on the hull against
0.2 and 0.25 ms for the other (docs/performance.md, "Load balance by work"). Each element weighs

    ELEMENT + CONTACT x (its ice contacts, counted at the end that computes them)
            + HULL x (1 if it touched a hull in the last step),

in tenths of an element's own cost (bonds, integration, water), whole numbers so that the cuts do
not depend on the order in which the ranks sum them. The weights are costs per unit measured on the
reference scene's 200 s checkpoint (docs/performance.md). The counts come from the state alone (the
positions, the bonds, the hull contact history), so a run restarted from a checkpoint moves its cuts
as the run that went on did.
"""

from __future__ import annotations

import numpy as np

from ..kernels.pair_list import build_pair_list

ELEMENT = 10   # an element's bonds, integration, water and halo: 0.16 us a step
CONTACT = 26   # an ice-ice contact and its share of the candidates: 0.42 us
HULL = 210     # an element touching a hull: the triangle tests of the elements near it, 3.4 us


def element_work(p) -> np.ndarray:
    """(nlocal,) float64 whole numbers: the modelled work of each owned element of ``p`` (module docstring)."""
    start, _ = build_pair_list(p.nlocal, p.n, p.gid, p.x, p.radius, p.bond_j, 0.0)  # the pairs in contact
    work = ELEMENT + CONTACT * np.diff(start).astype(np.float64)
    if p.hull_hist is not None and p.hull_hist.size:
        work += HULL * (p.hull_hist[:p.nlocal] != 0.0).any(axis=(1, 2))
    return work
