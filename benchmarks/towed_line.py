"""Towed-line test of Zhu & Ji (2022), Table 2: the top end of a model mooring line in surge.

Line 7.305 m, dry mass 0.162 kg/m, diameter 5.2 mm, E = 77.2 GPa, the top 1.2 m above and 6.97 m
from the anchor on the tank floor, in fresh water; the top surges with 75 mm amplitude and a 1.58 s
period. For each element count the script prints min, max and mean top tension over the last three
periods (after three periods of spin-up from rest, the motion ramped in over the first) and the vertical range of the point
0.8 m from the top, with the wall time, next to the static elastic catenary references
(`static_reference`); with --plot it saves both traces. tests/test_towed_line.py runs 10 and 20
elements through `run`, `static_reference` and `plot`.

    python benchmarks/towed_line.py [--elements 10,20,40,80] [--plot towed.png]
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from pice.physics.catenary import Segment, profile, solve_line
from pice.physics.mooring import LineSegment, build_lines

LENGTH, DRY, D, E = 7.305, 0.162, 0.0052, 77.2e9
RHO = 1000.0
AMP, PERIOD = 0.075, 1.58
TOP = np.array([6.97, 0.0, 1.2])


def surge(t: float):
    """Top-end position [m] and velocity [m/s]: 75 mm, 1.58 s, ramped in over the first period
    (a half-cosine ramp: no velocity jump at the start)."""
    w = 2 * math.pi / PERIOD
    ramp, dramp = (0.5 - 0.5 * math.cos(math.pi * t / PERIOD), 0.5 * math.pi / PERIOD * math.sin(math.pi * t / PERIOD)) \
        if t < PERIOD else (1.0, 0.0)
    x = AMP * ramp * math.sin(w * t)
    v = AMP * (dramp * math.sin(w * t) + ramp * w * math.cos(w * t))
    return TOP + np.array([x, 0.0, 0.0]), np.array([v, 0.0, 0.0])


def line_segment() -> LineSegment:
    """Table 2's line for the DEM model (drag and added-mass coefficients: assumptions)."""
    area = math.pi * D * D / 4
    return LineSegment(length=LENGTH, ea=E * area, diameter=D, wet_weight=(DRY - RHO * area) * 9.81,
                       dry_mass=DRY, drag_normal=1.2, drag_tangential=0.01, added_mass=1.0)


def static_reference(samples: int = 400) -> dict:
    """Static elastic catenary references (pice.physics.catenary, rigid frictionless tank floor):

    t_static   top tension [N] with the top at its mean position TOP (the line at rest);
    t_qs_mean  the cycle mean of the static top tension as the top moves through x = 6.97 + 0.075 sin
               (a line following the surge quasi-statically; above t_static, T(x) being convex);
    z_qs_range vertical range [m] of the point 0.8 m (unstretched) from the top between the static
               shapes at the two extreme top positions.
    """
    seg = line_segment()
    cat = [Segment(seg.length, seg.wet_weight, seg.ea)]

    def state(dx):
        return solve_line(cat, horizontal=TOP[0] + dx, vertical=TOP[2])

    phases = 2 * math.pi * np.arange(samples) / samples
    z_mark = [np.interp(LENGTH - 0.8, *profile(cat, state(dx), 400)[:, [0, 2]].T) for dx in (-AMP, AMP)]
    return {"t_static": state(0.0).fairlead_tension,
            "t_qs_mean": float(np.mean([state(AMP * math.sin(p)).fairlead_tension for p in phases])),
            "z_qs_range": abs(z_mark[1] - z_mark[0])}


def run(elements: int, periods: int = 6, outer_dt: float = 1e-3) -> dict:
    """Tow the DEM line with ``elements`` elements for ``periods`` periods after 2 s at rest.

    Returns the traces t [s], tension (top) [N], z (marker 0.8 m from the top) [m]; over the last
    three periods t_min, t_max, t_mean [N], z_range [m]; t_rest [N], the top tension at the end of
    the 2 s at rest; the sub-step dt [s] and the wall time [s] of the towed part.
    """
    seg = line_segment()
    ml = build_lines([((0.0, 0.0, 0.0), TOP, [seg])], element_length=LENGTH / elements, water_density=RHO,
                     water_level=1.3, seabed_z=0.0, bond_damping=0.2, seabed_stiffness=2.0e3,
                     seabed_friction=0.3)
    dt = 0.5 * ml.stable_step()
    nsub = max(1, math.ceil(outer_dt / dt))
    dt = outer_dt / nsub
    # arc-length position of the marker 0.8 m from the top: interpolate between the nodes
    s_nodes = np.linspace(0.0, LENGTH, len(ml.x))
    s_mark = LENGTH - 0.8
    k = int(np.searchsorted(s_nodes, s_mark)) - 1
    frac = (s_mark - s_nodes[k]) / (s_nodes[k + 1] - s_nodes[k])
    ml.advance(dt, round(2.0 / dt))  # settle from the static shape (2 s at rest)
    t_rest = float(ml.fairlead_tensions()[0])
    steps = round(periods * PERIOD / outer_dt)
    t_hist, tension, z_mark = np.empty(steps), np.empty(steps), np.empty(steps)
    t0 = time.perf_counter()
    for n in range(steps):
        t = (n + 1) * outer_dt
        xf, vf = surge(t)
        ml.advance(dt, nsub, xf[None, :], vf[None, :])
        t_hist[n] = t
        tension[n] = ml.fairlead_tensions()[0]
        z_mark[n] = (1 - frac) * ml.x[k, 2] + frac * ml.x[k + 1, 2]
    wall = time.perf_counter() - t0
    last = t_hist > (periods - 3) * PERIOD
    return {"elements": elements, "dt": dt, "wall": wall, "t": t_hist, "tension": tension, "z": z_mark,
            "t_rest": t_rest, "t_min": float(tension[last].min()), "t_max": float(tension[last].max()),
            "t_mean": float(tension[last].mean()), "z_range": float(np.ptp(z_mark[last]))}


def plot(results, path) -> None:
    """Save the top-tension and marker traces of ``run`` results to ``path`` (PNG)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (a, b) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    for r in results:
        a.plot(r["t"], r["tension"], label=f"{r['elements']} elements")
        b.plot(r["t"], 1e3 * (r["z"] - r["z"].mean()), label=f"{r['elements']} elements")
    a.set_ylabel("top tension [N]")
    b.set_ylabel("marker 0.8 m from top: z - mean [mm]")
    b.set_xlabel("time [s]")
    a.legend()
    a.set_title("Towed line (Zhu & Ji 2022, Table 2): top end in surge, 75 mm, 1.58 s")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--elements", default="10,20,40,80")
    ap.add_argument("--plot", help="save the traces to this PNG (needs matplotlib)")
    args = ap.parse_args()
    results = [run(int(n)) for n in args.elements.split(",")]
    print("elements  sub-step [s]  wall [s]  T_min [N]  T_max [N]  T_mean [N]  marker z range [mm]")
    for r in results:
        print(f"{r['elements']:8d}  {r['dt']:12.3e}  {r['wall']:8.2f}  {r['t_min']:9.3f}  {r['t_max']:9.3f}"
              f"  {r['t_mean']:10.3f}  {1e3 * r['z_range']:10.2f}")
    ref = static_reference()
    print(f"static catenary: top tension {ref['t_static']:.3f} N at the mean top position, quasi-static cycle "
          f"mean {ref['t_qs_mean']:.3f} N, marker z range {1e3 * ref['z_qs_range']:.2f} mm")
    if args.plot:
        plot(results, args.plot)
        print(f"saved {args.plot}")


if __name__ == "__main__":
    main()
