"""The measured windows of pice bench: the benchmark sheet's throughput and the full scene's cost.

Each scene is set up (numba compiles or loads its cache there and in the warm-up steps), warmed up,
then stepped for two windows of the same length on every rank: the first with the plain step (no
clock is read in the step: the throughput and the cost come from it), the second with the timed
step (pice/timers.py: the split of a step into its parts). The two windows follow one another, so
the second starts where the first ended. All functions here are collective.
"""

from __future__ import annotations

import pathlib
from time import perf_counter

import numpy as np


def window(sim, steps: int, *, out=None, every: int = 0) -> dict:
    """Advance ``steps`` steps from a barrier; with ``out`` (io.output.RunOutput) a series row and the
    events every ``every`` steps, as a run writes them. Returns {"wall_s": the slowest rank's wall
    time [s], "rank_s": this rank's, "block_ms": this rank's wall time per step [ms] of each block};
    with timers on, ``sim.timers`` holds the window's split.

    The steps are taken in blocks of the health check's interval (``run.check_every``: a block ends
    with its check, as in a long ``advance``), and the clock is read between blocks only (one read per
    ``check_every`` steps, none in the step). The median block (``block_median``) is the step's cost
    with the rare long pauses left out: a process preempted for milliseconds by another on a shared
    machine stretches the mean of a window, and on several ranks makes every other rank wait for it."""
    comm, timers = sim.comm, sim.timers
    block = max(int(sim.job.run.check_every), 1)
    comm.barrier()
    t0 = perf_counter()
    if timers is not None:
        timers.start()
    left, blocks, last = steps, [], t0
    while left > 0:
        n = min(block, left) if out is None else min(every - sim.c.step % every, block, left)
        sim.advance(n)
        left -= n
        now = perf_counter()
        blocks.append((now - last) / n * 1e3)
        last = now
        if out is not None and sim.c.step % every == 0:
            out.series()
            out.events()
            if timers is not None:
                timers.lap("output")
            last = perf_counter()  # the row's time is not a step's
    mine = perf_counter() - t0
    return {"wall_s": float(comm.max(mine)), "rank_s": mine, "block_ms": blocks}


def block_median(comm, plain: dict) -> float | None:
    """The median over a window's blocks of the slowest rank's wall time per step [ms] (``window``),
    on rank 0 (None elsewhere; collective)."""
    per_rank = comm.gather(np.asarray(plain["block_ms"]))
    if per_rank is None:
        return None
    return float(np.median(np.max(np.stack(per_rank), axis=0)))


def plain_and_timed(sim, steps: int, *, out=None, every: int = 0) -> tuple[dict, dict | None]:
    """The plain window, then the timed one. Returns (plain window, split) where the split is
    StepTimers.summary (rank 0; None elsewhere) with "outside_ms_per_step" (mean over ranks of the
    timed window's wall time per step, read outside the step) and "sum_over_outside" added."""
    plain = window(sim, steps, out=out, every=every)
    timers = sim.enable_timers()
    try:
        timed = window(sim, steps, out=out, every=every)
        split = timers.summary(sim.comm)
    finally:
        sim.disable_timers()
    outside = sim.comm.gather(timed["rank_s"])
    if split is not None:
        mean = sum(outside) / len(outside) / max(steps, 1) * 1e3
        split["outside_ms_per_step"] = mean
        split["sum_over_outside"] = split["ms_per_step"] / mean if mean > 0 else 0.0
    return plain, split


def _elements(sim) -> int:
    return int(sim.comm.sum(sim.p.nlocal))


def measure_sheet(comm, *, steps: int, warmup: int, length: float, width: float, broken: int) -> dict | None:
    """Particle-steps per second of the benchmark sheet (bench/sheet.py) on the ranks of ``comm``,
    and the split of its step. Returns the figures on rank 0, None elsewhere."""
    from .sheet import reference_sheet

    t0 = perf_counter()
    sim, count = reference_sheet(length=length, width=width, broken=broken, comm=comm)
    sim.advance(warmup)
    setup = comm.max(perf_counter() - t0)
    n = _elements(sim)
    bonds = int(comm.sum(sim.p.bond_count()))
    plain, split = plain_and_timed(sim, steps)
    median = block_median(comm, plain)
    if comm.rank != 0:
        return None
    rate = n * steps / plain["wall_s"] if plain["wall_s"] > 0 else 0.0
    return {"scene": f"benchmark sheet: {length:g} m x {width:g} m of 1 m elements, Table 4 bonds, no platform",
            "elements": n, "bonds_intact": bonds, "bonds_broken_before_timing": count,
            "dt": sim.dt, "dt_stable": sim.limit.stable, "setup_and_warmup_s": setup, "warmup_steps": warmup,
            "steps": steps, "wall_s": plain["wall_s"], "ms_per_step": plain["wall_s"] / max(steps, 1) * 1e3,
            "particle_steps_per_second": rate, "particle_steps_per_second_per_rank": rate / comm.size,
            "block_steps": int(sim.job.run.check_every), "median_block_ms_per_step": median,
            "median_block_particle_steps_per_second": n / (median * 1e-3) if median else 0.0,
            "split": split}


def measure_full(comm, job_path: pathlib.Path, *, steps: int, warmup: int, scratch: pathlib.Path,
                 restart=None) -> dict | None:
    """The wall time per simulated second of the job at ``job_path`` as it is written (the reference
    scene: its recommended setting), over a window of ``steps`` steps after ``warmup`` steps, with its
    series rows written at its series_every to the run file ``scratch`` (deleted at the end); the
    projected hours for its whole duration at that rate; the split of its step. ``restart``: a
    checkpoint of the job's run to start from (None: t = 0). Rank 0's figures, None elsewhere."""
    from ..io.output import RunOutput
    from ..job import load_job
    from ..runner import simulation_from_checkpoint
    from ..simulation import Simulation

    job = load_job(job_path)
    t0 = perf_counter()
    if restart is None:
        sim = Simulation(job, base_dir=job_path.parent, comm=comm)
    else:
        sim = simulation_from_checkpoint(job, restart, base_dir=job_path.parent, comm=comm)
    out = RunOutput(sim, str(scratch), job, True)
    every = job.run.series_every
    status = "failed"  # io.output.RunOutput.close: no collective call unless every rank got to the end
    try:
        sim.advance(warmup)
        out.series()  # compiles what the series row needs
        setup = comm.max(perf_counter() - t0)
        start = sim.c.step
        plain, split = plain_and_timed(sim, steps, out=out, every=every)
        status = "finished"
    finally:
        out.close(status)
        if comm.rank == 0:
            scratch.unlink(missing_ok=True)
    d = sim.describe()  # collective; the bodies and lines are rank 0's
    if comm.rank != 0:
        return None
    per_step = plain["wall_s"] / max(steps, 1)  # [s]
    per_sim_s = per_step / sim.dt               # wall [s] per simulated [s]
    n = d["elements"]
    return {"job": str(job_path), "elements": n, "bonds_intact": d["bonds"], "bodies": len(job.bodies),
            "mooring_lines": d.get("mooring_lines", 0), "mooring_nodes": d.get("mooring_nodes", 0),
            "mooring_substeps": d.get("mooring_substeps", 0), "dt": sim.dt, "dt_stable": sim.limit.stable,
            "dt_safety": d["dt_safety"], "duration_s": job.run.duration, "series_every": every,
            "setup_and_warmup_s": setup, "warmup_steps": warmup, "steps": steps,
            "window_start_time_s": start * sim.dt, "wall_s": plain["wall_s"], "ms_per_step": per_step * 1e3,
            "particle_steps_per_second": n / per_step if per_step > 0 else 0.0,
            "wall_s_per_simulated_s": per_sim_s, "projected_hours": per_sim_s * job.run.duration / 3600.0,
            "split": split}
