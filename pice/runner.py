"""Run a job to the end: the time loop with its output schedule, checkpoints, stop requests and
progress line.

Under MPI every rank steps its part of the ice; the run file is written by io/output.py (RunOutput:
series rows, events, snapshots, the status at the end), in either of the two modes of io/mpio.py.
"""

from __future__ import annotations

import math
import pathlib
import signal
import sys
import time as wall

from .errors import InstabilityError, JobError, RunInterrupted
from .io.output import RunOutput, snapshot_steps
from .simulation import Simulation


class _StopRequest:
    """SIGINT/SIGTERM only set a flag; the run loop reads it collectively at its chunk boundaries."""

    SIGNALS = (signal.SIGINT, signal.SIGTERM)

    def __init__(self, comm, progress):
        self.comm, self.progress = comm, progress
        self.flag = 0.0
        self.previous = {}

    def _handler(self, signum, frame):
        if not self.flag and self.progress is not None:
            print(f"pice: {signal.Signals(signum).name} received: stopping after the current steps, writing a "
                  "checkpoint first", file=self.progress, flush=True)
        self.flag = 1.0

    def install(self) -> "_StopRequest":
        try:
            for sig in self.SIGNALS:
                self.previous[sig] = signal.signal(sig, self._handler)
        except ValueError:  # not the main thread: no handler, no graceful stop
            self.previous.clear()
        return self

    def restore(self) -> None:
        for sig, handler in self.previous.items():
            signal.signal(sig, handler)
        self.previous = {}

    def requested(self) -> bool:
        """True on every rank once any rank has been asked to stop (collective)."""
        return self.comm.max(self.flag) > 0.0


def run_job(job, *, output, overwrite: bool = False, base_dir=None, progress="stderr", comm=None,
            restart=None, poll=None) -> dict:
    """Run ``job`` and write ``output``; return a summary. Raises PiceError subclasses on failure.

    The run file is created only after the job has been set up (so bad input writes nothing), and it
    is closed with its status whatever happens, keeping every row already written.

    ``restart``: a checkpoint to continue from; the run file ``output`` is then continued, not
    created. Checkpoints go to run.checkpoint (default <output>.ckpt.h5) every run.checkpoint_every
    simulated seconds, and when SIGINT/SIGTERM asks the run to stop (RunInterrupted, exit status 130).
    ``poll``: called with no argument after every chunk of steps (a study's queue served between steps).

    The summary's ``wall_time`` [s] and ``steps_run`` are this call's time loop; ``steps`` and
    ``wall_time_total`` [s] count from t = 0 over every call of a run continued from checkpoints (NaN
    when one of them was written by a pice that did not keep it).
    """
    progress = sys.stderr if progress == "stderr" else progress  # the stream at the call, not at import
    from .io.checkpoint import default_path

    if restart is not None:
        sim = simulation_from_checkpoint(job, restart, base_dir=base_dir, comm=comm)
    else:
        sim = Simulation(job, base_dir=base_dir, comm=comm)
    comm = sim.comm
    ckpt_path = job.run.checkpoint or default_path(output)
    ckpt_every = max(1, round(job.run.checkpoint_every / sim.dt)) if job.run.checkpoint_every > 0 else 0
    step0 = sim.c.step
    if comm.rank != 0:
        progress = None
    total = sim.total_steps
    snaps = snapshot_steps(total, job.run.snapshots)
    every = job.run.series_every
    out = RunOutput(sim, output, job, overwrite, restart=restart)
    status = "failed"
    wall0 = sim.c.wall_time  # the earlier calls' (a restart), NaN when its checkpoint did not keep it
    t0 = wall.perf_counter()
    last_report = t0
    snap_index = out.snapshots_kept  # 0, or after a restart the snapshots up to the checkpoint
    stop = _StopRequest(comm, progress).install()
    try:
        watch = _peak_watch(job, sim, out, restart)  # rank 0's; every rank takes part in its verdict
        watching = job.keel is not None and job.keel.end_after_peak is not None
        if restart is None:
            out.series()
            _watch_row(watch, out)
        if 0 in snaps and restart is None:
            out.snapshot(snap_index)
            snap_index += 1
        first_break = job.run.stop_at_first_break
        while sim.c.step < total:
            n = 1 if first_break else min(every - sim.c.step % every, total - sim.c.step)
            nxt = [s for s in snaps if sim.c.step < s <= sim.c.step + n]
            if nxt:
                n = min(nxt) - sim.c.step
            if ckpt_every:
                n = min(n, ckpt_every - sim.c.step % ckpt_every)
            sim.advance(n)
            if poll is not None:
                poll()
            if sim.c.step % every == 0 or sim.c.step == total:
                out.series()
                out.events()
                _watch_row(watch, out)
                if watching and comm.bcast(watch.past if comm.rank == 0 else None):  # collective
                    if progress is not None:
                        print(f"pice: t = {sim.c.time:.3f} s: the resistance is past its peak (its 6 m running "
                              f"average below {job.keel.end_after_peak:g} of it, the stem past the keel): the run "
                              "ends here (keel.end_after_peak)", file=progress, flush=True)
                    break
            if sim.c.step in snaps:
                out.snapshot(snap_index)
                snap_index += 1
            if first_break and comm.sum(sim.c.broken):
                out.series()
                out.events()
                out.snapshot(snap_index)
                break
            scheduled = ckpt_every and (sim.c.step % ckpt_every == 0 or sim.c.step == total)
            if scheduled:
                sim.c.wall_time = wall0 + (wall.perf_counter() - t0)
                out.checkpoint(ckpt_path)
            if stop.requested():
                if not scheduled:
                    sim.c.wall_time = wall0 + (wall.perf_counter() - t0)
                    out.checkpoint(ckpt_path)
                status = "interrupted"
                raise RunInterrupted(f"interrupted at step {sim.c.step} (t = {sim.c.time:.6g} s); checkpoint "
                                     f"written to {ckpt_path}; continue with: pice run {job.source} -o {output} "
                                     f"--restart {ckpt_path}")
            now = wall.perf_counter()
            if progress is not None and now - last_report > 5.0:
                rate = (sim.c.step - step0) / (now - t0)
                eta = (total - sim.c.step) / rate if rate > 0 else float("inf")
                status = getattr(out, "status", "")  # at the last series row
                print(f"pice: t = {sim.c.time:.3f} / {job.run.duration:g} s, {rate:.0f} steps/s, "
                      f"ETA {eta:.0f} s" + (f", {status}" if status else ""), file=progress, flush=True)
                last_report = now
        status = "finished"
    except RunInterrupted:
        raise
    except InstabilityError as exc:
        status = f"stopped: {exc}"
        raise
    except KeyboardInterrupt:
        status = "interrupted"
        raise
    finally:
        stop.restore()
        out.finish(status)  # the last events, the status attribute, the XDMF file beside the run file
    elapsed = wall.perf_counter() - t0
    sim.c.wall_time = wall0 + elapsed
    elements = int(comm.sum(sim.p.nlocal))
    broken = int(comm.sum(sim.c.broken))
    return dict(output=str(output), steps=sim.c.step, time=sim.c.time, wall_time=elapsed,
                steps_run=sim.c.step - step0, wall_time_total=comm.bcast(sim.c.wall_time),
                particle_steps_per_second=elements * (sim.c.step - step0) / max(elapsed, 1e-9),
                broken_bonds=broken, elements=elements, ranks=comm.size, rank=comm.rank,
                floes=sim.floes.n if sim.floes is not None else 0,
                floe_steps_per_second=(sim.floes.n if sim.floes is not None else 0) * (sim.c.step - step0)
                / max(elapsed, 1e-9),
                mooring_node_updates=comm.bcast(_node_updates(sim) if comm.rank == 0 else None))


def _peak_watch(job, sim, out, restart):
    """Rank 0's postproc.resistance.PeakWatch of a keel job with keel.end_after_peak (None otherwise, and
    on the other ranks), holding the rows already in the run file when the run continues from a checkpoint."""
    if job.keel is None or job.keel.end_after_peak is None or sim.comm.rank != 0:
        return None
    from .platform.build import initial_poses
    from .postproc.resistance import PeakWatch

    watch = PeakWatch.from_job(job, sim.hulls[0], initial_poses(job)[0])
    if restart is not None:
        s = out.file.series
        force = s["ice_force_mean"] if "ice_force_mean" in s else s["ice_force"]
        for x, f in zip(s["body_position"][:, 0, 0], force[:, 0, 0]):
            watch.add(x, f)
    return watch


def _watch_row(watch, out) -> None:
    """The series row just written into the watch (rank 0)."""
    if watch is not None:
        row = out.row
        watch.add(row["body_position"][0, 0], row.get("ice_force_mean", row["ice_force"])[0, 0])


def _node_updates(sim) -> int:
    """DEM mooring-node updates per ice step (nodes x line sub-steps; 0 without DEM lines), rank 0."""
    if sim.platform is None:
        return 0
    from .platform.output import describe as describe_platform

    d = describe_platform(sim.platform, sim.dt)
    return int(d["mooring_nodes"] * max(d["mooring_substeps"], 1)) if d["mooring_nodes"] else 0


def simulation_from_checkpoint(job, path, *, base_dir=None, comm=None) -> Simulation:
    """A Simulation continued from the checkpoint at ``path`` (rank 0 reads it; errors reach every rank)."""
    from .io.checkpoint import read_checkpoint
    from .parallel.comm import on_root, world

    comm = comm if comm is not None else world()
    data = on_root(comm, lambda: read_checkpoint(path))
    return Simulation.from_checkpoint(job, data, base_dir=base_dir, comm=comm)


def _trimmed_keel(job, path, base_dir, comm, t0: float) -> dict:
    """make_keel of a keel trimmed from a wider one's file (keel.trim_from): rank 0 reads, trims, writes."""
    from .io.keel_file import read_trim_source, write_keel
    from .parallel.comm import on_root
    from .physics.keel import trim_keel

    def trim():
        wider = read_trim_source(job, base_dir)
        keel = trim_keel(job.keel, wider)
        write_keel(path, job.keel, keel)
        return keel, wider["path"], wider["width"], len(wider["x"])

    keel, wider, width, of = comm.bcast(on_root(comm, trim))
    took = wall.perf_counter() - t0
    line = (f"pice keel: {path}: {len(keel.x):,} of the {of:,} blocks of {wider} ({width:g} m wide) trimmed to "
            f"{job.keel.width:g} m; porosity {keel.porosity:.3f} (core {keel.core_porosity:.3f}); {took:.1f} s of "
            "wall time")
    return dict(file=str(path), blocks=len(keel.x), released=keel.released, settle_time=keel.settle_time,
                rms_speed=keel.rms_speed, porosity=keel.porosity, core_porosity=keel.core_porosity,
                wall_time=took, rank=comm.rank, line=line, trimmed_from=str(wider))


def make_keel(job, *, output=None, base_dir=None, progress="stderr", comm=None) -> dict:
    """Generate the job's [keel] on the ranks of ``comm`` (physics/keel.py), write its keel file (rank
    0; ``output``, default keel.file or <job>.keel.h5 beside the job) and return a summary. progress:
    a stream for the settling's progress lines, "stderr" (sys.stderr at the call) or None."""
    progress = sys.stderr if progress == "stderr" else progress
    from .io.keel_file import generation_path, keel_path, read_generation, write_generation, write_keel
    from .parallel.comm import on_root, world
    from .physics.keel import generate_keel

    if job.keel is None:
        raise JobError(f"{job.source}: keel = (absent): pice keel generates a [keel]; give one")
    comm = comm if comm is not None else world()
    path = pathlib.Path(output) if output else keel_path(job, base_dir)
    loud = progress is not None and comm.rank == 0
    t0 = wall.perf_counter()

    def report(t, rms, contacts):
        if loud:
            print(f"pice keel: t = {t:.4g} s, RMS speed {rms:.3g} m/s, {contacts:,} block contacts", file=progress,
                  flush=True)

    if job.keel.trim_from is not None:  # no generation: the middle of a wider keel's file
        return _trimmed_keel(job, path, base_dir, comm, t0)
    gen = generation_path(path)  # a killed or unsettled generation is continued from it
    resume = comm.bcast(on_root(comm, lambda: read_generation(gen, job.keel, job.source)))
    if resume is not None and loud:
        print(f"pice keel: continuing the generation from t = {resume[0]:.4g} s ({gen})", file=progress, flush=True)
    keel = generate_keel(job, comm, progress=report, resume=resume,
                         save=lambda t, state: on_root(comm, lambda: write_generation(gen, job.keel, t, state)))
    on_root(comm, lambda: write_keel(path, job.keel, keel))
    on_root(comm, lambda: gen.unlink(missing_ok=True))
    took = wall.perf_counter() - t0
    line = (f"pice keel: {path}: {len(keel.x):,} of {keel.released:,} blocks in the keel, settled in "
            f"{keel.settle_time:.4g} s (RMS {keel.rms_speed:.2g} m/s"
            + (f", friction back from {keel.locked_at:.4g} s" if math.isfinite(keel.locked_at) else "")
            + f"); porosity {keel.porosity:.3f} (core "
            f"{keel.core_porosity:.3f}); {took:.1f} s of wall time")
    return dict(file=str(path), blocks=len(keel.x), released=keel.released, settle_time=keel.settle_time,
                rms_speed=keel.rms_speed, porosity=keel.porosity, core_porosity=keel.core_porosity,
                wall_time=took, rank=comm.rank, line=line)
