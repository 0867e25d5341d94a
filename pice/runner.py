"""Run a job to the end: the time loop with its output schedule and progress line."""

from __future__ import annotations

import sys
import time as wall

from .errors import InstabilityError
from .io.run_file import RunFile
from .simulation import Simulation


def snapshot_steps(total_steps: int, count: int) -> set[int]:
    """Steps at which to write snapshots: ``count`` evenly spaced, first and last included."""
    if count <= 0:
        return set()
    if count == 1:
        return {total_steps}
    return {round(k * total_steps / (count - 1)) for k in range(count)}


def run_job(job, *, output, overwrite: bool = False, base_dir=None, progress=sys.stderr) -> dict:
    """Run ``job`` and write ``output``; return a summary. Raises PiceError subclasses on failure.

    The run file is created only after the job has been set up (so bad input writes nothing), and it
    is closed with its status whatever happens, keeping every row already written.
    """
    sim = Simulation(job, base_dir=base_dir)
    total = sim.total_steps
    snaps = snapshot_steps(total, job.run.snapshots)
    every = job.run.series_every
    out = RunFile(output, job=job, overwrite=overwrite, extra_attrs={"dt": sim.dt, "dt_stable": sim.limit.stable})
    status = "failed"
    t0 = wall.perf_counter()
    last_report = t0
    written_events = 0
    snap_index = 0
    try:
        out.append_series(sim.series_row())
        if 0 in snaps:
            out.write_snapshot(snap_index, time=0.0, step=0, particles=sim.p)
            snap_index += 1
        while sim.c.step < total:
            n = min(every - sim.c.step % every, total - sim.c.step)
            nxt = [s for s in snaps if sim.c.step < s <= sim.c.step + n]
            if nxt:
                n = min(nxt) - sim.c.step
            sim.advance(n)
            if sim.c.step % every == 0 or sim.c.step == total:
                out.append_series(sim.series_row())
                out.append_events(sim.c.events[written_events:])
                written_events = len(sim.c.events)
            if sim.c.step in snaps:
                out.write_snapshot(snap_index, time=sim.c.time, step=sim.c.step, particles=sim.p)
                snap_index += 1
            if job.run.stop_at_first_break and sim.c.broken:
                out.append_series(sim.series_row())
                out.append_events(sim.c.events[written_events:])
                written_events = len(sim.c.events)
                out.write_snapshot(snap_index, time=sim.c.time, step=sim.c.step, particles=sim.p)
                break
            now = wall.perf_counter()
            if progress is not None and now - last_report > 5.0:
                rate = sim.c.step / (now - t0)
                eta = (total - sim.c.step) / rate if rate > 0 else float("inf")
                print(f"pice: t = {sim.c.time:.3f} / {job.run.duration:g} s, {rate:.0f} steps/s, "
                      f"ETA {eta:.0f} s, broken bonds {sim.c.broken}", file=progress, flush=True)
                last_report = now
        status = "finished"
    except InstabilityError as exc:
        status = f"stopped: {exc}"
        raise
    except KeyboardInterrupt:
        status = "interrupted"
        raise
    finally:
        out.append_events(sim.c.events[written_events:])
        out.close(status)
    elapsed = wall.perf_counter() - t0
    return dict(output=str(output), steps=sim.c.step, time=sim.c.time, wall_time=elapsed,
                particle_steps_per_second=sim.p.n * sim.c.step / max(elapsed, 1e-9),
                broken_bonds=sim.c.broken, elements=sim.p.n)
