"""Command line: ``pice run | check``. Heavy modules are imported inside each subcommand."""

from __future__ import annotations

import argparse
import pathlib
import sys


def _cmd_run(args) -> int:
    from .job import load_job
    from .runner import run_job

    job = load_job(args.job)
    out = args.output or job.run.output or str(pathlib.Path("runs") / (pathlib.Path(args.job).stem + ".h5"))
    summary = run_job(job, output=out, overwrite=args.overwrite, base_dir=pathlib.Path(args.job).parent)
    if summary["rank"] == 0:
        print(f"pice: wrote {summary['output']}: {summary['steps']} steps to t = {summary['time']:.4g} s in "
              f"{summary['wall_time']:.1f} s wall ({summary['particle_steps_per_second']:.3g} particle-steps/s), "
              f"{summary['broken_bonds']} broken bonds, {summary['ranks']} rank(s)")
    return 0


def _cmd_check(args) -> int:
    import time

    from .job import load_job
    from .simulation import Simulation

    job = load_job(args.job)
    sim = Simulation(job, base_dir=pathlib.Path(args.job).parent)
    d = sim.describe()
    sim.advance(3)  # compile and warm up
    probe = max(10, min(200, int(2e6 // max(d["elements"], 1))))
    t0 = time.perf_counter()
    sim.advance(probe)
    per_step = (time.perf_counter() - t0) / probe
    wall_per_s = per_step * d["steps_per_second"]
    mb = d["memory_bytes"] / 2**20
    print(f"{args.job}: valid")
    print(f"  elements          {d['elements']:,} in {d['layers']} layer(s), modelled thickness "
          f"{d['thickness_modelled']:.3g} m")
    print(f"  bonds             {d['bonds']:,}")
    print(f"  memory (particles) {mb:,.1f} MiB")
    print(f"  stable time step  {d['dt_stable']:.4g} s ({d['dt_governed_by']})")
    print(f"  chosen time step  {d['dt']:.4g} s ({d['dt_safety']:.2g} x the limit)")
    print(f"  steps per sim. s  {d['steps_per_second']:,.0f}")
    print(f"  bond springs      k_n {d['bond_kn']:.4g} N/m, k_s {d['bond_ks']:.4g} N/m, "
          f"k_bend {d['bond_kb']:.4g} N m/rad, k_twist {d['bond_kt']:.4g} N m/rad")
    print(f"  bond strength     normal {d['normal_strength']:.4g} Pa, shear {d['shear_strength']:.4g} Pa, "
          f"friction {d['bond_friction']:.3g}")
    print(f"  wall time / sim. s {wall_per_s:,.1f} s on this machine, 1 rank (probe of {probe} steps: "
          f"{d['elements'] / per_step:,.3g} particle-steps/s); the {job.run.duration:g} s job: "
          f"~{wall_per_s * job.run.duration:,.0f} s")
    return 0


def build_parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(prog="pice", description="DEM of sea ice acting on moored floating structures")
    sub = ap.add_subparsers(dest="command", required=True)
    r = sub.add_parser("run", help="run a TOML job and write one HDF5 run file")
    r.add_argument("job")
    r.add_argument("-o", "--output", help="run file (default: run.output of the job, else runs/<job>.h5)")
    r.add_argument("--overwrite", action="store_true", help="replace an existing run file")
    r.set_defaults(func=_cmd_run)
    c = sub.add_parser("check", help="validate a job and print its size, time step and estimated cost")
    c.add_argument("job")
    c.set_defaults(func=_cmd_check)
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
            print(f"pice: error: {exc}" if not hasattr(exc, "lines") else str(exc), file=sys.stderr)
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
