"""The reference job's surge restoring curve: the independent catenary beside pice's two line models.

For jobs/zhu_ji_2022_semisub.toml's [[moorings]] as a run builds them (pice.platform.build: the
layout solve places the anchors for the 221.7 kN pretension), the platform translated in surge by
0-30 m without rotation: the restoring force -F_x [MN] and the largest fairlead tension [MN] of

  * the independent elastic catenary with seabed contact (tests/reference_catenary.py);
  * pice's model = "quasi_static" (pice.platform.quasi_static);
  * pice's model = "dem" lines (the job's 10 m elements and the coarse run's 20 m), measured
    statically: the fairleads carried at 1 m/s from offset to offset as a surging hull carries them,
    then held until the lines settle (kinetic damping to 1 N per node), the current switched off;
  * with --coupled, the independent catenary with heave and pitch free (benchmarks/mooring_layouts.py:
    the hull's hydrostatics, the load acting at the line of action of the coarse run's mean loads),
    which is how the platform of a run meets the lines.

tests/physics/test_restoring_curve.py checks the quasi-static lines at eight of these offsets and the DEM
lines (20 m) at three; docs/reference_scene.md has the table.

    python benchmarks/restoring_curve.py [--coupled] [--offsets 0,5,10,...]
"""

from __future__ import annotations

import argparse
import math
import pathlib
import time

import numpy as np

import mooring_layouts as ml
import reference_catenary as rc  # on sys.path through mooring_layouts

JOB = pathlib.Path(__file__).resolve().parents[1] / "jobs" / "zhu_ji_2022_semisub.toml"


def job_lines(**mooring):
    """(job, lines of its [[moorings]] entry as the run builds them), ``mooring`` keys replaced."""
    try:
        import tomllib
    except ModuleNotFoundError:  # Python 3.10
        import tomli as tomllib

    from pice.job import parse_job
    from pice.platform.build import _mooring_group, initial_poses

    data = tomllib.loads(JOB.read_text())
    data["moorings"][0].update(mooring)
    job = parse_job(data, source=str(JOB))
    return job, _mooring_group(job, 0, initial_poses(job)).lines


def quasi_static(offsets) -> list[tuple[float, float]]:
    """(restoring force [N], largest fairlead tension [N]) of model = "quasi_static" at each offset [m]."""
    _, qs = job_lines(model="quasi_static")
    fl0, out = qs.fairlead_x.copy(), []
    for s in offsets:
        qs.advance(0.0, 1, fl0 + [s, 0.0, 0.0])
        out.append((-qs.reactions(qs.fairleads)[:, 0].sum(), qs.fairlead_tensions().max()))
    return out


def dem(offsets, element_length: float, speed: float = 1.0) -> list[tuple[float, float]]:
    """(restoring force [N], largest fairlead tension [N]) of the DEM lines carried at ``speed`` [m/s]
    through the offsets [m] (increasing) and settled at each."""
    _, lines = job_lines(element_length=element_length)
    lines.current[:] = 0.0
    fl0, at, out = lines.x[lines.fairleads].copy(), 0.0, []
    dt = 0.5 * lines.stable_step()
    for s in offsets:
        if s > at:
            n = int(math.ceil((s - at) / speed / dt))
            lines.advance((s - at) / speed / n, n, fl0 + [s, 0.0, 0.0], np.tile([speed, 0.0, 0.0], (len(fl0), 1)))
        lines.relax(tol=1.0)
        if not lines.settled:
            raise RuntimeError(f"the DEM lines did not settle at {s} m")
        out.append((-lines.reactions(lines.fairleads)[:, 0].sum(), lines.fairlead_tensions().max()))
        at = s
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--offsets", default="0,5,10,14.7,15,17.6,20,23.3,25,27.5,28,30")
    ap.add_argument("--coupled", action="store_true")
    args = ap.parse_args()
    offsets = [float(s) for s in args.offsets.split(",")]
    anchors = ml.Layout("ours").anchors()
    ref = [rc.restoring(ml.LINE, anchors, s) for s in offsets]
    qs = quasi_static(offsets)
    t0 = time.perf_counter()
    d10 = dem(offsets, 10.0)
    t1 = time.perf_counter()
    d20 = dem(offsets, 20.0)
    t2 = time.perf_counter()
    print(f"(DEM: {t1 - t0:.0f} s with 10 m elements, {t2 - t1:.0f} s with 20 m)")
    head = ("| surge [m] | independent catenary F / T_max [MN] | pice quasi-static F / T_max [MN] "
            "| pice DEM 10 m F / T_max [MN] | pice DEM 20 m F [MN] |")
    if args.coupled:
        hull = ml.Hull(ml.Layout("ours"), ml.CORNERS)
        lever = ml.RUN["ice_my"] / (ml.RUN["ice_x"] + ml.RUN["hull_drag"])  # [m] above the CG
        head += " heave and pitch free: F / T_max [MN], heave [m], pitch [deg] |"
    print(head)
    print("|---" * (head.count("|") - 1) + "|")
    for k, s in enumerate(offsets):
        pair = [f"{f / 1e6:.3f} / {t / 1e6:.3f}" for f, t in (ref[k], qs[k], d10[k])]
        line = f"| {s:g} | {' | '.join(pair)} | {d20[k][0] / 1e6:.3f} |"
        if args.coupled:
            f, h, p, t = ml.coupled_force(hull, s, lever)
            line += f" {f / 1e6:.2f} / {t / 1e6:.2f}, {h:.2f}, {p:.2f} |"
        print(line)


if __name__ == "__main__":
    main()
