"""The `pice study` command line: its arguments and its handler (kept out of pice/cli.py, which
imports this module only; the study's machinery is imported when the command runs)."""

from __future__ import annotations

import pathlib

from ..errors import JobError


def add_study_parser(sub) -> None:
    """The `pice study` subcommand's arguments."""
    st = sub.add_parser("study", help="run variants of a job (--vary KEY=v1,v2,...) and compare their cost with "
                                      "their peak loads, offsets and line tensions; or run a sweep file's phases")
    st.add_argument("job", help="a job, or a sweep file ([study] table: designs, phases, criteria)")
    st.add_argument("--vary", action="append", metavar="KEY=V1,V2,...",
                    help="a key of the job as the TOML file writes it (run.dt, ice.element_diameter, "
                         "moorings[0].element_length) and its values; several --vary: every combination")
    st.add_argument("--out", metavar="DIR", help="folder of the variants' jobs and runs and the report "
                                                 "(default runs/<job>_study/)")
    st.add_argument("--reference", type=int, metavar="K",
                    help="compare with variant K (default: the finest, the most particle-steps)")
    st.add_argument("--settle", type=float, default=0.0, metavar="SECONDS",
                    help="offsets over t >= SECONDS only (default 0)")
    st.add_argument("--group-size", type=int, metavar="G",
                    help="split the ranks into groups of G that run different variants side by side, taking "
                         "them from a queue on rank 0, largest first (default: every variant on all ranks)")
    st.add_argument("--criterion", action="append", metavar="\"METRIC OP NUMBER\"",
                    help="mark each variant pass or fail, e.g. \"max_pitch_deg < 15\" (metrics named as the "
                         "CSV's columns, with their unit); several: all must hold")
    st.set_defaults(func=study_command)


def study_command(args) -> int:
    """`pice study`: a job's variants (--vary), or a sweep file's phases (study/sweep.py)."""
    from .report import study_table
    from .runner import run_study
    from .sweep import is_sweep_file, run_sweep, sweep_table

    if is_sweep_file(args.job):
        given = [o for o, x in (("--vary", args.vary), ("--criterion", args.criterion), ("--reference", args.reference),
                                ("--settle", args.settle or None)) if x]
        if given:
            raise JobError(f"{args.job}: a sweep file sets its own designs, phases and criteria: drop {given[0]}")
        summary = run_sweep(args.job, out_dir=args.out, group_size=args.group_size)
        if summary is not None:  # rank 0
            print("\n".join(sweep_table(summary)))
            print(f"pice: wrote sweep.csv, sweep.json and each phase's study in {summary['out_dir']}")
        return 0
    if not args.vary:
        raise JobError(f"{args.job}: give the values to vary, e.g. --vary run.dt=1e-4,2e-4 (or a sweep file, "
                       "docs/buoy_design.md)")
    study = run_study(args.job, args.vary, out_dir=args.out, reference=args.reference, settle=args.settle,
                      criteria=args.criterion or (), group_size=args.group_size)
    if study is not None:  # rank 0
        print("\n".join(study_table(study)))
        print(f"pice: wrote {len(study['variants'])} run(s) and " + ", ".join(pathlib.Path(p).name for p in study["files"])
              + f" in {study['out_dir']}")
    return 0
