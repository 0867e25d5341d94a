"""Command line: ``pice run | keel | check | export | plot | study | lab | bench``; each imports its heavy modules."""

from __future__ import annotations

import argparse
import math
import pathlib
import sys

from .study.command import add_study_parser


def _cmd_run(args) -> int:
    from .job import load_job
    from .runner import run_job

    job = load_job(args.job)
    out = args.output or job.run.output or str(pathlib.Path("runs") / (pathlib.Path(args.job).stem + ".h5"))
    summary = run_job(job, output=out, overwrite=args.overwrite, base_dir=pathlib.Path(args.job).parent,
                      restart=args.restart)
    if summary["rank"] == 0:
        print("\n".join(_summary_lines(summary, job)))
    return 0


def _over_calls(summary: dict) -> str:
    """The run's time over all its calls, when this call continued it from a checkpoint."""
    if summary.get("steps_run", summary["steps"]) == summary["steps"]:
        return ""
    total = summary.get("wall_time_total", float("nan"))
    if total != total:
        return "; this call only (the run continued from a checkpoint that did not keep the time before it)"
    return f"; {total:.1f} s to t = {summary['time']:.4g} s over the run's calls from checkpoints"


def _summary_lines(summary: dict, job) -> list[str]:
    """The end-of-run block: output, steps, wall time and throughput, broken bonds, peak wall loads."""
    out = pathlib.Path(summary["output"])
    xdmf = out.with_suffix(".xdmf")
    lines = [f"pice: wrote {out}" + (f" (ParaView: {xdmf})" if xdmf.is_file() else ""),
             f"  simulated     {summary['steps']:,} steps to t = {summary['time']:.4g} s, "
             f"{summary['elements']:,} elements" + (f", {summary['floes']:,} floes" if summary.get("floes") else "")
             + f", {summary['ranks']} rank(s)",
             f"  wall time     {summary['wall_time']:.1f} s, "
             + (f"{summary['particle_steps_per_second']:.3g} particle-steps/s" if summary["elements"] else
                f"{summary.get('floe_steps_per_second', 0.0):.3g} floe-steps/s" if summary.get("floes") else
                f"{summary.get('steps_run', summary['steps']) / max(summary['wall_time'], 1e-9):.3g} steps/s")
             + _over_calls(summary)]
    if summary["elements"]:
        lines.append(f"  broken bonds  {summary['broken_bonds']:,}")
    import numpy as np

    from .io.errors import RunFileError
    from .io.run_reader import open_run

    try:  # peak loads from the recorded series rows
        with open_run(out) as run:
            force, time = run.series("wall_force"), run.series("time")
    except (RunFileError, OSError):
        return lines
    if force is not None and time is not None and force.size and len(time) == len(force):
        mag = np.linalg.norm(force, axis=2)
        names = [w.name or f"wall{k}" for k, w in enumerate(job.walls)]
        for k in range(mag.shape[1]):
            i = int(np.argmax(mag[:, k]))
            name = names[k] if k < len(names) else f"wall{k}"
            lines.append(f"  peak |F| on {name}: {mag[i, k] / 1e3:,.4g} kN at t = {time[i]:.4g} s")
    return lines


def _cmd_keel(args) -> int:
    from .job import load_job
    from .runner import make_keel

    s = make_keel(load_job(args.job), output=args.output, base_dir=pathlib.Path(args.job).parent)
    if s["rank"] == 0:
        print(s["line"])
    return 0


def _cmd_check(args) -> int:
    from .check import check_job

    return check_job(args.job)


def _cmd_export(args) -> int:
    if not args.vtk and not args.xdmf:
        print("pice export: give --vtk DIR (VTK files and a .pvd) and/or --xdmf (an XDMF file beside the run)",
              file=sys.stderr)
        return 2
    if args.xdmf:
        from .io.xdmf import write_xdmf

        print(f"pice: wrote {write_xdmf(args.run)}")  # RunFileError for a missing or unreadable run file
    if args.vtk:
        from .io.vtk_export import export_vtk

        result = export_vtk(args.run, args.vtk)
        print(f"pice: wrote {len(result['files'])} .vtu files and {result['pvd']} (open it in ParaView)")
    return 0


def _cmd_plot(args) -> int:
    from .io.run_reader import open_run
    from .postproc.plots import default_out_dir, plot_run

    out = pathlib.Path(args.out) if args.out else default_out_dir(args.run)
    written = plot_run(args.run, out, skip=args.skip, baseline=args.baseline)  # a bad run file stops here
    if not args.no_render:
        with open_run(args.run) as run:
            has_snapshots = bool(run.snapshots)
        if has_snapshots:
            from .postproc.render import render_snapshot

            written.append(render_snapshot(args.run, out / f"render_{args.color_by}.png", snapshot=args.snapshot,
                                           color_by=args.color_by))
        else:
            print(f"pice: {args.run} holds no snapshots: nothing to render", file=sys.stderr)
    print(f"pice: wrote {len(written)} PNG file(s) in {out}: " + ", ".join(p.name for p in written))
    return 0


def _cmd_lab(args) -> int:
    import os

    from .log import launch_rank

    if launch_rank() != 0:  # the specimens are small: rank 0 runs them alone, without MPI
        return 0
    ranks = next((int(os.environ[v]) for v in ("PMI_SIZE", "OMPI_COMM_WORLD_SIZE") if v in os.environ), 1)
    if ranks > 1:
        print(f"pice lab: runs on rank 0 only (the specimens are small); the other {ranks - 1} rank(s) idle",
              file=sys.stderr)
    from dataclasses import replace

    from .job import load_job
    from .lab import QUICK_SIZES, LabSizes, run_lab
    from .lab.report import report_lines, write_json

    job = load_job(args.job)
    sizes = QUICK_SIZES if args.quick else LabSizes()
    given = {k: getattr(args, k) for k in ("block_length", "block_width", "beam_span", "beam_width",
                                           "cantilever_length", "clamp_length") if getattr(args, k) is not None}
    lab = run_lab(job, element_sizes=args.element_size, sizes=replace(sizes, **given), periods=args.periods,
                  tests=args.tests, quick=args.quick)
    print("\n".join(report_lines(lab)))
    out = args.json or str(pathlib.Path("runs") / (pathlib.Path(args.job).stem + "_lab.json"))
    print(f"pice: wrote {write_json(lab, out)}")
    return 0


def _cmd_bench(args) -> int:
    from .bench import run_bench
    from .bench.report import report_lines

    sheet = {k: getattr(args, k) for k in ("length", "width", "broken") if getattr(args, k) is not None}
    result = run_bench(scene=args.scene, steps=args.steps, warmup=args.warmup, job=args.job, json_path=args.json,
                       restart=args.restart, **sheet)
    if result is not None:  # rank 0
        print("\n".join(report_lines(result)))
        print(f"pice: wrote {result['json']}")
    return 0


def _count(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise argparse.ArgumentTypeError(f"{text!r}: must be a whole number >= 1")
    return value


def _add_bench_parser(sub) -> None:
    b = sub.add_parser("bench", help="measure the speed on this machine (the 92k sheet's particle-steps/s, the "
                                     "full reference scene's wall time per simulated second, the split of a step) "
                                     "and write it as JSON with the machine, commit and settings")
    b.add_argument("--scene", choices=("sheet", "full", "both"), default="both",
                   help="the benchmark sheet, the full reference scene, or both (default)")
    b.add_argument("--steps", type=_count, default=500, metavar="N",
                   help="steps in each measured window (default 500; there are two per scene: plain and timed)")
    b.add_argument("--warmup", type=_count, default=20, metavar="N",
                   help="steps before the windows, after set-up (default 20): numba compiled, caches warm")
    b.add_argument("--json", metavar="PATH", help="results as JSON (default runs/bench_<commit>_<R>ranks.json)")
    b.add_argument("--job", metavar="PATH", help="the full scene's job (default jobs/zhu_ji_2022_semisub.toml)")
    b.add_argument("--restart", metavar="CHECKPOINT",
                   help="start the full scene's window from this checkpoint of its job (a run's later phase: "
                        "fracture, crushing), not from t = 0")
    b.add_argument("--length", type=_positive, metavar="M", help="the sheet's length [m] (default 400)")
    b.add_argument("--width", type=_positive, metavar="M", help="the sheet's width [m] (default 200)")
    b.add_argument("--broken", type=int, metavar="N",
                   help="bonds of the sheet broken at random before timing (default 300)")
    b.set_defaults(func=_cmd_bench)


def _lab_size(text: str):
    from .lab.specimens import parse_size

    try:
        return parse_size(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def _lab_tests(text: str) -> tuple:
    from .lab import TESTS

    names = tuple(t.strip().replace("-", "_") for t in text.split(",") if t.strip())
    bad = [t for t in names if t not in TESTS]
    if bad or not names:
        raise argparse.ArgumentTypeError(f"{text!r}: a comma-separated list of {', '.join(TESTS)}")
    return names


def _positive(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not value > 0 or value == math.inf:
        raise argparse.ArgumentTypeError(f"{text!r}: must be a positive number")
    return value


def _add_lab_parser(sub) -> None:
    la = sub.add_parser("lab", help="virtual ice lab: measure E, nu, sigma_c (compression), EI and sigma_f "
                                    "(three-point beam, cantilever) of the job's ice, beside the intended values")
    la.add_argument("job")
    la.add_argument("--element-size", type=_positive, action="append", metavar="D",
                    help="element size [m] to test (repeat for several; default the job's ice.element_diameter)")
    la.add_argument("--tests", type=_lab_tests, default=("compression", "three_point", "cantilever"),
                    metavar="LIST", help="comma-separated: compression, three_point, cantilever (default all)")
    la.add_argument("--json", metavar="PATH", help="results as JSON (default runs/<job>_lab.json)")
    la.add_argument("--periods", type=_positive, metavar="N",
                    help="loading time to the intended strength in fundamental periods of the specimen "
                         "(default 5, --quick 3): slower is more quasi-static")
    la.add_argument("--quick", action="store_true", help="smaller specimens and faster loading (seconds; for tests)")
    sizes = la.add_argument_group("specimen sizes", "a length in metres (15 or 15m), thicknesses (20h) or element "
                                                    "spacings (12d); widths are rounded to whole rows")
    for flag, what, default in (("--block-length", "compression block, platen to platen", "10h"),
                                ("--block-width", "compression block", "5.2h"),
                                ("--beam-span", "three-point beam, support to support", "20h"),
                                ("--beam-width", "three-point beam and cantilever", "5.2h"),
                                ("--cantilever-length", "cantilever, clamp face to tip", "10h"),
                                ("--clamp-length", "cantilever's clamped root block", "2h")):
        sizes.add_argument(flag, type=_lab_size, metavar="SIZE", help=f"{what} (default {default}; --quick: "
                           "block 6h, span 10h, cantilever 6h)")
    la.set_defaults(func=_cmd_lab)


def build_parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(prog="pice", description="DEM of sea ice acting on moored floating structures")
    sub = ap.add_subparsers(dest="command", required=True)
    r = sub.add_parser("run", help="run a TOML job and write one HDF5 run file")
    r.add_argument("job")
    r.add_argument("-o", "--output", help="run file (default: run.output of the job, else runs/<job>.h5)")
    r.add_argument("--overwrite", action="store_true", help="replace an existing run file")
    r.add_argument("--restart", metavar="CHECKPOINT",
                   help="continue from a checkpoint (run.checkpoint, default <run>.ckpt.h5): the run file is "
                        "continued from the checkpoint's step; any rank count")
    r.set_defaults(func=_cmd_run)
    c = sub.add_parser("check", help="validate a job and print its size, time step and estimated cost")
    c.add_argument("job")
    c.set_defaults(func=_cmd_check)
    k = sub.add_parser("keel", help="generate a job's [keel]: settle its blocks under the cover, trim, write the file")
    k.add_argument("job")
    k.add_argument("-o", "--output", help="keel file (default: keel.file, else <job>.keel.h5 beside the job)")
    k.set_defaults(func=_cmd_keel)
    e = sub.add_parser("export", help="write VTK (.vtu per snapshot, walls, .pvd) or XDMF for a run file")
    e.add_argument("run", help="the .h5 run file")
    e.add_argument("--vtk", metavar="DIR", help="folder for the .vtu files and the .pvd collection")
    e.add_argument("--xdmf", action="store_true", help="(re)write <run>.xdmf beside the run file")
    e.set_defaults(func=_cmd_export)
    pl = sub.add_parser("plot", help="PNG figures of a run (ice loads, energies, broken bonds) and a render")
    pl.add_argument("run", help="the .h5 run file")
    pl.add_argument("--out", metavar="DIR", help="output folder (default <run>_plots/ beside the run file)")
    pl.add_argument("--snapshot", type=int, default=-1, help="snapshot index to render (default -1, the last)")
    pl.add_argument("--color-by", choices=("velocity", "damage"), default="velocity",
                    help="colour of the rendered spheres (default velocity)")
    pl.add_argument("--no-render", action="store_true", help="figures only, no pyvista render")
    pl.add_argument("--skip", type=float, default=0.0, metavar="SECONDS",
                    help="leave out the first SECONDS of the mooring load's spectrum and ice events (seed 003: 1500)")
    pl.add_argument("--baseline", metavar="RUN", help="a run of the same scene without ice: its mooring load is "
                    "subtracted, leaving the ice-induced load (seed 003: 'direct current and wave loads excluded')")
    pl.set_defaults(func=_cmd_plot)
    add_study_parser(sub)
    _add_lab_parser(sub)
    _add_bench_parser(sub)
    return ap


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    from .errors import PiceError
    from .log import configure

    configure()

    try:
        return args.func(args)
    except PiceError as exc:  # raised on every rank alike (checks are collective): rank 0 reports
        from .log import launch_rank

        if launch_rank() == 0:
            from .errors import RunInterrupted

            what = "" if isinstance(exc, RunInterrupted) else "error: "
            print(f"pice: {what}{exc}" if not hasattr(exc, "lines") else str(exc), file=sys.stderr)
        if getattr(exc, "hard_exit", False):  # HDF5 crashes at exit after a failed write (see OutputError)
            import os

            from .parallel.comm import settle_all

            sys.stdout.flush()
            sys.stderr.flush()
            settle_all()
            os._exit(exc.exit_code)
        return exc.exit_code
    except KeyboardInterrupt:
        print("pice: interrupted; the run file keeps every row written so far", file=sys.stderr)
        return 130
    except Exception:  # a bug: show it, and under MPI take the other ranks down with this one
        import traceback

        from .parallel.comm import abort_all

        traceback.print_exc()
        sys.stderr.flush()
        abort_all(1)
        return 1


if __name__ == "__main__":
    sys.exit(main())
