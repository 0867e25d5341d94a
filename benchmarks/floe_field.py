"""Cost of the rigid-floe step (issue 14 groundwork; one rank): a managed-ice field drifting in a
0.4 m/s current onto a fixed cone like the Kulluk's (seed 003), with pice/physics/floes.py.

    python benchmarks/floe_field.py [--length 400] [--width 240] [--concentration 0.7] [--steps 200] [--dt 0.02]

Prints the floes, the step [s], wall time per step and floe-steps per second, the contacts and the
structure's load at the end. The step is set by accuracy, not stability: Table 3's dashpot damps a
contact over m_eff / c_n ~ 0.6 s for 3,000 t floes (tests/physics/test_floe_contact.py).
"""

from __future__ import annotations

import argparse
import time

from pice.physics.floes import FloeLaw, Floes, FloeWater
from pice.platform.hulls import revolved
from pice.scenes.floe_field import floe_field

KULLUK = [(-12.5, 31.0), (-10.06, 31.0), (0.0, 35.0), (9.0, 40.5)]  # (z, r) [m]: Table 1 of seed 003, assumed


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--length", type=float, default=400.0)
    ap.add_argument("--width", type=float, default=240.0)
    ap.add_argument("--concentration", type=float, default=0.7)
    ap.add_argument("--steps", type=int, default=200)
    ap.add_argument("--dt", type=float, default=0.02)
    args = ap.parse_args()
    field = floe_field(area=(-args.length - 45.0, -0.5 * args.width, -45.0, 0.5 * args.width), size=(20.0, 30.0),
                       concentration=args.concentration, seed=2017)
    floes = Floes(field.polygons, field.thickness, velocity=(0.4, 0.0, 0.0), law=FloeLaw(),
                  water=FloeWater(current=(0.4, 0.0)))
    for k in range(len(KULLUK) - 1):  # convex pieces: each ring to the next a frustum (the profile widens upwards)
        floes.add_structure(*revolved(KULLUK[k:k + 2], 40), centre=(0.0, 0.0, 0.0))
    floes.compute_forces(args.dt)
    floes.step(args.dt)  # compile
    t0 = time.perf_counter()
    for _ in range(args.steps):
        floes.step(args.dt)
    wall = time.perf_counter() - t0
    n = len(floes.mass)
    print(f"floes               {n} ({field.concentration:.1%} of {args.length:.0f} m x {args.width:.0f} m, 20-30 m)")
    print(f"step                {args.dt} s, {args.steps} steps in {wall:.2f} s: {1e3 * wall / args.steps:.2f} ms a step, "
          f"{n * args.steps / wall:.3g} floe-steps/s")
    print(f"contacts            {floes.stats[0]} floe-floe at the end; structure load "
          f"{floes.structure_load[:, :3].sum(axis=0).round(0).tolist()} N")


if __name__ == "__main__":
    main()
