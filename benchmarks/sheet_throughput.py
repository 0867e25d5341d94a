"""Particle-steps per second of the 92,000-element level-ice sheet on one rank.

The sheet of Zhu & Ji (2022), Table 4: 200 m x 400 m, 1 m elements, one layer, floating in a
1 m/s current; a few hundred bonds are broken at random before timing so the contact search has
work to do (the sheet is pice/bench/sheet.py's, which `pice bench` measures on any rank count). Times
``--steps`` steps after a warm-up (JIT compile and caches).

    python benchmarks/sheet_throughput.py [--steps 1000] [--broken 300] [--length 400 --width 200]
"""

from __future__ import annotations

import argparse
import time

from pice.bench.sheet import BROKEN, SHEET_LENGTH, SHEET_WIDTH, reference_sheet


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=1000)
    ap.add_argument("--warmup", type=int, default=20)
    ap.add_argument("--broken", type=int, default=BROKEN)
    ap.add_argument("--length", type=float, default=SHEET_LENGTH)
    ap.add_argument("--width", type=float, default=SHEET_WIDTH)
    args = ap.parse_args()
    t0 = time.perf_counter()
    sim, nb = reference_sheet(length=args.length, width=args.width, broken=args.broken)  # pice/bench/sheet.py
    setup = time.perf_counter() - t0
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
