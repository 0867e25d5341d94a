"""`pice study`: run variants of one job and weigh their cost against what designers read off them.

``pice study jobs/x.toml --vary run.dt=1e-4,2e-4 --vary ice.element_diameter=1.0,2.0`` makes the
Cartesian product of the values (4 variants) and validates every one, including the set-up checks
that need the built scene (the stability limit of run.dt), before anything runs. Each variant is
written as ``<out>/x_<k>.toml`` (a job you can run again; its run.output is ``<out>/x_<k>.h5``) and
run to ``<out>/x_<k>.h5``, one after the other inside this MPI job. Rank 0 then reads the metrics
of each run file (peak ice loads [N], offsets [m], fairlead tension [N]), compares them with the
reference variant (by default the finest: the most particle-steps) and writes the report.

One module per step; each imports only modules listed above it (no import circle):

    variants.py   --vary parsed and checked against the job; every combination as a job of its own
    metrics.py    the metrics of one run file (io/run_reader.py) and their change against the reference
    criteria.py   --criterion "max_pitch_deg < 15": each variant marked pass or fail
    plot.py       the figure: each metric's change against the wall time of each variant
    report.py     the printed table, study.csv, study.json and study.png
    runner.py     run_study: set every variant up, run them, measure them, write the report
    sweep.py      a sweep file: designs through phases, each running those the last one passed
    command.py    the `pice study` command line (imported by pice/cli.py; imports the rest when run)
"""

__all__ = ["run_study"]


def __getattr__(name):  # run_study imported on first use: `pice --help` does not load the simulation
    if name == "run_study":
        from .runner import run_study

        return run_study
    raise AttributeError(name)
