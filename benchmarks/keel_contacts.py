"""Cost of a ship run through a settled keel (issue 15), one rank: the step, the block-block contact
kernel within it, and the overlap geometry per contacting pair.

    python benchmarks/keel_contacts.py [JOB] [--steps 100] [--repeat 3]

JOB (default jobs/gong_2017_keel_w17_3.toml) is a ship run whose keel file exists (`pice keel JOB`).
Prints the blocks, the candidate pairs of the neighbour list, the pairs whose bounding spheres and
boxes meet, the pairs that overlap; then, --repeat times, the wall time of a step, of the block-block
contacts in it (Floes.pair_records), and of the overlap geometry alone
(kernels/polyhedron_contact.contact_scalars over the overlapping pairs) per pair. When the blocks are
boxes, each repeat times the box kernel (kernels/box_contact.py) too, interleaved with the general one,
and their ratios are printed. The medians of the repeats are printed last: compare a change with the
commit before it, run after run, on a quiet machine.
"""

from __future__ import annotations

import argparse
import pathlib
import statistics
import time

import numpy as np
from numba import njit

from pice.job import load_job
from pice.kernels.box_contact import box_buffer, box_contact_scalars
from pice.kernels.floe_contact import _boxes_meet, floe_boxes
from pice.kernels.floe_motion import floe_rotations
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
def box_geometry(pairs, x, rot, half, reps):
    """``overlap_geometry`` by the box kernel (kernels/box_contact.py)."""
    buf, ca, cb = box_buffer(), np.empty((8, 3)), np.empty((8, 3))
    ka, kb = np.empty(8, np.int64), np.empty(8, np.int64)
    rel, rel_t = np.empty((3, 3)), np.empty((3, 3))
    total = 0.0
    for _ in range(reps):
        for k in range(pairs.shape[0]):
            i, j = pairs[k, 0], pairs[k, 1]
            total += box_contact_scalars(x[i], rot[i], half[i], x[j], rot[j], half[j], buf, ca, cb, ka, kb, rel,
                                         rel_t)[0]
    return total


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
    half = f.box_half
    pts, counts = f.world()
    box = floe_boxes(len(f.mass), pts, counts)
    cand, near, pairs = overlapping_pairs(f.near[1], f.near[2], f.x, f.bound, box, pts, counts)
    print(f"{args.job}: {len(f.mass):,} blocks{' (boxes)' if len(half) else ''}; pair list {cand:,} candidates, "
          f"{near:,} with spheres and boxes meeting, {len(pairs):,} overlapping")
    overlap_geometry(pairs, pts, counts, 1)
    if len(half):
        box_geometry(pairs, f.x, floe_rotations(f.q), half, 1)
    paths = ["general", "box"] if len(half) else ["general"]
    times = {(what, path): [] for what in ("step", "kernel", "geometry") for path in paths}
    omega = f.omega
    for r in range(args.repeat):
        for path in paths:  # interleaved: the two kernels see the same machine
            f.box_half = half if path == "box" else np.empty((0, 3))
            t0 = time.perf_counter()
            sim.advance(args.steps)
            times["step", path].append((time.perf_counter() - t0) / args.steps)
            pts, counts = f.world()
            kept = [a.copy() for a in (f.cgid, f.stamp, f.hist)]  # the contacts' history, given back after
            t0 = time.perf_counter()
            for _ in range(10):
                f.pair_records(0, len(f.mass), pts, counts, omega, sim.dt)
            times["kernel", path].append((time.perf_counter() - t0) / 10)
            f.cgid[:], f.stamp[:], f.hist[:] = kept
            t0 = time.perf_counter()
            if path == "box":
                box_geometry(pairs, f.x, floe_rotations(f.q), half, 10)
            else:
                overlap_geometry(pairs, pts, counts, 10)
            times["geometry", path].append((time.perf_counter() - t0) / 10 / max(len(pairs), 1))
            print(f"  run {r + 1}, {path} kernel: step {times['step', path][-1] * 1e3:.2f} ms, block-block contacts "
                  f"{times['kernel', path][-1] * 1e3:.2f} ms, overlap geometry {times['geometry', path][-1] * 1e6:.3f} "
                  "us a pair")
    f.box_half = half
    med = {key: statistics.median(v) for key, v in times.items()}
    for path in paths:
        print(f"median of {args.repeat}, {path} kernel: step {med['step', path] * 1e3:.2f} ms, block-block contacts "
              f"{med['kernel', path] * 1e3:.2f} ms ({med['kernel', path] / med['step', path]:.0%} of the step), "
              f"overlap geometry {med['geometry', path] * 1e6:.3f} us a pair "
              f"({med['geometry', path] * len(pairs) / med['kernel', path]:.0%} of the contacts' time)")
    if len(paths) == 2:
        print("general over box: " + ", ".join(f"{what} {med[what, 'general'] / med[what, 'box']:.2f}"
                                              for what in ("step", "kernel", "geometry")))


if __name__ == "__main__":
    main()
