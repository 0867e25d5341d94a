"""Run a job to the end: the time loop with its output schedule and progress line.

Under MPI every rank steps its part of the ice and the run file is written in one of two modes
(io/mpio.py): by every rank through h5py's mpio driver when h5py has MPI, else by rank 0 from
reduced series rows and gathered snapshots. The file is the same either way.
"""

from __future__ import annotations

import logging
import signal
import sys
import time as wall

import numpy as np

from .errors import InstabilityError, PiceError, RunInterrupted
from .io.mpio import MODE_ENV, choose_mode, h5py_has_mpi
from .io.run_file import OutputError, RunFile
from .io.xdmf import write_xdmf_quietly
from .simulation import Simulation


def snapshot_steps(total_steps: int, count: int) -> set[int]:
    """Steps at which to write snapshots: ``count`` evenly spaced, first and last included."""
    if count <= 0:
        return set()
    if count == 1:
        return {total_steps}
    return {round(k * total_steps / (count - 1)) for k in range(count)}


class _Output:
    """The run file. Mode "mpio": every rank holds the RunFile and writes its own part. Mode
    "gathered": rank 0 owns the RunFile; every rank takes part in the gathers."""

    def __init__(self, sim, output, job, overwrite, restart=None):
        self.sim, self.comm = sim, sim.comm
        self.file = None
        # a restart continues its file serially (RunFile.open_for_restart): gathered
        self.mode = "gathered" if restart is not None else choose_mode(self.comm)
        if self.comm.size > 1 and self.comm.rank == 0:
            logging.getLogger("pice").info(
                "run file: parallel HDF5, every rank writes through the mpio driver" if self.mode == "mpio" else
                "run file: gathered to rank 0 and written there (" + (
                    "a restart continues its file that way)" if restart is not None else
                    f"{MODE_ENV}=gathered)" if h5py_has_mpi() else "this h5py has no MPI)"))
        error = None
        if self.mode == "mpio":  # collective; an error is raised on every rank alike
            self.file = RunFile(output, job=job, overwrite=overwrite, ranks=self.comm.size, comm=self.comm,
                                extra_attrs={"dt": sim.dt, "dt_stable": sim.limit.stable})
        elif self.comm.rank == 0:
            try:
                if restart is not None:  # continue the run file: rows up to the checkpoint's step stay
                    self.file = RunFile.open_for_restart(output, step=sim.c.step, job=job, ranks=self.comm.size,
                                                         restarted_from=str(restart))
                else:
                    self.file = RunFile(output, job=job, overwrite=overwrite, ranks=self.comm.size,
                                        extra_attrs={"dt": sim.dt, "dt_stable": sim.limit.stable})
            except PiceError as exc:
                error = exc
        error = self.comm.bcast(error)
        if error is not None:
            raise error
        self.events_written = len(sim.c.events)  # a restart's events are in the file already
        self.snapshots_kept = self.comm.bcast(len(self.file.snapshots) if self.file else 0)

    def series(self):
        row = self.sim.series_row()  # collective
        self.broken = int(row["broken_bonds"])  # all ranks' count, for the progress line
        if self.mode == "mpio":  # collective
            self.file.append_series(row)
        else:
            self._write(lambda: self.file.append_series(row))

    def events(self):
        new = self.sim.c.events[self.events_written:]
        self.events_written = len(self.sim.c.events)
        if self.mode == "mpio":  # collective: the RunFile gathers and sorts them
            self.file.append_events(new)
            return
        gathered = self.comm.gather(new)
        self._write(lambda: self.file.append_events(sorted(e for part in gathered for e in part)))

    def snapshot(self, index):
        self.sim.sync()
        p = self.sim.p
        n = p.nlocal
        part = dict(gid=p.gid[:n].copy(), x=p.x[:n].copy(), v=p.v[:n].copy(), w=p.w[:n].copy(),
                    radius=p.radius[:n].copy(), kind=p.kind[:n].copy(), bonds=p.intact_bonds())
        extras = self.sim.platform_snapshot(first=index == 0)  # rank 0's bodies and lines (None elsewhere)
        if self.mode == "mpio":  # collective: each rank writes its part at its gid-sorted place
            self.file.write_snapshot_arrays(index, time=self.sim.c.time, step=self.sim.c.step, arrays=part,
                                            extras=extras)
            return
        parts = self.comm.gather(part)
        self._write(lambda: self.file.write_snapshot_arrays(
            index, time=self.sim.c.time, step=self.sim.c.step,
            arrays={k: np.concatenate([q[k] for q in parts]) for k in part}, extras=extras))

    def _write(self, write):
        """Every rank holding the file calls ``write`` (gathered: rank 0 only); an OutputError (a full
        disk...) is raised on every rank, so none is left waiting in a collective."""
        error = None
        if self.file:
            try:
                write()
            except OutputError as exc:
                error = exc
        if self.comm.size > 1:
            error = self.comm.bcast(error)
        if error is not None:
            raise error

    def checkpoint(self, path):
        """Events and rows so far into the run file, then the checkpoint, then the rebuild a restart does."""
        from .io.checkpoint import write_checkpoint

        self.events()
        self._write(lambda: self.file.flush())
        write_checkpoint(self.sim, path)
        self.sim.rebuild_for_checkpoint()

    def _together(self, status) -> bool:
        """Did every rank reach this status together (so collective file calls are safe)?"""
        return (status in ("finished", "interrupted") or status.startswith("stopped")
                or bool(self.file and self.file.failed))

    def events_after_failure(self, status):
        if self.mode == "gathered":
            if self.file and not self.file.failed:  # other ranks may be gone: write what rank 0 has
                self.file.append_events(self.sim.c.events[self.events_written:])
        elif self._together(status) and not self.file.failed:
            self.events()

    def close(self, status):
        if self.file:
            if self.mode == "mpio" and not self._together(status):
                self.file.abandon()  # one rank's failure: no collective call; flushed rows stay
            else:
                self.file.close(status)


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


def run_job(job, *, output, overwrite: bool = False, base_dir=None, progress=sys.stderr, comm=None,
            restart=None) -> dict:
    """Run ``job`` and write ``output``; return a summary. Raises PiceError subclasses on failure.

    The run file is created only after the job has been set up (so bad input writes nothing), and it
    is closed with its status whatever happens, keeping every row already written.

    ``restart``: a checkpoint to continue from; the run file ``output`` is then continued, not
    created. Checkpoints go to run.checkpoint (default <output>.ckpt.h5) every run.checkpoint_every
    simulated seconds, and when SIGINT/SIGTERM asks the run to stop (RunInterrupted, exit status 130).
    """
    from .io.checkpoint import default_path

    if restart is not None:
        sim = _restarted(job, restart, base_dir=base_dir, comm=comm)
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
    out = _Output(sim, output, job, overwrite, restart=restart)
    status = "failed"
    t0 = wall.perf_counter()
    last_report = t0
    snap_index = out.snapshots_kept  # 0, or after a restart the snapshots up to the checkpoint
    stop = _StopRequest(comm, progress).install()
    try:
        if restart is None:
            out.series()
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
            scheduled = ckpt_every and (sim.c.step % ckpt_every == 0 or sim.c.step == total)
            if scheduled:
                out.checkpoint(ckpt_path)
            if stop.requested():
                if not scheduled:
                    out.checkpoint(ckpt_path)
                status = "interrupted"
                raise RunInterrupted(f"interrupted at step {sim.c.step} (t = {sim.c.time:.6g} s); checkpoint "
                                     f"written to {ckpt_path}; continue with: pice run {job.source} -o {output} "
                                     f"--restart {ckpt_path}")
            now = wall.perf_counter()
            if progress is not None and now - last_report > 5.0:
                rate = (sim.c.step - step0) / (now - t0)
                eta = (total - sim.c.step) / rate if rate > 0 else float("inf")
                broken = getattr(out, "broken", sim.c.broken)  # at the last series row, all ranks
                print(f"pice: t = {sim.c.time:.3f} / {job.run.duration:g} s, {rate:.0f} steps/s, "
                      f"ETA {eta:.0f} s, broken bonds {broken}", file=progress, flush=True)
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
        try:
            if status == "finished":
                out.events()
            else:
                out.events_after_failure(status)
        finally:
            out.close(status)
            if comm.rank == 0:  # ParaView opens <run>.xdmf directly; a failure here only warns
                write_xdmf_quietly(output)
    elapsed = wall.perf_counter() - t0
    elements = int(comm.sum(sim.p.nlocal))
    broken = int(comm.sum(sim.c.broken))
    return dict(output=str(output), steps=sim.c.step, time=sim.c.time, wall_time=elapsed,
                particle_steps_per_second=elements * (sim.c.step - step0) / max(elapsed, 1e-9),
                broken_bonds=broken, elements=elements, ranks=comm.size, rank=comm.rank)


def _restarted(job, path, *, base_dir=None, comm=None) -> Simulation:
    """A Simulation continued from the checkpoint at ``path`` (rank 0 reads it; errors reach every rank)."""
    from .io.checkpoint import read_checkpoint
    from .parallel.comm import world

    comm = comm if comm is not None else world()
    data, error = None, None
    if comm.rank == 0:
        try:
            data = read_checkpoint(path)
        except PiceError as exc:
            error = exc
    error = comm.bcast(error)
    if error is not None:
        raise error
    return Simulation.from_checkpoint(job, data, base_dir=base_dir, comm=comm)
