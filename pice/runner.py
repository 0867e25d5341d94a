"""Run a job to the end: the time loop with its output schedule and progress line.

Under MPI every rank steps its part of the ice; rank 0 writes the run file from reduced series rows
and gathered snapshots (a parallel writer joins in the output issue).
"""

from __future__ import annotations

import sys
import time as wall

import numpy as np

from .errors import InstabilityError, PiceError
from .io.run_file import RunFile
from .simulation import Simulation


def snapshot_steps(total_steps: int, count: int) -> set[int]:
    """Steps at which to write snapshots: ``count`` evenly spaced, first and last included."""
    if count <= 0:
        return set()
    if count == 1:
        return {total_steps}
    return {round(k * total_steps / (count - 1)) for k in range(count)}


class _Output:
    """Rank 0 owns the RunFile; every rank takes part in the gathers."""

    def __init__(self, sim, output, job, overwrite):
        self.sim, self.comm = sim, sim.comm
        self.file = None
        error = None
        if self.comm.rank == 0:
            try:
                self.file = RunFile(output, job=job, overwrite=overwrite, ranks=self.comm.size,
                                    extra_attrs={"dt": sim.dt, "dt_stable": sim.limit.stable})
            except PiceError as exc:
                error = exc
        error = self.comm.bcast(error)
        if error is not None:
            raise error
        self.events_written = 0

    def series(self):
        row = self.sim.series_row()  # collective
        if self.file:
            self.file.append_series(row)

    def events(self):
        new = self.sim.c.events[self.events_written:]
        self.events_written = len(self.sim.c.events)
        gathered = self.comm.gather(new)
        if self.file:
            merged = sorted(e for part in gathered for e in part)
            self.file.append_events(merged)

    def snapshot(self, index):
        self.sim.sync()
        p = self.sim.p
        n = p.nlocal
        part = dict(gid=p.gid[:n].copy(), x=p.x[:n].copy(), v=p.v[:n].copy(), w=p.w[:n].copy(),
                    radius=p.radius[:n].copy(), kind=p.kind[:n].copy(), bonds=p.intact_bonds())
        parts = self.comm.gather(part)
        if self.file:
            self.file.write_snapshot_arrays(index, time=self.sim.c.time, step=self.sim.c.step,
                                            arrays={k: np.concatenate([q[k] for q in parts]) for k in part})

    def close(self, status):
        if self.file:
            self.file.close(status)


def run_job(job, *, output, overwrite: bool = False, base_dir=None, progress=sys.stderr, comm=None) -> dict:
    """Run ``job`` and write ``output``; return a summary. Raises PiceError subclasses on failure.

    The run file is created only after the job has been set up (so bad input writes nothing), and it
    is closed with its status whatever happens, keeping every row already written.
    """
    sim = Simulation(job, base_dir=base_dir, comm=comm)
    comm = sim.comm
    if comm.rank != 0:
        progress = None
    total = sim.total_steps
    snaps = snapshot_steps(total, job.run.snapshots)
    every = job.run.series_every
    out = _Output(sim, output, job, overwrite)
    status = "failed"
    t0 = wall.perf_counter()
    last_report = t0
    snap_index = 0
    try:
        out.series()
        if 0 in snaps:
            out.snapshot(snap_index)
            snap_index += 1
        first_break = job.run.stop_at_first_break
        while sim.c.step < total:
            n = 1 if first_break else min(every - sim.c.step % every, total - sim.c.step)
            nxt = [s for s in snaps if sim.c.step < s <= sim.c.step + n]
            if nxt:
                n = min(nxt) - sim.c.step
            sim.advance(n)
            if sim.c.step % every == 0 or sim.c.step == total:
                out.series()
                out.events()
            if sim.c.step in snaps:
                out.snapshot(snap_index)
                snap_index += 1
            if first_break and comm.sum(sim.c.broken):
                out.series()
                out.events()
                out.snapshot(snap_index)
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
        try:
            if status == "finished":
                out.events()
            elif out.file:  # other ranks may be gone: write what rank 0 has
                out.file.append_events(sim.c.events[out.events_written:])
        finally:
            out.close(status)
    elapsed = wall.perf_counter() - t0
    elements = int(comm.sum(sim.p.nlocal))
    broken = int(comm.sum(sim.c.broken))
    return dict(output=str(output), steps=sim.c.step, time=sim.c.time, wall_time=elapsed,
                particle_steps_per_second=elements * sim.c.step / max(elapsed, 1e-9),
                broken_bonds=broken, elements=elements, ranks=comm.size, rank=comm.rank)
