"""Cost of a ship run through a settled keel (issue 15), one rank: the step, the block-block contact
kernel within it, and the overlap geometry per contacting pair.

    python benchmarks/keel_contacts.py [JOB] [--steps 100] [--repeat 3]

JOB (default jobs/gong_2017_keel_w17_3.toml) is a ship run whose keel file exists (`pice keel JOB`).
Prints the blocks, the candidate pairs of the neighbour list, the pairs whose bounding spheres and
boxes meet, the pairs that overlap; then, --repeat times, the wall time of a step, of the block-block
contacts in it (Floes.pair_records), and of the overlap geometry alone
(kernels/polyhedron_contact.contact_scalars over the overlapping pairs) per pair. The medians of the
repeats are printed last: compare a change with the commit before it, run after run, on a quiet
machine.
"""

from __future__ import annotations

import argparse
import pathlib
import statistics
import time

import numpy as np
from numba import njit

from pice.job import load_job
from pice.kernels.floe_contact import _boxes_meet, floe_boxes
from pice.kernels.polyhedra import face_planes
from pice.kernels.polyhedron_contact import contact_buffer, contact_scalars
from pice.simulation import Simulation

ROOT = pathlib.Path(__file__).resolve().parents[1]


@njit(cache=True)
def overlapping_pairs(start, partners, x, bound, box, pts, counts):
    """(candidates, pairs whose spheres and boxes meet, (k, 2) the pairs that overlap) of a pair list
    built for every floe (one rank: start has n + 1 entries)."""
    planes = face_planes(pts, counts)
    buf = contact_buffer(pts[0], planes[0], pts[0], planes[0])
    near, out = 0, np.empty((partners.shape[0], 2), np.int64)
    m = 0
    for i in range(start.shape[0] - 1):
        for q in range(start[i], start[i + 1]):
            j = partners[q]
            d0, d1, d2 = x[j, 0] - x[i, 0], x[j, 1] - x[i, 1], x[j, 2] - x[i, 2]
            reach = bound[i] + bound[j]
            if d0 * d0 + d1 * d1 + d2 * d2 < reach * reach and _boxes_meet(box, i, j):
                near += 1
                if contact_scalars(pts[i], counts[i], planes[i], pts[j], counts[j], planes[j], buf)[0] > 0.0:
                    out[m, 0], out[m, 1] = i, j
                    m += 1
    return partners.shape[0], near, out[:m]


@njit(cache=True)
def overlap_geometry(pairs, pts, counts, reps):
    """The overlap volumes [m^3] of ``pairs``, ``reps`` times over (the timed loop; the sum returned)."""
    planes = face_planes(pts, counts)
    buf = contact_buffer(pts[0], planes[0], pts[0], planes[0])
    total = 0.0
    for _ in range(reps):
        for k in range(pairs.shape[0]):
            i, j = pairs[k, 0], pairs[k, 1]
            total += contact_scalars(pts[i], counts[i], planes[i], pts[j], counts[j], planes[j], buf)[0]
    return total


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("job", nargs="?", default=str(ROOT / "jobs" / "gong_2017_keel_w17_3.toml"))
    ap.add_argument("--steps", type=int, default=100)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    job = load_job(args.job)
    sim = Simulation(job, base_dir=pathlib.Path(args.job).parent)
    sim.advance(5)  # compile, and the first pair list
    f = sim.floes.f
    pts, counts = f.world()
    box = floe_boxes(len(f.mass), pts, counts)
    cand, near, pairs = overlapping_pairs(f.near[1], f.near[2], f.x, f.bound, box, pts, counts)
    print(f"{args.job}: {len(f.mass):,} blocks; pair list {cand:,} candidates, {near:,} with spheres and boxes "
          f"meeting, {len(pairs):,} overlapping")
    overlap_geometry(pairs, pts, counts, 1)
    steps, kernel, geometry = [], [], []
    omega = f.omega
    for r in range(args.repeat):
        t0 = time.perf_counter()
        sim.advance(args.steps)
        steps.append((time.perf_counter() - t0) / args.steps)
        pts, counts = f.world()
        kept = [a.copy() for a in (f.cgid, f.stamp, f.hist)]  # the contacts' history, given back after
        t0 = time.perf_counter()
        for _ in range(10):
            f.pair_records(0, len(f.mass), pts, counts, omega, sim.dt)
        kernel.append((time.perf_counter() - t0) / 10)
        f.cgid[:], f.stamp[:], f.hist[:] = kept
        t0 = time.perf_counter()
        overlap_geometry(pairs, pts, counts, 10)
        geometry.append((time.perf_counter() - t0) / 10 / max(len(pairs), 1))
        print(f"  run {r + 1}: step {steps[-1] * 1e3:.2f} ms, block-block contacts {kernel[-1] * 1e3:.2f} ms, "
              f"overlap geometry {geometry[-1] * 1e6:.3f} us a pair")
    med = statistics.median
    print(f"median of {args.repeat}: step {med(steps) * 1e3:.2f} ms, block-block contacts {med(kernel) * 1e3:.2f} ms "
          f"({med(kernel) / med(steps):.0%} of the step), overlap geometry {med(geometry) * 1e6:.3f} us a pair "
          f"({med(geometry) * len(pairs) / med(kernel):.0%} of the contacts' time)")


if __name__ == "__main__":
    main()
