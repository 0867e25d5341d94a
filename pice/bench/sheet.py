"""The benchmark sheet: the 92,000-element level ice of Zhu & Ji (2022), Table 4, with no platform
(pice bench, benchmarks/sheet_throughput.py).

200 m x 400 m of 1 m elements in one layer, floating in a 1 m/s current (scenes/reference.py); a
few hundred bonds are broken at random before timing so that the contact search has work to do.
The bonds are chosen over the whole sheet by gid, so the same ones break on any rank count.
"""

from __future__ import annotations

import numpy as np

SHEET_LENGTH = 400.0  # [m] along the current
SHEET_WIDTH = 200.0   # [m]
BROKEN = 300          # bonds broken at random before timing
SEED = 1


def reference_sheet(*, length: float = SHEET_LENGTH, width: float = SHEET_WIDTH, broken: int = BROKEN,
                    seed: int = SEED, comm=None, source: str = "benchmark"):
    """(Simulation, bonds broken) of the sheet on the ranks of ``comm`` (collective), its forces
    computed after the breaks. ``length`` and ``width`` [m]; ``broken`` random bonds, ``seed``."""
    from ..scenes.reference import zhu_ji_sheet_job
    from ..simulation import Simulation

    sim = Simulation(zhu_ji_sheet_job(length=length, width=width, source=source), comm=comm)
    count = break_random_bonds(sim, broken, seed)
    sim.compute_forces()
    return sim, count


def break_random_bonds(sim, count: int, seed: int = SEED) -> int:
    """Break ``count`` random intact bonds, both copies, on every rank that holds them, as cracks
    would (collective). The draw is over the whole sheet's bonds in (gid, slot) order, the same on
    any rank count; on one rank it is the draw benchmarks/sheet_throughput.py always made."""
    p, comm = sim.p, sim.comm
    n = p.nlocal
    gid, partner = p.gid[:n], p.bond_gid[:n]
    rows, slots = np.nonzero((partner >= 0) & (partner > gid[:, None]))
    mine = np.stack([gid[rows], slots, partner[rows, slots]], axis=1).astype(np.int64)
    every = comm.gather(mine)
    pairs = None
    if every is not None:  # rank 0
        bonds = np.concatenate(every)
        bonds = bonds[np.lexsort((bonds[:, 1], bonds[:, 0]))]
        rng = np.random.default_rng(seed)
        pick = rng.choice(len(bonds), size=min(count, len(bonds)), replace=False)
        pairs = bonds[pick][:, [0, 2]]
    pairs = comm.bcast(pairs)
    keys = _pair_key(pairs[:, 0], pairs[:, 1])
    m = p.n  # owned and ghost rows: every copy of a broken bond goes
    a = np.broadcast_to(p.gid[:m, None], p.bond_gid[:m].shape)
    b = p.bond_gid[:m]
    hit = (b >= 0) & np.isin(_pair_key(a, b), keys)
    p.bond_j[:m][hit] = -1
    p.bond_gid[:m][hit] = -1
    p.topology += 1
    return len(pairs)


def _pair_key(a, b) -> np.ndarray:
    """One int64 per unordered pair of gids: lower * 2^32 + higher."""
    a, b = np.asarray(a, dtype=np.int64), np.asarray(b, dtype=np.int64)
    return np.minimum(a, b) * (1 << 32) + np.maximum(a, b)
