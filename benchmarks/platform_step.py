"""The platform's step on rank 0, part by part: warm, and with the caches evicted between steps.

In a full-scene step rank 0 steps the bodies and lines between the ice's kernels, which sweep tens of
megabytes and evict whatever the platform used the step before. This script builds a job's platform
alone (no ice: the ice load is held at zero), steps it as pice.simulation does (``begin_step``: the
kick and the drift; ``finish_step``: the loads, the peaks' tensions and the closing kick) and prints the median time of each part over the steps, first
warm (step after step), then with a sweep over ``--evict`` MB between the steps (the cache state the
full scene leaves behind). Issue 12's target is the platform under 3 % of a full-scene step
(docs/performance.md, "The platform and the output").

    python benchmarks/platform_step.py [--job jobs/zhu_ji_2022_semisub.toml] [--steps 2000] [--dt 2.6e-4]
                                       [--evict 64] [--general] [--json out.json]

``--general`` takes the general path even where the fused one applies (platform/fused_step.py), for
a side-by-side comparison.
"""

from __future__ import annotations

import argparse
import json
import pathlib
import sys
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
PARTS = ("begin", "finish")


def build(job_path: pathlib.Path):
    from pice.job import load_job
    from pice.platform.build import build_platform, hulls_from_job

    job = load_job(job_path)
    return build_platform(job, hulls_from_job(job, default_kn=1e8, reach=0.5))


def run(platform, steps: int, dt: float, evict: np.ndarray | None) -> dict[str, float]:
    """Median [us] of each part over ``steps`` steps; ``evict``: a buffer summed between the steps."""
    half = 0.5 * dt
    ice = np.zeros((len(platform.bodies), 6))
    times = np.zeros((steps, len(PARTS)))
    clock = time.perf_counter_ns
    for s in range(steps):
        if evict is not None:
            evict.sum()
        t0 = clock()
        platform.begin_step(half, dt)
        t1 = clock()
        platform.finish_step(ice, half)
        t2 = clock()
        times[s] = (t1 - t0, t2 - t1)
    med = np.median(times, axis=0) / 1e3
    out = dict(zip(PARTS, med.tolist()))
    out["step"] = float(np.median(times.sum(axis=1)) / 1e3)
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--job", type=pathlib.Path, default=ROOT / "jobs" / "zhu_ji_2022_semisub.toml")
    ap.add_argument("--steps", type=int, default=2000)
    ap.add_argument("--dt", type=float, default=2.6e-4, help="[s] (the reference scene's step at dt_safety 0.7)")
    ap.add_argument("--evict", type=float, default=64.0, help="[MB] swept between steps in the second pass")
    ap.add_argument("--general", action="store_true", help="the general path, not the fused step")
    ap.add_argument("--json", type=pathlib.Path)
    args = ap.parse_args(argv)
    platform = build(args.job)
    if args.general:
        platform.fused = None
    run(platform, 200, args.dt, None)  # compile and warm up
    warm = run(platform, args.steps, args.dt, None)
    buf = np.ones(int(args.evict * 2**20 / 8))
    evicted = run(platform, args.steps, args.dt, buf)
    path = "fused" if platform.fused is not None else "general"
    print(f"{args.job.name}: {len(platform.bodies)} bodies, {platform.n_lines} lines, dt {args.dt:g} s, {path} "
          f"path, median of {args.steps} steps [us]")
    print(f"{'part':10s} {'warm':>9s} {'evicted':>9s}")
    for name in PARTS + ("step",):
        print(f"{name:10s} {warm[name]:9.1f} {evicted[name]:9.1f}")
    if args.json:
        args.json.write_text(json.dumps({"job": str(args.job), "dt": args.dt, "steps": args.steps,
                                         "evict_MB": args.evict, "path": path, "warm_us": warm, "evicted_us": evicted}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
