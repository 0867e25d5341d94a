"""The numbers docs/reference_scene.md sets beside Zhu & Ji (2022), read from reference-scene run files.

    python benchmarks/reference_scene_table.py RUN.h5 [RUN.h5 ...] [--window T0 T1] [--until T] [--json OUT]

For each run file (a run of jobs/zhu_ji_2022_semisub*.toml), over the whole run unless it says
"window": the peak ice load Fx on the hull and when it came, the mean Fx over the window, the peak
|Fz| and Fz/Fx, the mean (window) and maximum surge offset, the sway and heave ranges, the roll,
pitch and yaw ranges, the largest fairlead tension, the largest mooring restoring force, and the
bonds broken by failure mode (kernels.bonds: 1 tension/bending, 2 shear/twist, 3 compression,
4 crushed through) from the broken-bond log. Units: MN, m, deg.
"""

from __future__ import annotations

import argparse
import json
import sys

import numpy as np

from pice.io.run_reader import open_run

MODES = {1: "tension_bending", 2: "shear_twist", 3: "compression", 4: "crushed"}


def table_row(path: str, window: tuple[float, float], until: float = np.inf) -> dict:
    """The reference-scene figures of one run file (module docstring), over its rows and breaks up
    to ``until`` [s] (to set the start of a long run beside a short one)."""
    with open_run(path) as run:
        keep = run.series("time") <= until

        def s(name):
            return run.series(name)[keep]

        t = s("time")
        fx_hi = np.maximum(s("ice_force_max")[:, 0, 0], s("ice_force")[:, 0, 0])
        fz = np.maximum(np.abs(s("ice_force_max")[:, 0, 2]), np.abs(s("ice_force_min")[:, 0, 2]))
        pos = s("body_position")[:, 0, :] - s("body_position")[0, 0, :]
        rot = np.degrees(s("body_rotation")[:, 0, :])
        tension = s("fairlead_tension_max")
        restoring = s("mooring_force")[:, 0, :2]
        events = run.broken_bonds()
        events = events[events[:, 1] <= until]
        w = (t >= window[0]) & (t <= window[1])
        modes = {name: int((events[:, 4] == m).sum()) for m, name in MODES.items()}
        return dict(
            run=path, t_end=float(t[-1]), window=list(window),
            peak_fx=float(fx_hi.max() / 1e6), t_peak=float(t[fx_hi.argmax()]),
            mean_fx=float(s("ice_force")[w, 0, 0].mean() / 1e6),
            peak_fz=float(fz.max() / 1e6), fz_over_fx=float(fz.max() / fx_hi.max()),
            mean_offset=float(pos[w, 0].mean()), max_offset=float(pos[:, 0].max()),
            sway_range=float(np.ptp(pos[:, 1])), heave_range=float(np.ptp(pos[:, 2])),
            roll_pitch_yaw_range=[float(v) for v in np.ptp(rot, axis=0)],
            max_tension=float(tension.max() / 1e6),
            max_restoring=float(np.linalg.norm(restoring, axis=1).max() / 1e6),
            broken=int(len(events)), broken_by_mode=modes)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--window", nargs=2, type=float, default=(0.0, 1e9), metavar=("T0", "T1"),
                    help="time window [s] of the means (default: the whole run)")
    ap.add_argument("--json", help="also write the rows here")
    ap.add_argument("--until", type=float, default=np.inf, help="read each run only up to this time [s]")
    a = ap.parse_args(argv)
    rows = [table_row(r, tuple(a.window), a.until) for r in a.runs]
    for r in rows:
        print(f"{r['run']} (to t = {r['t_end']:.1f} s; means over {r['window'][0]:g}-{min(r['window'][1], r['t_end']):g} s)")
        print(f"  peak Fx {r['peak_fx']:.2f} MN at t = {r['t_peak']:.1f} s; mean Fx {r['mean_fx']:.2f} MN; "
              f"peak |Fz| {r['peak_fz']:.2f} MN (Fz/Fx {r['fz_over_fx']:.3f})")
        print(f"  offset mean {r['mean_offset']:.1f} m, max {r['max_offset']:.1f} m; sway range "
              f"{r['sway_range']:.2f} m, heave range {r['heave_range']:.2f} m; roll/pitch/yaw ranges "
              + " / ".join(f"{v:.1f}" for v in r["roll_pitch_yaw_range"]) + " deg")
        print(f"  max fairlead tension {r['max_tension']:.2f} MN; max restoring force {r['max_restoring']:.2f} MN")
        print(f"  broken bonds {r['broken']}: " + ", ".join(f"{k} {v}" for k, v in r["broken_by_mode"].items()))
    if a.json:
        with open(a.json, "w") as f:
            json.dump(rows, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
