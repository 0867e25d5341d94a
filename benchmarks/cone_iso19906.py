"""A DEM cone beside ISO 19906's sloping-structure loads (A.8.2.4.4.2 Croasdale, A.8.2.4.4.3 Ralston).

A rigid, fixed, upward-breaking cone (60 degrees from the horizontal, 14 m at the waterline, the
slope from 4 m below to 3 m above the water, a 5 m vertical neck above: pice/scenes/cone.py) as a
mesh hull of a body with prescribed zero velocity; a level sheet 60 m wide and 50 m long (E 1 GPa,
sigma_f 0.56 MPa, the reference scene's ice) drifts onto it at 0.5 m/s with the current, driven at the
far field. For each element size and thickness the script prints the DEM's horizontal load over
t > --start (the first metres of penetration left out): its mean, its largest value, the mean of its
maxima over 1 s windows (about one breaking cycle each), the height the ice rides up the cone, and
beside them ISO's F_H: Croasdale 3D with no rubble (the standard's), 2D (l_c = w) and 3D with the
DEM's ride-up height as the rubble height, and Ralston. Then the exponent of F ~ h^k fitted over the
thicknesses for each. Results go to cone_iso19906.json beside this script (--json to change);
docs/iso19906.md has the table. tests/physics/test_cone_iso19906.py runs the coarse case.

    python benchmarks/cone_iso19906.py [--thickness 0.5,0.75,1.0] [--element-diameter 1.0,2.0]
                                       [--duration 30] [--start 5]

About 5 min of one core for each 1 m-element case, 50 s for a 2 m one: ~17 min for the default sweep.
"""

from __future__ import annotations

import argparse
import json
import pathlib
import tempfile

import numpy as np

from pice.job import parse_job
from pice.scenes.cone import cone_job, iso_loads, measure_cone_load, summarize, write_cone_mesh
from pice.simulation import Simulation

GEOMETRY = dict(diameter=14.0, angle_deg=60.0, below=4.0, above=3.0, neck=5.0)
DEM_KEYS = ("mean", "peak", "peak_mean")
ISO_KEYS = ("croasdale", "croasdale_2d", "croasdale_rubble", "ralston")


def run_case(folder: pathlib.Path, *, thickness: float, element_diameter: float, duration: float,
             start: float) -> dict:
    """One DEM run and its ISO references (loads in N)."""
    mesh = folder / "cone.stl"
    centre = write_cone_mesh(mesh, **GEOMETRY)
    job = parse_job(cone_job(mesh, centre, diameter=GEOMETRY["diameter"], angle_deg=GEOMETRY["angle_deg"],
                             thickness=thickness, element_diameter=element_diameter, duration=duration),
                    source="cone")
    rec = measure_cone_load(Simulation(job), near=0.5 * GEOMETRY["diameter"] + 3.0)
    dem = summarize(rec, start=start)
    iso = iso_loads(diameter=GEOMETRY["diameter"], angle_deg=GEOMETRY["angle_deg"], thickness=thickness,
                    ride_up=dem["ride_up"], above=GEOMETRY["above"])
    return dict(thickness=thickness, element_diameter=element_diameter, elements=rec.elements, cpu=rec.cpu,
                modes=rec.modes.tolist(), **dem, **iso)


def exponent(rows: list[dict], key: str) -> float:
    """k of F ~ h^k, least squares in log-log over the rows (one element size)."""
    h = np.log([r["thickness"] for r in rows])
    return float(np.polyfit(h, np.log([r[key] for r in rows]), 1)[0])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--thickness", default="0.5,0.75,1.0", help="ice thicknesses [m]")
    ap.add_argument("--element-diameter", default="1.0,2.0", help="element sizes [m]")
    ap.add_argument("--duration", type=float, default=30.0, help="simulated time [s]")
    ap.add_argument("--start", type=float, default=5.0, help="statistics over t > start [s]")
    ap.add_argument("--json", default=str(pathlib.Path(__file__).with_suffix(".json")))
    args = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for d in map(float, args.element_diameter.split(",")):
            for h in map(float, args.thickness.split(",")):
                rows.append(run_case(pathlib.Path(tmp), thickness=h, element_diameter=d, duration=args.duration,
                                     start=args.start))
                r = rows[-1]
                print(f"d = {d} m, h = {h} m: {r['elements']} elements, {r['cpu']:.0f} s cpu", flush=True)
    print(f"\ncone {GEOMETRY['diameter']} m at the waterline, {GEOMETRY['angle_deg']} deg; loads in MN over "
          f"t > {args.start} s of {args.duration} s")
    print("  d [m]  h [m]  DEM mean   peak  1s-peaks  ride-up [m]  Croasdale  2D   +rubble  Ralston"
          "  peaks/Croasdale")
    for r in rows:
        mn = {k: r[k] / 1e6 for k in DEM_KEYS + ISO_KEYS}
        print(f"  {r['element_diameter']:5.1f}  {r['thickness']:5.2f}  {mn['mean']:8.3f} {mn['peak']:6.3f}"
              f"  {mn['peak_mean']:8.3f}  {r['ride_up']:11.2f}  {mn['croasdale']:9.3f} {mn['croasdale_2d']:5.3f}"
              f"  {mn['croasdale_rubble']:7.3f}  {mn['ralston']:7.3f}  {r['peak_mean'] / r['croasdale']:15.2f}")
    fits = {}
    for d in sorted({r["element_diameter"] for r in rows}):
        same = [r for r in rows if r["element_diameter"] == d]
        if len(same) > 1:
            fits[str(d)] = {k: exponent(same, k) for k in DEM_KEYS + ISO_KEYS}
            print(f"  d = {d} m: F ~ h^k, k = " + ", ".join(f"{k} {v:.2f}" for k, v in fits[str(d)].items()))
    pathlib.Path(args.json).write_text(json.dumps(dict(geometry=GEOMETRY, duration=args.duration, start=args.start,
                                                       rows=rows, exponents=fits), indent=1) + "\n")
    print(f"wrote {args.json}")


if __name__ == "__main__":
    main()
