"""Seed 002's two model checks on a small keel (issue 15; docs/ridge_keel.md, "Half and full model,
mu_i, and the keel at step 0.2, on a small keel"): the half model with its symmetry wall against the full model, and the ice-ice
friction mu_i 0.3 against 0.6, on one rank.

    python benchmarks/keel_half_full.py [--seeds 1 2 3] [--frictions 0.3 0.6] [--fraction 0.1] [--out DIR]

The scene is benchmarks/keel_step_trade.py's: a 2.5 m deep triangular keel 8.66 m wide of seed 002's
0.3 m blocks, met at 1 m/s by a ship of M/T Uikku's angles at a fifth of its length, breadth and draft
(30 m, 4.44 m, 1.9 m), for 20 s. The half model: the keel 8 m long from the symmetry wall at y = 0 and
the half hull (as that script's runs); the full model: the keel 16 m long from y = -8 m, basin walls at
both ends, and the whole hull. Each seed generates one keel of each model (the jobs' staged settling
at --fraction, 0.1 as the jobs, or 0.2: docs/ridge_keel.md, "The step"); every keel is run at every
friction, at the same step.

What it prints: the keels (blocks, porosity), each run's R^p (6 m running average's peak, seed 002's
Fig. 5) and work of R, then
- the full model's R^p over twice the half model's, seed by seed and of the means (seed 002: full
  models 6-10 % above twice the half; the issue's check: within 10 %);
- R^p at mu_i 0.6 over 0.3 on the same keel (seed 002, Fig. 8: +16 to +38 %, most at small w).
The first is read against the spread of R^p from one random keel to the next; the second is paired
(one keel, both frictions). Results go to DIR (default runs/keel_half_full); the files are named as
keel_step_trade.py names them, so with its --out the half keels and runs already there are reused.
"""

from __future__ import annotations

import argparse
import json
import pathlib

import numpy as np
from keel_step_trade import generate, ship_run  # this folder's script: the scene and its runs


def _ratio(a: list[float], b: list[float]) -> str:
    """mean(a) / mean(b) with the standard error of the ratio from the seeds' spread (first order)."""
    ma, mb = np.mean(a), np.mean(b)
    r = ma / mb
    if len(a) < 2 or len(b) < 2:
        return f"{r:.3f}"
    se = r * np.hypot(np.std(a, ddof=1) / np.sqrt(len(a)) / ma, np.std(b, ddof=1) / np.sqrt(len(b)) / mb)
    return f"{r:.3f} +- {se:.3f}"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    ap.add_argument("--frictions", type=float, nargs="+", default=[0.3, 0.6])
    ap.add_argument("--models", nargs="+", choices=("half", "full"), default=["half", "full"])
    ap.add_argument("--fraction", type=float, default=0.1, help="keel.step_fraction of the keels and the runs")
    ap.add_argument("--out", default="runs/keel_half_full")
    args = ap.parse_args()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    f = args.fraction
    keels = {(m, s): generate(out, s, f, m) for m in args.models for s in args.seeds}
    print(f"keels (step_fraction {f:g}, the jobs' staged settling; a triangle 8.66 m x 2.5 m)")
    print(f"{'model':>5} {'seed':>4} {'released':>8} {'kept':>5} {'porosity':>8} {'core':>6} {'wall [s]':>8}")
    for (m, s), k in keels.items():
        print(f"{m:>5} {s:>4} {k['released']:>8} {k['kept']:>5} {k['porosity']:>8.3f} {k['core']:>6.3f} {k['wall']:>8.0f}")
    runs = {(m, s, mu): ship_run(out, keels[(m, s)], f, mu) for m in args.models for s in args.seeds
            for mu in args.frictions}
    print(f"\nship runs (1 m/s, 20 s, step_fraction {f:g})")
    print(f"{'model':>5} {'seed':>4} {'mu_i':>5} {'R^p [kN]':>8} {'at [m]':>6} {'work [kJ]':>9} {'wall [s]':>8}")
    for (m, s, mu), r in runs.items():
        print(f"{m:>5} {s:>4} {mu:>5g} {r['peak_kN']:>8.2f} {r['at_m']:>6.1f} {r['work_kJ']:>9.1f} {r['wall']:>8.0f}")
    summary = {}
    for mu in args.frictions:
        peaks = {m: [runs[(m, s, mu)]["peak_kN"] for s in args.seeds] for m in args.models}
        for m, p in peaks.items():
            sd = f", sd {np.std(p, ddof=1):.2f} ({np.std(p, ddof=1) / np.mean(p):.1%})" if len(p) > 1 else ""
            print(f"\nmu_i {mu:g}, {m}: R^p mean {np.mean(p):.2f} kN{sd}", end="")
        if {"half", "full"} <= set(args.models):
            twice = [2.0 * p for p in peaks["half"]]
            print(f"\nmu_i {mu:g}: full / (2 x half) = {_ratio(peaks['full'], twice)} (means over the seeds; "
                  "seed 002: 1.06-1.10)")
            summary[f"full_over_twice_half_mu{mu:g}"] = float(np.mean(peaks["full"]) / np.mean(twice))
    if len(args.frictions) > 1:
        lo, hi = min(args.frictions), max(args.frictions)
        for m in args.models:
            a = [runs[(m, s, hi)]["peak_kN"] for s in args.seeds]
            b = [runs[(m, s, lo)]["peak_kN"] for s in args.seeds]
            # paired: both frictions on one keel, so the ratio is taken keel by keel and the keels'
            # spread of R^p cancels in it; the +- is the standard error of those ratios' mean
            paired = np.array(a) / np.array(b)
            each = ", ".join(f"{x:.3f}" for x in paired)
            se = f" +- {np.std(paired, ddof=1) / np.sqrt(len(paired)):.3f}" if len(paired) > 1 else ""
            print(f"\n{m}: R^p(mu_i {hi:g}) / R^p(mu_i {lo:g}) = {paired.mean():.3f}{se} (keel by keel {each}; "
                  "seed 002: 1.16-1.38)", end="")
            summary[f"friction_ratio_{m}"] = float(paired.mean())
    print()
    (out / "summary.json").write_text(json.dumps(dict(keels=list(keels.values()), runs=list(runs.values()),
                                                      ratios=summary), indent=1))


if __name__ == "__main__":
    main()
