"""Towed-line test of Zhu & Ji (2022), Table 2: the top end of a model mooring line in surge.

The model is pice/scenes/towed_line.py (line 7.305 m, dry mass 0.162 kg/m, diameter 5.2 mm,
E = 77.2 GPa, the top 1.2 m above and 6.97 m from the anchor on the tank floor, in fresh water; the
top surges with 75 mm amplitude and a 1.58 s period). For each element count the script prints min,
max and mean top tension over the last three periods (after three periods of spin-up from rest, the
motion ramped in over the first) and the vertical range of the point 0.8 m from the top, with the
wall time, next to the static elastic catenary references (`static_reference`); with --plot it
saves both traces (pice/postproc/towed_line.py). tests/physics/test_towed_line.py runs 10, 20 and
40 elements.

    python benchmarks/towed_line.py [--elements 10,20,40,80] [--plot towed.png]
"""

from __future__ import annotations

import argparse

from pice.scenes.towed_line import run, static_reference


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
        from pice.postproc.towed_line import plot_towed_line

        plot_towed_line(results, args.plot)
        print(f"saved {args.plot}")


if __name__ == "__main__":
    main()
