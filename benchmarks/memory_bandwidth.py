"""This machine's memory bandwidth and the bond kernel's distance to it (docs/performance.md, "The
step's cost").

    python benchmarks/memory_bandwidth.py [--mib 512] [--repeat 7]

Prints, on one core:
- STREAM-like copy (a = b) and triad (a = b + s c) bandwidth [GB/s] over arrays of --mib MiB each,
  compiled with numba (bytes moved: copy 2 x 8 B, triad 3 x 8 B per element; write-allocate
  traffic not counted, as STREAM does not);
- the bond kernel (kernels.bonds.bond_forces) on the 92k benchmark sheet (pice/bench/sheet.py):
  time per call and per bond, the bytes it must move per call (the arrays it reads and writes, each
  touched cache line once) and the achieved bandwidth against the triad's.

The fastest of --repeat blocks is reported: on a shared machine the fastest is the least disturbed.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from numba import njit


@njit(cache=True)
def _copy(a, b):
    for i in range(a.shape[0]):
        a[i] = b[i]


@njit(cache=True)
def _triad(a, b, c, s):
    for i in range(a.shape[0]):
        a[i] = b[i] + s * c[i]


def fastest(fn, repeat: int) -> float:
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def stream(mib: int, repeat: int) -> dict:
    n = mib * 1024 * 1024 // 8
    a, b, c = np.zeros(n), np.random.default_rng(0).random(n), np.random.default_rng(1).random(n)
    _copy(a[:10], b[:10])
    _triad(a[:10], b[:10], c[:10], 3.0)
    t_copy = fastest(lambda: _copy(a, b), repeat)
    t_triad = fastest(lambda: _triad(a, b, c, 3.0), repeat)
    return {"copy_GBps": 16 * n / t_copy / 1e9, "triad_GBps": 24 * n / t_triad / 1e9}


def bond_kernel(repeat: int) -> dict:
    from pice.bench.sheet import reference_sheet
    from pice.kernels.bonds import bond_forces

    sim, _ = reference_sheet()
    p, law, dt = sim.p, sim.bond_term.law, sim.dt
    events = np.zeros((1000, 3), np.int64)
    removed = np.zeros((1000, 2), np.int64)
    hist = p.bond_hist.copy()

    def call():
        bond_forces(p.nlocal, p.gid, p.x, p.v, p.w, p.radius, p.bond_j, p.bond_mate, p.bond_gid, p.bond_L0,
                    hist, law, dt, p.force, p.torque, events, removed)

    call()
    t = fastest(call, repeat)
    n = p.nlocal
    bonds = p.bond_count()
    used = np.count_nonzero(p.bond_j[:n] >= 0, axis=1)
    # bytes per call: x, v, w read (72 B) and force, torque read and written (96 B) per element; the
    # element's bond_j row (48 B) and gid; per bond evaluated, its history read and written (128 B)
    # and its rest length (8 B); the partner's x, v, w come from cache (neighbours in the lattice)
    per_element = 72 + 96 + p.bond_j.shape[1] * p.bond_j.itemsize + 8
    nbytes = n * per_element + bonds * (2 * 8 * p.bond_hist.shape[2] + 8)
    return {"elements": n, "bonds": bonds, "slots_used_mean": float(used.mean()), "ms_per_call": 1e3 * t,
            "ns_per_bond": 1e9 * t / bonds, "bytes_per_call": nbytes, "GBps": nbytes / t / 1e9}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mib", type=int, default=512)
    ap.add_argument("--repeat", type=int, default=7)
    args = ap.parse_args()
    s = stream(args.mib, args.repeat)
    print(f"copy                {s['copy_GBps']:.1f} GB/s   ({args.mib} MiB arrays, one core, fastest of {args.repeat})")
    print(f"triad               {s['triad_GBps']:.1f} GB/s")
    b = bond_kernel(args.repeat)
    print(f"bond kernel         {b['ms_per_call']:.2f} ms a call: {b['bonds']:,} bonds of {b['elements']:,} elements, "
          f"{b['ns_per_bond']:.1f} ns a bond")
    print(f"  bytes a call      {b['bytes_per_call'] / 1e6:.1f} MB -> {b['GBps']:.2f} GB/s, "
          f"{b['GBps'] / s['triad_GBps']:.0%} of the triad's bandwidth")


if __name__ == "__main__":
    main()
