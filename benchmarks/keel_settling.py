"""Cost of a rubble keel's settling step (issue 15; one rank): the blocks of a small keel of
jobs/gong_2017_keel_w17_3.toml (its width, length and depth scaled down) released under the cover
and let rise for --warm seconds, then timed over --steps steps.

    python benchmarks/keel_settling.py [--width 8.66] [--length 2.0] [--depth 2.5] [--warm 6] [--steps 300]
    python benchmarks/keel_settling.py --porosity MU [--lock SPEED] [--seed N] [--width ...]

Prints the blocks, the step [s], the wall time a step, the block contacts at the end and the wall
time per contact (the step's whole cost over its contacts: an upper bound on the contact kernel's).
Compare commits by running it from each commit's tree, one after the other, on a quiet machine.

With --porosity MU the keel is generated instead (physics/keel.generate_keel: settled to 5 mm/s
within 60 s, with keel.settle_friction = MU, then trimmed) and its porosity printed: the measure of
docs/ridge_keel.md, "Porosity" (MU 0.3: 0.615, core 0.589; MU 0: 0.387, core 0.327; a few minutes).
--lock SPEED gives keel.lock_speed: the contact's friction returns below that RMS speed.

With --checkpoint FILE (a generation checkpoint of jobs/gong_2017_keel_w17_3.toml, <keel file>.gen.h5)
the pile it holds is trimmed as the generation trims it and its porosity printed: the full-size
figures of docs/ridge_keel.md, "The narrow keel with the staged settling".
"""

from __future__ import annotations

import argparse
import pathlib
import time

import numpy as np

from pice.job import load_job
from pice.parallel.comm import SerialComm
from pice.physics.floe_system import FloeSystem
from pice.physics.keel import (blocks_as_floes, generate_keel, keel_law, keel_step, keel_walls, keel_water,
                               release_blocks, settle_steps)

JOB = pathlib.Path(__file__).resolve().parents[1] / "jobs" / "gong_2017_keel_w17_3.toml"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--width", type=float, default=8.66, help="[m] at the cover (default: a 2.5 m deep triangle)")
    ap.add_argument("--length", type=float, default=2.0, help="[m]")
    ap.add_argument("--depth", type=float, default=2.5, help="[m]")
    ap.add_argument("--warm", type=float, default=6.0, help="[s] of settling before the timed steps")
    ap.add_argument("--steps", type=int, default=300)
    ap.add_argument("--porosity", type=float, metavar="MU", help="generate with this settling friction and print "
                    "the keel's porosity instead of timing")
    ap.add_argument("--lock", type=float, metavar="SPEED", help="[m/s] with --porosity: keel.lock_speed")
    ap.add_argument("--seed", type=int, help="keel.seed (default: the job's)")
    ap.add_argument("--checkpoint", metavar="FILE", help="the porosity of this generation checkpoint of the job's "
                    "full-size keel instead")
    args = ap.parse_args()
    job = load_job(JOB)
    if args.checkpoint:
        checkpoint_porosity(job, args.checkpoint)
        return
    keel = job.keel.model_copy(update=dict(width=args.width, length=args.length, depth=args.depth,
                                           seed=job.keel.seed if args.seed is None else args.seed))
    job = job.model_copy(update=dict(keel=keel))
    if args.porosity is not None:
        keel = keel.model_copy(update=dict(settle_friction=args.porosity, settle_speed=5e-3, settle_time=60.0,
                                           lock_speed=args.lock))
        k = generate_keel(job.model_copy(update=dict(keel=keel)), SerialComm())
        print(f"settle_friction {args.porosity:g}, lock_speed {args.lock}: {k.released} blocks released, {len(k.x)} kept, settled at "
              f"{k.settle_time:.1f} s (RMS {k.rms_speed:.2g} m/s); porosity {k.porosity:.3f}, core {k.core_porosity:.3f}")
        return
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


def checkpoint_porosity(job, path) -> None:
    """Print the trimmed porosity of the pile in the generation checkpoint ``path`` of ``job``'s keel."""
    import h5py

    from pice.scenes.rubble import inside_keel, porosity

    keel = job.keel
    rects = release_blocks(keel)[0]
    with h5py.File(path) as f:
        t, x, q, v = float(f.attrs["time"]), f["x"][()], f["q"][()], f["v"][()]
    keep = inside_keel(keel, x)
    # the prisms' polygons in their principal frames (Floes), which q turns
    body = np.array(blocks_as_floes(keel, rects, x, q, keel_law(keel), keel_water(job)).polygons)[keep]
    p_all = porosity(keel, x[keep], q[keep], body, keel.blocks.thickness)
    p_core = porosity(keel, x[keep], q[keep], body, keel.blocks.thickness, core=0.5)
    speed = np.linalg.norm(v, axis=1)
    print(f"t = {t:.4g} s: {keep.sum():,} of {len(x):,} blocks in the keel; porosity {p_all:.3f}, core {p_core:.3f}; "
          f"RMS speed {np.sqrt((speed ** 2).mean()):.3g} m/s, median {np.median(speed):.3g} m/s")


if __name__ == "__main__":
    main()
