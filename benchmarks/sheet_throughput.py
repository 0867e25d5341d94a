"""Particle-steps per second of the 92,000-element level-ice sheet on one rank.

The sheet of Zhu & Ji (2022), Table 4: 200 m x 400 m, 1 m elements, one layer, floating in a
1 m/s current; a few hundred bonds are broken at random before timing so the contact search has
work to do. Times ``--steps`` steps after a warm-up (JIT compile and caches).

    python benchmarks/sheet_throughput.py [--steps 1000] [--broken 300] [--length 400 --width 200]
"""

from __future__ import annotations

import argparse
import time

import numpy as np


def build(length: float, width: float):
    from pice.scenes.reference import zhu_ji_sheet_job
    from pice.simulation import Simulation

    return Simulation(zhu_ji_sheet_job(length=length, width=width, source="benchmark"))


def break_random_bonds(sim, count: int, seed: int = 1) -> int:
    """Break ``count`` random intact bonds (both copies), as cracks would."""
    p = sim.p
    rng = np.random.default_rng(seed)
    i_idx, s_idx = np.nonzero((p.bond_gid >= 0) & (p.bond_gid > p.gid[:, None]))
    pick = rng.choice(len(i_idx), size=min(count, len(i_idx)), replace=False)
    for i, s in zip(i_idx[pick], s_idx[pick]):
        j, m = p.bond_j[i, s], p.bond_mate[i, s]
        p.bond_j[i, s] = p.bond_gid[i, s] = -1
        p.bond_j[j, m] = p.bond_gid[j, m] = -1
    return len(pick)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=1000)
    ap.add_argument("--warmup", type=int, default=20)
    ap.add_argument("--broken", type=int, default=300)
    ap.add_argument("--length", type=float, default=400.0)
    ap.add_argument("--width", type=float, default=200.0)
    args = ap.parse_args()
    t0 = time.perf_counter()
    sim = build(args.length, args.width)
    setup = time.perf_counter() - t0
    nb = break_random_bonds(sim, args.broken)
    sim.compute_forces()
    sim.advance(args.warmup)
    t0 = time.perf_counter()
    sim.advance(args.steps)
    elapsed = time.perf_counter() - t0
    n = sim.p.n
    rate = n * args.steps / elapsed
    print(f"elements            {n}")
    print(f"intact bonds        {sim.p.bond_count()} ({nb} broken at random before timing)")
    print(f"set-up              {setup:.1f} s (incl. JIT compile on a cold cache)")
    print(f"steps timed         {args.steps} in {elapsed:.2f} s")
    print(f"particle-steps/s    {rate:.3e}  (LAMMPS BPM reference on this machine: ~1.0e6 per core)")


if __name__ == "__main__":
    main()
