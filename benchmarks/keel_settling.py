"""Cost of a rubble keel's settling step (issue 15; one rank): the blocks of a small keel of
jobs/gong_2017_keel_w17_3.toml (its width, length and depth scaled down) released under the cover
and let rise for --warm seconds, then timed over --steps steps.

    python benchmarks/keel_settling.py [--width 8.66] [--length 2.0] [--depth 2.5] [--warm 6] [--steps 300]

Prints the blocks, the step [s], the wall time a step, the block contacts at the end and the wall
time per contact (the step's whole cost over its contacts: an upper bound on the contact kernel's).
Compare commits by running it from each commit's tree, one after the other, on a quiet machine.
"""

from __future__ import annotations

import argparse
import pathlib
import time

import numpy as np

from pice.job import load_job
from pice.parallel.comm import SerialComm
from pice.physics.floe_system import FloeSystem
from pice.physics.keel import (blocks_as_floes, keel_law, keel_step, keel_walls, keel_water, release_blocks,
                               settle_steps)

JOB = pathlib.Path(__file__).resolve().parents[1] / "jobs" / "gong_2017_keel_w17_3.toml"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--width", type=float, default=8.66, help="[m] at the cover (default: a 2.5 m deep triangle)")
    ap.add_argument("--length", type=float, default=2.0, help="[m]")
    ap.add_argument("--depth", type=float, default=2.5, help="[m]")
    ap.add_argument("--warm", type=float, default=6.0, help="[s] of settling before the timed steps")
    ap.add_argument("--steps", type=int, default=300)
    args = ap.parse_args()
    job = load_job(JOB)
    keel = job.keel.model_copy(update=dict(width=args.width, length=args.length, depth=args.depth))
    job = job.model_copy(update=dict(keel=keel))
    rects, x, q = release_blocks(keel)
    floes = blocks_as_floes(keel, rects, x, q, keel_law(keel), keel_water(job))
    keel_walls(floes, keel, generation=True)
    system = FloeSystem(floes, SerialComm(), [])
    dt = keel_step(keel, floes)
    system.compute_forces(np.zeros((0, 13)), 0.0, dt)
    t = settle_steps(system, int(round(args.warm / dt)), 0.0, dt)
    t0 = time.perf_counter()
    settle_steps(system, args.steps, t, dt)
    wall = (time.perf_counter() - t0) / args.steps
    contacts = system.contacts
    print(f"blocks              {len(floes.mass)} (keel {args.width:g} m x {args.length:g} m x {args.depth:g} m)")
    print(f"step                {dt:.3g} s; {args.steps} steps after {args.warm:g} s of settling")
    print(f"wall time           {1e3 * wall:.3f} ms a step; {contacts} block contacts at the end: "
          f"{1e6 * wall / max(contacts, 1):.2f} us a contact (the whole step)")


if __name__ == "__main__":
    main()
