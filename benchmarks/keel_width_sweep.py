"""Seed 002's width sweep (issue 15; docs/ridge_keel.md, "The width sweep"): the half-model jobs of
Table 2, jobs/gong_2017_keel_w{17_3,30,40,60,80}.toml, generated and run as they are except for what
the options change, on one rank each; R^p against the keel width w beside the seed's Fig. 8.

    python benchmarks/keel_width_sweep.py [--widths 17.3 30 40 60 80] [--frictions 0.3 0.6]
        [--block-scale 2] [--form-drag 0] [--fraction 0.2] [--past 30] [--end-after-peak F] [--seed 1]
        [--trim] [--full] [--out DIR] [--report]

At the jobs' 0.3 m blocks the matrix costs about 110 h on this machine (docs/ridge_keel.md, "Still to
build"). The options trade that against the seed's scene, each change named in what it prints:
- ``--block-scale s``: every block s times as long, wide and thick (s^3 fewer blocks; the contact
  law, its stiffness and the contact time's fraction unchanged, so the step grows with s^1.5). Its
  effect is measured on the narrowest keel against the jobs' blocks (docs).
- ``--form-drag C_d``: the blocks' form drag (the jobs: 1, a per-block upper bound; 0 the lower).
- ``--fraction``: keel.step_fraction for the generation and the run (0.2: about 2 % on R^p, "The
  step").
- ``--past m``: the run ends when the stem is m metres past the keel's far edge at the waterline
  (w + 2 + m seconds at 1 m/s; seed 002: R^p "is reached when the ship bow has nearly penetrated the
  whole ridge"; the jobs run w + 80 s for the midbody's friction as well).
- ``--end-after-peak F``: keel.end_after_peak (the jobs: 0.5; the sweep: off): each run ends sooner
  once its 6 m running average is below F times its peak, the stem past the keel.

- ``--trim``: one generation, the widest keel's (80 m); each narrower keel is trimmed from its middle
  (keel.trim_from) instead of generated (docs/ridge_keel.md, "One generation").

Each width is generated once (its keel serves every friction) and each (width, friction) run once:
results go to DIR (default runs/keel_width_sweep) as <name>.json, so a sweep stopped and started again
(or two processes given different --widths, one per core) continues; a run killed part-way restarts
from its checkpoint, a generation from its own (pice keel's .gen.h5). ``--report`` prints the table
of what DIR holds: per width the blocks kept, the porosity, R^p (half model and x 2 for the ship),
where it peaks, R^p over the narrowest keel's (seed 002: about eight-fold at 80 m, steep to 40 m,
slow after), R^p at mu_i 0.6 over 0.3 (seed: +16 to +38 %, most at small w), and Malmberg's R_A for
the ship (the seed: about 1000 kN, its w = 80 m keel 700-800 kN). ``--full`` runs the full model
instead (jobs/gong_2017_keel_w17_3_full.toml: l_f = 60 m, the whole hull; w = 17.3 m only), and the
report then adds its R^p over twice the half model's (seed 002: 6-10 % above; the issue: within 10 %).
"""

from __future__ import annotations

import argparse
import json
import pathlib
import time
import tomllib

from pice.cli import main as pice
from pice.io.toml_text import toml_text

JOBS = pathlib.Path(__file__).resolve().parents[1] / "jobs"
WIDTHS = {17.3: "17_3", 30.0: "30", 40.0: "40", 60.0: "60", 80.0: "80"}  # Table 2's half models
FULL = {17.3: "17_3_full"}  # and its full model


def _job(width: float, args) -> str:
    """The name of the Table 2 job of ``width`` (the full model's with --full)."""
    return (FULL if args.full else WIDTHS)[width]


def _pice(*args: str) -> None:
    """``pice ARGS`` in this process; stop the sweep, naming the command, when it fails."""
    if pice(list(args)) != 0:
        raise SystemExit(f"keel_width_sweep: `pice {' '.join(args)}` failed (its message is above)")


WIDEST = max(WIDTHS)  # --trim: the one keel generated


def _tag(args, generated: bool = False) -> str:
    """The settings every file name of the sweep carries (so that other settings never mix in); a keel
    trimmed from the widest (--trim) carries "_trim", the widest's own generation does not."""
    trim = "_trim" if args.trim and not generated else ""
    return f"b{args.block_scale:g}_cd{args.form_drag:g}_f{args.fraction:g}_s{args.seed}{trim}"


def sweep_job(width: float, friction: float, args, keel_file: str, name: str) -> dict:
    """Table 2's half-model job of ``width`` with the sweep's changes (module docstring)."""
    job = tomllib.loads((JOBS / f"gong_2017_keel_w{_job(width, args)}.toml").read_text())
    keel, run = job["keel"], job["run"]
    s = args.block_scale
    keel["blocks"]["thickness"] *= s
    keel["blocks"]["length"] = [s * v for v in keel["blocks"]["length"]]
    keel["form_drag_coefficient"] = args.form_drag
    keel["step_fraction"] = args.fraction
    keel["seed"] = args.seed
    keel["file"] = keel_file
    keel["contact"]["friction"] = friction
    if args.trim and width != WIDEST:  # the keel trimmed from the widest's generation (a generation key)
        keel["trim_from"] = f"keel_w{_job(WIDEST, args)}_{_tag(args, generated=True)}.keel.h5"
    keel.pop("end_after_peak", None)  # the records to --past, as documented; --end-after-peak ends them sooner
    if args.end_after_peak is not None:
        keel["end_after_peak"] = args.end_after_peak
    stem_x = 75.0  # the stem at the waterline (the hull is centred on x = 0, 150 m long)
    far_edge = keel["x"] + 0.5 * keel["width"]
    run.update(name=name, duration=float(far_edge - stem_x + args.past), snapshots=5, checkpoint_every=5.0)
    return job


def generate(width: float, args, out: pathlib.Path) -> dict:
    """The keel of ``width`` (generated once); its blocks, porosity and the generation's wall time."""
    from pice.io.keel_file import read_keel
    from pice.job import load_job

    trimmed = args.trim and width != WIDEST
    stem = f"keel_w{_job(width, args)}_{_tag(args, generated=not trimmed)}"
    path = out / f"{stem}.toml"
    job = sweep_job(width, 0.3, args, f"{stem}.keel.h5", stem)
    if trimmed:  # the widest keel first, then this one from its middle
        generate(WIDEST, args, out)
    path.write_text(toml_text(job, header="benchmarks/keel_width_sweep.py: a keel " +
                              ("trimmed from the widest" if trimmed else "generation")))
    took = out / f"{stem}.wall"
    if not (out / f"{stem}.keel.h5").exists():
        t0 = time.perf_counter()
        _pice("keel", str(path))
        took.write_text(repr(time.perf_counter() - t0))
    k = read_keel(out / f"{stem}.keel.h5", load_job(path).keel, str(path))
    return dict(kept=len(k["x"]), released=k["released"], porosity=k["porosity"], core=k["core_porosity"],
                wall=float(took.read_text()) if took.exists() else float("nan"), file=f"{stem}.keel.h5")


def ship_run(width: float, friction: float, args, out: pathlib.Path) -> dict:
    """The half hull through the keel of ``width`` at mu_i = ``friction``: R^p [kN], where [m], the
    work of R [kJ], wall [s] (resumed from its checkpoint when one is there)."""
    from pice.io.run_reader import open_run
    from pice.postproc.resistance import peak_resistance, resistance_record, resistance_work

    name = f"ship_w{_job(width, args)}_{_tag(args)}_mu{friction:g}"
    done = out / f"{name}.json"
    if done.exists():
        return json.loads(done.read_text())
    keel = generate(width, args, out)
    path = out / f"{name}.toml"
    path.write_text(toml_text(sweep_job(width, friction, args, keel["file"], name),
                              header="benchmarks/keel_width_sweep.py: a ship run"))
    checkpoint = out / f"{name}.ckpt.h5"
    t0 = time.perf_counter()
    if checkpoint.exists():
        _pice("run", str(path), "-o", str(out / f"{name}.h5"), "--restart", str(checkpoint))
    else:
        _pice("run", str(path), "-o", str(out / f"{name}.h5"), "--overwrite")
    wall = time.perf_counter() - t0
    with open_run(out / f"{name}.h5") as run:
        delta, r = resistance_record(run)
        dt = float(run.attrs["dt"]) if "dt" in run.attrs else float("nan")
    peak, where = peak_resistance(delta, r)
    work = resistance_work(delta, r)
    result = dict(width=width, friction=friction, dt=dt, peak_kN=peak / 1e3, at_m=where, work_kJ=work / 1e3,
                  delta_end=float(delta[-1]), wall=wall, **{f"keel_{k}": v for k, v in keel.items()})
    done.write_text(json.dumps(result))
    return result


def report(args, out: pathlib.Path) -> None:
    """The table of the runs in ``out`` at these settings (module docstring)."""
    from pice.physics.ridge import malmberg_resistance

    rows, full = {}, {}
    for p in sorted(out.glob(f"ship_w*_{_tag(args)}_mu*.json")):
        r = json.loads(p.read_text())
        (full if "_full_" in p.name else rows)[(r["width"], r["friction"])] = r
    if not rows:
        print(f"no runs at {_tag(args)} in {out}")
        return
    malm = malmberg_resistance(draft=9.5, breadth=22.2, midbody=67.5, waterline_angle_deg=25.2, stem_angle_deg=29.7,
                               keel_depth=5.0).total / 1e3
    print(f"width sweep, half model, blocks x{args.block_scale:g}, form drag C_d {args.form_drag:g}, "
          f"step_fraction {args.fraction:g}, keel seed {args.seed}; Malmberg R_A (ship) {malm:.0f} kN")
    print(f"{'w [m]':>5} {'mu_i':>4} {'blocks':>6} {'poros.':>6} {'R^p [kN]':>8} {'ship':>6} {'at [m]':>6} "
          f"{'/ w17.3':>7} {'/ mu0.3':>7} {'/ R_A':>6} {'work [kJ]':>9} {'wall [s]':>8}")
    for (w, mu), r in sorted(rows.items()):
        narrow = rows.get((17.3, mu))
        low = rows.get((w, 0.3))
        print(f"{w:>5g} {mu:>4g} {r['keel_kept']:>6} {r['keel_porosity']:>6.3f} {r['peak_kN']:>8.1f} "
              f"{2 * r['peak_kN']:>6.0f} {r['at_m']:>6.1f} "
              f"{r['peak_kN'] / narrow['peak_kN'] if narrow else float('nan'):>7.2f} "
              f"{r['peak_kN'] / low['peak_kN'] if low else float('nan'):>7.2f} {2 * r['peak_kN'] / malm:>6.2f} "
              f"{r['work_kJ']:>9.0f} {r['wall']:>8.0f}")
    for (w, mu), r in sorted(full.items()):
        half = rows.get((w, mu))
        ratio = f"{r['peak_kN'] / (2 * half['peak_kN']):.3f}" if half else "(no half model run)"
        print(f"full model, w = {w:g} m, mu_i {mu:g}: {r['keel_kept']} blocks, porosity {r['keel_porosity']:.3f}, "
              f"R^p {r['peak_kN']:.1f} kN at {r['at_m']:.1f} m; over twice the half model's: {ratio} "
              "(seed 002: 1.06-1.10)")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--widths", type=float, nargs="+", default=list(WIDTHS))
    ap.add_argument("--frictions", type=float, nargs="+", default=[0.3, 0.6])
    ap.add_argument("--block-scale", type=float, default=2.0)
    ap.add_argument("--form-drag", type=float, default=0.0)
    ap.add_argument("--fraction", type=float, default=0.2)
    ap.add_argument("--past", type=float, default=30.0)
    ap.add_argument("--end-after-peak", type=float, default=None)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--trim", action="store_true", help="trim the narrower keels from the widest's generation")
    ap.add_argument("--full", action="store_true", help="the full model (w = 17.3 m) instead of the half")
    ap.add_argument("--out", default="runs/keel_width_sweep")
    ap.add_argument("--report", action="store_true", help="print the table of the runs already in --out")
    args = ap.parse_args()
    if args.full and args.trim:
        ap.error("--trim: the full model's keel (l_f = 60 m) is not one of the half models' widths; drop --trim")
    if args.full and args.widths == list(WIDTHS):
        args.widths = list(FULL)
    models = FULL if args.full else WIDTHS
    unknown = [w for w in args.widths if w not in models]
    if unknown:
        ap.error(f"--widths: {unknown} not in Table 2's {'full' if args.full else 'half'} models {list(models)}")
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    if not args.report:
        for w in args.widths:
            for mu in args.frictions:
                ship_run(w, mu, args, out)
    report(args, out)


if __name__ == "__main__":
    main()
