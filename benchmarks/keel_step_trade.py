"""The ridge runs' time step against their answer (issue 15; docs/ridge_keel.md, "The step"): a small
keel of jobs/gong_2017_keel_w17_3.toml's blocks and contact, met by a ship of M/T Uikku's lines
scaled to a fifth, generated and run at several keel.step_fraction, on one rank.

    python benchmarks/keel_step_trade.py [--fractions 0.05 0.1 0.2] [--generate 0.1 0.2] [--seeds 1 2 3] [--out DIR]

The scene: a 2.5 m deep triangular keel, 8.66 m wide at the cover and 8 m long (half model, the
symmetry wall at y = 0), of seed 002's 0.3 m blocks (Table 1); a half ship hull of Table 1's angles
(waterline 25.2 deg, stem 29.7 deg) and a fifth of its length, breadth and draft (30 m, 4.44 m,
1.9 m), driven at 1 m/s for 20 s: the bow through the keel and 4 m beyond.

What it prints:
- each keel generated at 0.1 for every seed, and at every --generate fraction for the first seed:
  blocks kept, porosity, settling time, wall time;
- each ship run from the first seed's keel at every fraction, from every seed's keel at the
  fraction 0.1, and from each --generate keel at its own fraction (the whole pipeline at one step):
  R^p (the 6 m running average's peak, seed 002's Fig. 5), the work of R over the penetration (kJ)
  and the wall time.

The step's effect is read against the spread of the same answers from one random keel to another
(the seeds): a step whose change is well inside that spread costs the user nothing they could see.
Results go to DIR (default runs/keel_step_trade) and a JSON summary beside them; a study run again
with more seeds or fractions reuses the keels and runs already in DIR.
"""

from __future__ import annotations

import argparse
import json
import pathlib
import time

import numpy as np

from pice.cli import main as pice

KEEL = """
[run]
name = "{name}"
duration = {duration}
dt = "auto"
series_every = 20
snapshots = 0

[water]
density = 1010.0

[keel]
width = 8.66
length = {length}
depth = 2.5
pile_angle = 30.0
x = 21.33
y0 = {y0}
cover = 0.0
seed = {seed}
settle_friction = 0.0
lock_speed = 0.05
step_fraction = {fraction}
file = "{keel_file}"
blocks = {{thickness = 0.3, aspect = 0.615, length = [0.6, 1.4]}}
contact = {{normal_stiffness = 1.0e7, damping_ratio = 0.3, tangential_stiffness = 0.6e7, friction = {friction}, compressive_strength = 1.0e15}}
"""
SHIP = """
[[bodies]]
name = "ship"
hull = {{type = "ship", length = 30.0, midbody = 13.5, breadth = 4.44, draft = 1.9, waterline_angle = 25.2, stem_angle = 29.7, half = {half}}}
mass = 1.7e5
inertia = [1.0e6, 1.0e7, 1.0e7]
position = [0.0, 0.0, 0.0]
motion = "prescribed"
velocity = [[0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0]]
friction = 0.1
"""
# the half model: the keel from the symmetry wall at y = 0 to y = 8 m beside the half hull; the full
# model: twice as long, y = -8 to 8 m, about the whole hull (seed 002's l_h and l_f, at this scale)
MODELS = {"half": dict(length=8.0, y0=0.0, half="true"), "full": dict(length=16.0, y0=-8.0, half="false")}
DURATION = 20.0  # [s] at 1 m/s: the stem meets the keel at delta = 2 m, the bow's shoulder leaves it at 15.4 m


def _pice(*args: str) -> None:
    """``pice ARGS`` in this process; stop the study, naming the command, when it fails."""
    if pice(list(args)) != 0:
        raise SystemExit(f"keel_step_trade: `pice {' '.join(args)}` failed (its message is above)")


def keel_job(name: str, seed: int, fraction: float, keel_file: str, model: str = "half", friction: float = 0.3) -> str:
    """The TOML of the small keel (``model``: "half" or "full", MODELS) at ``fraction`` with mu_i =
    ``friction``."""
    m = MODELS[model]
    return KEEL.format(name=name, duration=DURATION, seed=seed, fraction=fraction, keel_file=keel_file,
                       length=m["length"], y0=m["y0"], friction=friction)


def generate(out: pathlib.Path, seed: int, fraction: float, model: str = "half") -> dict:
    """Generate the ``model`` keel of ``seed`` at ``fraction``; its file's records and the wall time [s]."""
    from pice.io.keel_file import read_keel
    from pice.job import load_job

    stem = f"keel_s{seed}_f{fraction:g}" + ("" if model == "half" else f"_{model}")
    keel_file = out / f"{stem}.keel.h5"
    job = out / f"{stem}.toml"
    job.write_text(keel_job(job.stem, seed, fraction, keel_file.name, model))
    took = out / f"{job.stem}.wall"  # the generation's wall time [s], kept for a continued study
    if not keel_file.exists():
        t0 = time.perf_counter()
        _pice("keel", str(job))
        took.write_text(repr(time.perf_counter() - t0))
    wall = float(took.read_text()) if took.exists() else float("nan")
    k = read_keel(keel_file, load_job(job).keel, str(job))
    return dict(seed=seed, fraction=fraction, kept=len(k["x"]), released=k["released"], porosity=k["porosity"],
                core=k["core_porosity"], settled_at=k["settle_time"], wall=wall, file=keel_file.name, model=model)


def ship_run(out: pathlib.Path, keel: dict, fraction: float, friction: float = 0.3) -> dict:
    """Run the ship through ``keel``'s file at ``fraction`` with mu_i = ``friction``: R^p [kN], where [m],
    the work [kJ], wall [s]; the hull half or whole as the keel's model."""
    from pice.io.run_reader import open_run
    from pice.postproc.resistance import peak_resistance, resistance_record, resistance_work

    generated = "" if keel["fraction"] == 0.1 else f"_g{keel['fraction']:g}"  # a keel of another step
    model = keel.get("model", "half")
    name = (f"ship_s{keel['seed']}{generated}_f{fraction:g}" + ("" if model == "half" else f"_{model}")
            + ("" if friction == 0.3 else f"_mu{friction:g}"))
    done = out / f"{name}.json"
    if done.exists():  # run before (a study continued with more seeds or fractions)
        return json.loads(done.read_text())
    job = out / f"{name}.toml"
    job.write_text(keel_job(name, keel["seed"], fraction, keel["file"], model, friction)
                   + SHIP.format(half=MODELS[model]["half"]))
    t0 = time.perf_counter()
    _pice("run", str(job), "-o", str(out / f"{name}.h5"))
    wall = time.perf_counter() - t0
    with open_run(out / f"{name}.h5") as run:
        delta, r = resistance_record(run)
        dt = float(run.attrs["dt"]) if "dt" in run.attrs else float("nan")
    peak, where = peak_resistance(delta, r)
    work = resistance_work(delta, r)
    result = dict(seed=keel["seed"], model=model, friction=friction, generated=keel["fraction"], fraction=fraction,
                  dt=dt, peak_kN=peak / 1e3, at_m=where, work_kJ=work / 1e3, max_kN=float(r.max()) / 1e3, wall=wall)
    done.write_text(json.dumps(result))
    return result


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fractions", type=float, nargs="+", default=[0.05, 0.1, 0.2])
    ap.add_argument("--generate", type=float, nargs="+", default=[0.1, 0.2],
                    help="the first seed's keel is also generated at these fractions")
    ap.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    ap.add_argument("--out", default="runs/keel_step_trade")
    args = ap.parse_args()
    if 0.1 not in args.fractions:
        ap.error("--fractions must include 0.1, the jobs' step, against which the others are read")
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    seed0 = args.seeds[0]
    keels = {(s, 0.1): generate(out, s, 0.1) for s in args.seeds}
    keels.update({(seed0, f): generate(out, seed0, f) for f in args.generate if f != 0.1})
    print("keel generations (the jobs' staged settling; a triangle 8.66 m x 2.5 m, 8 m long)")
    print(f"{'seed':>4} {'fraction':>8} {'released':>8} {'kept':>5} {'porosity':>8} {'core':>6} {'settled [s]':>11} {'wall [s]':>8}")
    for k in keels.values():
        print(f"{k['seed']:>4} {k['fraction']:>8g} {k['released']:>8} {k['kept']:>5} {k['porosity']:>8.3f} "
              f"{k['core']:>6.3f} {k['settled_at']:>11.1f} {k['wall']:>8.0f}")
    runs = [ship_run(out, keels[(seed0, 0.1)], f) for f in args.fractions]
    runs += [ship_run(out, keels[(s, 0.1)], 0.1) for s in args.seeds if s != seed0]
    runs += [ship_run(out, keels[(seed0, f)], f) for f in args.generate if f != 0.1]
    print(f"\nship runs (half hull, 1 m/s, {DURATION:g} s; 'keel at': the step its keel was generated at)")
    print(f"{'seed':>4} {'keel at':>7} {'fraction':>8} {'dt [s]':>9} {'R^p [kN]':>8} {'at [m]':>6} {'max R [kN]':>10} "
          f"{'work [kJ]':>9} {'wall [s]':>8}")
    for r in runs:
        print(f"{r['seed']:>4} {r.get('generated', 0.1):>7g} {r['fraction']:>8g} {r['dt']:>9.3g} {r['peak_kN']:>8.2f} "
              f"{r['at_m']:>6.1f} {r['max_kN']:>10.2f} {r['work_kJ']:>9.1f} {r['wall']:>8.0f}")
    spread = [r["peak_kN"] for r in runs if r["fraction"] == 0.1 and r.get("generated", 0.1) == 0.1]
    if len(spread) > 1:
        print(f"\nR^p over the seeds at 0.1: {min(spread):.2f}-{max(spread):.2f} kN "
              f"(mean {np.mean(spread):.2f}, standard deviation {np.std(spread, ddof=1):.2f})")
    (out / "summary.json").write_text(json.dumps(dict(keels=list(keels.values()), runs=runs), indent=1))


if __name__ == "__main__":
    main()
