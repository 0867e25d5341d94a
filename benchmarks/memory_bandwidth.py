"""This machine's memory bandwidth and arithmetic throughput, and the bond kernel's distance to both
(docs/performance.md, "The bond kernel against the machine's limits").

    python benchmarks/memory_bandwidth.py [--mib 512] [--repeat 7]

Prints, on one core:
- STREAM-like copy (a = b) and triad (a = b + s c) bandwidth [GB/s] over arrays of --mib MiB each,
  compiled with numba (bytes moved: copy 2 x 8 B, triad 3 x 8 B per element; write-allocate
  traffic not counted, as STREAM does not);
- the core's scalar floating-point throughput [Gflop/s]: eight independent chains of fused
  multiply-adds (2 flops each), compiled with the bond kernel's flags and checked to be scalar code
  (the bond kernel is scalar: numba does not vectorise its gathers and branches; AVX2 would offer 4
  times this on paper, AVX-512 8);
- the bond kernel (kernels.bonds.bond_forces) on the 92k benchmark sheet (pice/bench/sheet.py):
  time per call and per bond, the bytes it must move per call (the arrays it reads and writes, each
  touched cache line once) and the achieved bandwidth against the triad's; the floating-point
  operations per bond (OPS_PER_BOND, counted in the source) and the achieved rate against the
  core's;
- the same kernel on a sheet small enough to stay in the core's L2 cache, called over and over:
  the kernel's own arithmetic limit as compiled, with memory out of the way.

The fastest of --repeat blocks is reported: on a shared machine the fastest is the least disturbed.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from numba import njit

from pice.kernels import JIT_FMA

# Floating-point operations of one intact bond (kernels/bonds.py, counted in the source: each +, -, *
# and / once, a fused multiply-add as the two it replaces; the sqrt counted apart): the geometry
# (length, normal, lever arms) 17, the relative velocity at the contact point 33, its normal and
# shear parts and the spin's 25, turning the two history vectors 52, the increments and the tension
# 19, the failure criteria on squared magnitudes 23, the forces and moments on both ends 49, adding
# them to the two elements 15. Of these 3 are divisions (1/L and two in turning the history), and
# the bond takes one square root. The constants of the law (1/A, c/I, c_t/J) are loop-invariant.
OPS_PER_BOND = 233
DIVISIONS_PER_BOND = 3


@njit(cache=True)
def _copy(a, b):
    for i in range(a.shape[0]):
        a[i] = b[i]


@njit(cache=True)
def _triad(a, b, c, s):
    for i in range(a.shape[0]):
        a[i] = b[i] + s * c[i]


@njit(**dict(JIT_FMA, cache=False))  # not cached: its assembly is inspected
def _fma_scalar(n, a, b):
    """8 independent chains x = x a + b, n rounds: 16 n flops, scalar."""
    x0, x1, x2, x3, x4, x5, x6, x7 = 1.0, 1.1, 1.2, 1.3, 1.4, 1.5, 1.6, 1.7
    for _ in range(n):
        x0 = x0 * a + b
        x1 = x1 * a + b
        x2 = x2 * a + b
        x3 = x3 * a + b
        x4 = x4 * a + b
        x5 = x5 * a + b
        x6 = x6 * a + b
        x7 = x7 * a + b
    return x0 + x1 + x2 + x3 + x4 + x5 + x6 + x7


def flops(repeat: int) -> dict:
    """The core's scalar fused multiply-add throughput [Gflop/s], and whether the code was scalar."""
    n = 20_000_000
    a, b = 0.999999, 1e-7
    _fma_scalar(10, a, b)
    asm = next(iter(_fma_scalar.inspect_asm().values()))
    scalar = "vfmadd" in asm and "pd" not in "".join(line.split()[0] for line in asm.splitlines()
                                                     if "vfmadd" in line and line.split())
    t_scalar = fastest(lambda: _fma_scalar(n, a, b), repeat)
    return {"scalar_Gflops": 16 * n / t_scalar / 1e9, "scalar_is_scalar_fma": scalar}


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


def bond_kernel(repeat: int, length: float | None = None, width: float | None = None,
                calls: int = 1) -> dict:
    """The bond kernel on the benchmark sheet (its default size, or ``length`` x ``width`` [m]),
    ``calls`` calls a timing."""
    from pice.bench.sheet import reference_sheet
    from pice.kernels.bonds import bond_forces

    size = {} if length is None else {"length": length, "width": width}
    sim, _ = reference_sheet(**size)
    p, law, dt = sim.p, sim.bond_term.law, sim.dt
    events = np.zeros((1000, 3), np.int64)
    removed = np.zeros((1000, 2), np.int64)
    hist = p.bond_hist.copy()

    def call():
        for _ in range(calls):
            bond_forces(p.nlocal, p.gid, p.x, p.v, p.w, p.radius, p.bond_j, p.bond_mate, p.bond_gid,
                        p.bond_L0, hist, law, dt, p.force, p.torque, events, removed)

    call()
    t = fastest(call, repeat) / calls
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
    f = flops(args.repeat)
    kind = "scalar code checked" if f["scalar_is_scalar_fma"] else "NOT checked scalar: the compiler vectorised it"
    print(f"fused multiply-add  {f['scalar_Gflops']:.1f} Gflop/s scalar ({kind})")
    b = bond_kernel(args.repeat)
    print(f"bond kernel         {b['ms_per_call']:.2f} ms a call: {b['bonds']:,} bonds of {b['elements']:,} elements, "
          f"{b['ns_per_bond']:.1f} ns a bond, {b['bonds'] / b['elements']:.2f} bonds an element")
    print(f"  bytes a call      {b['bytes_per_call'] / 1e6:.1f} MB -> {b['GBps']:.2f} GB/s, "
          f"{b['GBps'] / s['triad_GBps']:.0%} of the triad's bandwidth; at the triad's it would take "
          f"{1e3 * b['bytes_per_call'] / (s['triad_GBps'] * 1e9):.2f} ms")
    rate = OPS_PER_BOND / b["ns_per_bond"]
    print(f"  operations        {OPS_PER_BOND} a bond ({DIVISIONS_PER_BOND} divisions, 1 sqrt) -> {rate:.2f} Gflop/s, "
          f"{rate / f['scalar_Gflops']:.0%} of the scalar rate")
    per_element = b["bonds"] / b["elements"]
    print(f"  per element-step  {b['bytes_per_call'] / b['elements']:.0f} B and {OPS_PER_BOND * per_element:.0f} flops "
          f"(intensity {OPS_PER_BOND * b['bonds'] / b['bytes_per_call']:.2f} flop/B)")
    c = bond_kernel(args.repeat, length=24.0, width=24.0, calls=200)
    print(f"in cache            {c['ns_per_bond']:.1f} ns a bond: {c['bonds']:,} bonds of {c['elements']:,} elements "
          f"({c['bytes_per_call'] / 1e6:.2f} MB, inside L2), 200 calls a timing; the 92k sheet's bond costs "
          f"{b['ns_per_bond'] / c['ns_per_bond']:.2f} times this")


if __name__ == "__main__":
    main()
