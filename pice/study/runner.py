"""Running a study: every variant set up and warmed up first (a bad one stops the study before
anything runs), then run one after the other inside this MPI job (run_job is collective: under
``mpiexec -n 2`` every variant runs on 2 ranks); rank 0 then measures each run file
(study/metrics.py) and writes the report (study/report.py).

Cost: ``wall_time`` [s] of the time loop as run_job measures it (set-up excluded; every variant is
set up and stepped twice beforehand, so numba's compile time falls on none of them), from t = 0 over
every call of a variant continued from its checkpoint (a killed or stopped study; NaN when one of its
checkpoints was written by a pice that did not keep the time, ``wall_time_last_call`` then the last
call's), and ``particle_steps`` = (elements + floes + mooring nodes) x steps.
"""

from __future__ import annotations

import json
import math
import pathlib
import signal
import sys
import time

from ..errors import JobError, PiceError, RunInterrupted
from ..io.checkpoint import CheckpointError
from ..io.errors import OutputError
from ..parallel.comm import on_root, world
from ..parallel.ensemble import WorkQueue, split, wait_for_all
from .criteria import judge, parse_criterion
from .metrics import METRICS, compare, run_metrics
from .report import write_report
from .variants import Variant, make_variants, show_value

WARM_UP_STEPS = 2  # steps each variant takes before the runs, to compile the kernels (not timed)


def _preflight(variants: list[Variant], *, out_dir, comm) -> tuple[dict[int, str], dict[int, int]]:
    """Set every variant up and advance it WARM_UP_STEPS (collective), writing nothing: the checks
    that need the built scene (the stability limit of run.dt, overlaps, regions) run here, before
    the first run, and numba has loaded or compiled every kernel before the timed runs. Returns
    ({variant: reason} of those whose set-up was refused: they are recorded as failed, not run;
    {variant: its cost in particle-steps, elements x steps}: the queue's order, largest first)."""
    from ..simulation import Simulation

    refused, cost = {}, {}
    for v in variants:
        try:
            sim = Simulation(v.job.model_copy(update={"source": v.label}), base_dir=out_dir, comm=comm)
            cost[v.index] = int(comm.sum(sim.p.nlocal)) * sim.total_steps
            sim.advance(min(WARM_UP_STEPS, sim.total_steps))
        except PiceError as exc:
            refused[v.index] = str(exc)
    return refused, cost


def _record(v: Variant) -> pathlib.Path:
    """Where a variant's outcome is kept, so that a killed study does not run it again."""
    return v.run.with_suffix(".outcome.json")


def _job_body(text: str) -> str:
    """A variant's job text without its header comment (which names the job file it came from: a
    study moved to another folder, or its job renamed, is the same study)."""
    lines = text.splitlines()
    while lines and lines[0].startswith("#"):
        lines.pop(0)
    return "\n".join(lines)


def _finished(v: Variant) -> dict | None:
    """The outcome of a variant run to its end (or refused) by an earlier call of the same study (its
    job text unchanged but for the header comment, its run file closed as "finished" when it ran),
    else None."""
    import json

    import h5py

    try:
        row = json.loads(_record(v).read_text(encoding="utf-8"))
        if _job_body(row.get("job_text", "")) != _job_body(v.text):
            return None
        if row.get("error") is None:
            with h5py.File(v.run, "r") as f:
                status = f.attrs["status"]
            if (status.decode() if isinstance(status, bytes) else str(status)) != "finished":
                return None
        return row
    except (OSError, ValueError, KeyError):
        return None


def run_study(job_path, specs: list, *, out_dir=None, reference: int | None = None, settle: float = 0.0,
              criteria=(), group_size: int | None = None, progress="stderr", comm=None, keep=None) -> dict | None:
    """Run every variant (collective) and write the report; return the study dict on rank 0, None on
    the others. ``settle`` [s]: offsets are taken over t >= settle. ``criteria``: texts of
    study/criteria.py marking each variant pass or fail. ``group_size``: the ranks split into groups
    of that many (parallel/ensemble.py), each running the variants it takes from rank 0's queue,
    largest first (None: all ranks run every variant in turn). ``keep``: which combinations of the
    specs run (study/variants.make_variants; a phase of a sweep). Bad input raises JobError before
    anything is written or run."""
    progress = sys.stderr if progress == "stderr" else progress  # the stream at the call, not at import
    from ..runner import run_job  # looked up at call time (the simulation is heavy to import)

    comm = comm if comm is not None else world()
    job_path = pathlib.Path(job_path)
    out_dir = pathlib.Path(out_dir) if out_dir else pathlib.Path("runs") / f"{job_path.stem}_study"
    if not settle >= 0.0 or math.isinf(settle):
        raise JobError(f"--settle {settle}: must be a time >= 0 s")
    judged = [parse_criterion(text) for text in criteria]
    try:
        group, colour, ngroups = split(comm, group_size) if group_size is not None else (comm, 0, 1)
    except ValueError as exc:
        raise JobError(str(exc)) from None
    variants = make_variants(job_path, specs, out_dir=out_dir, keep=keep)
    if not variants:
        raise JobError(f"{job_path}: no variant to run (every combination was left out)")
    if reference is not None and reference not in {v.index for v in variants}:
        raise JobError(f"--reference {reference}: must be a variant number 0..{len(variants) - 1}")
    done = comm.bcast({v.index: _finished(v) for v in variants} if comm.rank == 0 else None)
    todo = [v for v in variants if done[v.index] is None]
    refused, cost = _preflight(todo, out_dir=out_dir, comm=comm)
    _on_rank0(comm, lambda: _write_jobs(out_dir, variants), f"{out_dir}: cannot write the variants")
    if comm.rank == 0 and progress is not None:
        for v in variants:
            if done[v.index] is not None:
                print(f"pice study: variant {v.index}: done before ({_record(v).name}), not run again",
                      file=progress, flush=True)
    start = time.perf_counter()
    if ngroups == 1:
        try:
            mine = _run_in_turn(todo, refused, run_job, out_dir=out_dir, comm=comm,
                                progress=progress if comm.rank == 0 else None, count=variants[0].total)
        except RunInterrupted as exc:  # the study's own command continues it, not the run's
            raise RunInterrupted(f"study stopped ({str(exc).split('; ')[0]}); the same command continues each "
                                 "unfinished variant from its checkpoint") from None
    else:
        order = sorted(todo, key=lambda v: (-cost.get(v.index, 0), v.index))
        mine = _run_from_queue(order, refused, run_job, out_dir=out_dir, comm=comm, group=group, colour=colour,
                               progress=progress if group.rank == 0 else None, count=variants[0].total)
    mine, stopped = mine if ngroups > 1 else (mine, None)
    gathered = comm.gather((mine, stopped))
    why = comm.bcast(next((s for _, s in gathered if s), None) if comm.rank == 0 else None)
    if why is not None:  # a stop was asked for: the unfinished variants kept their checkpoints
        raise RunInterrupted(f"study stopped ({why.splitlines()[0]}); the same command continues each unfinished "
                             "variant from its checkpoint")
    gathered = [part for part, _ in gathered] if comm.rank == 0 else None
    elapsed = time.perf_counter() - start
    rows = []
    if comm.rank == 0:
        ran = {row["variant"]: row for part in gathered for row in part}
        rows = [{k: x for k, x in (done[v.index] or ran[v.index]).items() if k != "job_text"} for v in variants]
        busy = busy_fractions(list(ran.values()), ngroups, elapsed)

    def report():
        for row in rows:
            if row["error"] is None:
                row["metrics"] = run_metrics(row["run"], settle=settle)
                row["passed"], row["failed"] = judge(judged, row["metrics"])
            else:
                row["metrics"] = dict.fromkeys((name for name, _, _ in METRICS), math.nan)
                row["passed"], row["failed"] = False, [f"failed: {row['error']}"]
        ref = compare(rows, reference)
        study = dict(job=str(job_path), out_dir=str(out_dir), varied=list(variants[0].values),
                     reference=ref, reference_rule="--reference" if reference is not None else "most particle-steps",
                     loads_on="body 0" if variants[0].job.bodies else "the walls (sum)",
                     settle=settle, units={name: unit for name, unit, _ in METRICS}, variants=rows,
                     criteria=[str(c) for c in judged], busy=busy)
        study["files"] = [str(p) for p in write_report(study, out_dir)]
        return study

    return _on_rank0(comm, report, f"{out_dir}: cannot write the study report")


def busy_fractions(rows: list[dict], ngroups: int, elapsed: float) -> dict:
    """How busy the ranks were while this call ran its variants: each group's time in its variants
    (set-up included, ``busy_time``) over the study's elapsed wall time [s], and their mean."""
    per = [0.0] * ngroups
    for row in rows:
        per[row.get("group", 0)] += row.get("busy_time", 0.0)
    frac = [b / elapsed if elapsed > 0 else 0.0 for b in per]
    return dict(elapsed=elapsed, groups=frac, overall=sum(frac) / ngroups)


def _run_in_turn(todo, refused, run_job, *, out_dir, comm, progress, count) -> list[dict]:
    """Every variant on all the ranks, one after the other; rank 0 records each outcome."""
    rows = []
    for v in todo:
        row = _run_variant(v, refused.get(v.index), run_job, out_dir=out_dir, progress=progress, comm=comm,
                           count=count)
        _on_rank0(comm, lambda: _record(v).write_text(json.dumps(row), encoding="utf-8"),
                  f"{out_dir}: cannot record variant {v.index}")
        rows.append(row)
    return rows if comm.rank == 0 else []


def _run_from_queue(order, refused, run_job, *, out_dir, comm, group, colour, progress, count):
    """Each group takes the next variant of ``order`` from rank 0's queue until none is left; its
    leader records the outcome and keeps the row. Returns (rows, why the study was stopped or None).

    SIGINT/SIGTERM: a running variant writes its checkpoint and stops (run_job), and its group takes
    no other; a rank between variants takes no other either (this function's handler, which a run
    replaces while it runs). Every rank then waits for the others without spinning, so that the
    ranks still writing their checkpoints are not killed by an idle rank's exit."""
    queue = WorkQueue(comm)
    rows, stopped = [], None
    stop = _Stop().install()
    try:
        while not group.max(1.0 if stop.flag else 0.0):
            k = group.bcast(queue.take() if group.rank == 0 else None)
            if k >= len(order):
                break
            v = order[k]
            try:
                row = _run_variant(v, refused.get(v.index), run_job, out_dir=out_dir, progress=progress, comm=group,
                                   count=count, label=f"group {colour}: ", poll=queue.serve)
            except RunInterrupted as exc:
                stopped = str(exc)
                break
            row["group"] = colour
            if group.rank == 0:
                try:
                    _record(v).write_text(json.dumps(row), encoding="utf-8")
                except OSError as exc:  # the study goes on; only its restart would run this variant again
                    print(f"pice study: cannot record variant {v.index} ({exc.strerror or exc})", file=sys.stderr)
                rows.append(row)
        if stop.flag and stopped is None:
            stopped = "SIGINT/SIGTERM between variants"
        wait_for_all(comm, queue.serve)
    finally:
        stop.restore()
    queue.free()
    return rows, stopped


class _Stop:
    """A rank between variants of a grouped study: SIGINT/SIGTERM set a flag instead of killing it."""

    def __init__(self):
        self.flag, self.previous = False, {}

    def install(self) -> "_Stop":
        try:
            for sig in (signal.SIGINT, signal.SIGTERM):
                self.previous[sig] = signal.signal(sig, self._handler)
        except ValueError:  # not the main thread: no handler
            self.previous.clear()
        return self

    def _handler(self, signum, frame):
        self.flag = True

    def restore(self) -> None:
        for sig, handler in self.previous.items():
            signal.signal(sig, handler)
        self.previous = {}


def _checkpoint_of(v: Variant) -> str | None:
    """The checkpoint an unfinished run of the variant left (a killed study), to continue from."""
    from ..io.checkpoint import default_path

    ckpt = default_path(v.run)
    return str(ckpt) if ckpt.exists() and v.run.exists() else None


def _run_variant(v: Variant, refused: str | None, run_job, *, out_dir, progress, comm, count: int,
                 label: str = "", poll=None) -> dict:
    """Run one variant (collective); its row, with ``error`` the reason when its set-up was refused or
    its run stopped (a refused step, a blow-up, a bad geometry): the study goes on."""
    row = dict(variant=v.index, values=v.values, toml=str(v.toml), run=str(v.run), job_text=v.text, error=refused,
               wall_time=0.0, steps=0, elements=0, particle_steps=0, particle_steps_per_second=0.0, ranks=comm.size)
    if progress is not None:
        print(f"pice study: {label}variant {v.index} of 0..{count - 1}: "
              + ", ".join(f"{k} = {show_value(v.values[k])}" for k in (v.shown or v.values)) + f" -> {v.run}"
              + (f": refused at set-up: {refused}" if refused else ""), file=progress, flush=True)
    if refused:
        return row
    resume = comm.bcast(_checkpoint_of(v) if comm.rank == 0 else None)
    began = time.perf_counter()
    row["began"] = time.time()  # [s] since the epoch: the groups' timeline
    try:
        if resume is not None:
            if progress is not None:
                print(f"pice study: {label}variant {v.index}: continued from its checkpoint {resume}",
                      file=progress, flush=True)
            try:
                summary = run_job(v.job, output=str(v.run), base_dir=out_dir, progress=progress, comm=comm,
                                  restart=resume, poll=poll)
            except CheckpointError as exc:  # another job wrote it (the study changed): start afresh
                if progress is not None:
                    print(f"pice study: {label}variant {v.index}: its checkpoint does not fit ({exc}); run from "
                          "the start", file=progress, flush=True)
                resume = None
        if resume is None:
            summary = run_job(v.job, output=str(v.run), overwrite=True, base_dir=out_dir, progress=progress,
                              comm=comm, poll=poll)
    except RunInterrupted:  # asked to stop: not an outcome (the variant continues from its checkpoint)
        raise
    except (PiceError, FloatingPointError) as exc:  # every rank raises it (the checks are collective)
        row["error"] = str(exc).splitlines()[0]
        row["busy_time"] = time.perf_counter() - began
        row["ended"] = time.time()
        if progress is not None:
            print(f"pice study: variant {v.index} failed: {row['error']}", file=progress, flush=True)
        return row
    particles = summary["elements"] + summary.get("floes", 0) + summary.get("mooring_node_updates", 0)
    row.update(busy_time=time.perf_counter() - began, ended=time.time(), wall_time=summary["wall_time_total"],
               wall_time_last_call=summary["wall_time"], steps=summary["steps"], elements=summary["elements"],
               floes=summary.get("floes", 0), particle_steps=particles * summary["steps"],
               particle_steps_per_second=particles * summary["steps_run"] / max(summary["wall_time"], 1e-9),
               ranks=summary["ranks"])
    return row


def _write_jobs(out_dir: pathlib.Path, variants: list[Variant]) -> None:
    out_dir.mkdir(parents=True, exist_ok=True)
    for v in variants:
        v.toml.write_text(v.text, encoding="utf-8")


def _on_rank0(comm, work, what: str):
    """``work()`` on rank 0 (parallel.comm.on_root); an OSError there is an OutputError saying
    ``what`` failed, raised on every rank like any PiceError."""

    def translate(exc):
        if isinstance(exc, OSError):
            return OutputError(f"{what} ({exc.strerror or exc}); choose another folder with --out DIR")
        return None

    return on_root(comm, work, translate=translate)
