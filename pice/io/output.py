"""A run's output while it runs: series rows, broken-bond events, snapshots and checkpoints into the
run file, on every rank of the run (pice/runner.py decides when; this module writes).

The run file is written in one of two modes (io/mpio.py): "mpio", every rank holds the RunFile and
writes its own particles through h5py's mpio driver; "gathered", rank 0 owns the RunFile and every
rank takes part in the gathers. The file is the same either way. A failed write (a full disk, a
denied path: io/run_file.py checks the free space before each write) raises the same OutputError
on every rank, so none is left waiting in a collective; rows are flushed as written, and
``finish`` records why the run stopped in the file's status attribute, then writes the XDMF file.
"""

from __future__ import annotations

import logging

import numpy as np

from ..parallel.comm import on_root
from ..physics.crushing import crush_depth
from ..platform.output import describe as describe_platform
from ..platform.output import snapshot_arrays
from .mpio import MODE_ENV, choose_mode, h5py_has_mpi
from .run_file import RunFile
from .xdmf import write_xdmf_quietly


def refuse_outputs_beyond_run(job, total_steps: int, dt: float) -> None:
    """A schedule asking for more snapshots than the run has steps (t = 0 and every step at most)
    is refused, not clamped: JobError naming run.snapshots, the steps the run has and the fix. The
    other outputs cannot exceed the run: series rows every ``series_every`` steps and checkpoints
    every ``checkpoint_every`` seconds are written at least at the start and the end."""
    from ..errors import JobError

    if job.run.snapshots > total_steps + 1:
        raise JobError(f"{job.source}: run.snapshots = {job.run.snapshots}: more snapshots than the run has steps "
                       f"(run.duration = {job.run.duration:g} s at dt = {dt:.4g} s is {total_steps:,} steps, so at "
                       f"most {total_steps + 1:,} snapshots: t = 0 and every step); refused, not clamped: lower "
                       "run.snapshots or lengthen run.duration")


def snapshot_steps(total_steps: int, count: int) -> set[int]:
    """Steps at which to write snapshots: ``count`` evenly spaced, first and last included."""
    if count <= 0:
        return set()
    if count == 1:
        return {total_steps}
    return {round(k * total_steps / (count - 1)) for k in range(count)}


class RunOutput:
    """The run file of ``sim``'s run (collective: every rank constructs it and calls every method).

    ``restart``: the checkpoint the run continues from; its run file ``output`` is then continued
    (serially, RunFile.open_for_restart: gathered mode) from the checkpoint's step."""

    def __init__(self, sim, output, job, overwrite, restart=None):
        self.sim, self.comm = sim, sim.comm
        self.path = output
        self.file = None
        # a restart continues its file serially (RunFile.open_for_restart): gathered
        self.mode = "gathered" if restart is not None else choose_mode(self.comm)
        if self.comm.size > 1 and self.comm.rank == 0:
            logging.getLogger("pice").info(
                "run file: parallel HDF5, every rank writes through the mpio driver" if self.mode == "mpio" else
                "run file: gathered to rank 0 and written there (" + (
                    "a restart continues its file that way)" if restart is not None else
                    f"{MODE_ENV}=gathered)" if h5py_has_mpi() else "this h5py has no MPI)"))
        attrs = {"dt": sim.dt, "dt_stable": sim.limit.stable}
        if sim.platform is not None:  # rank 0, whose attributes the file keeps: bodies, their resolved masses, lines
            attrs.update(describe_platform(sim.platform, sim.dt))
        if self.mode == "mpio":  # collective; an error is raised on every rank alike
            self.file = RunFile(output, job=job, overwrite=overwrite, ranks=self.comm.size, comm=self.comm,
                                extra_attrs=attrs)
        else:
            def open_file():
                if restart is not None:  # continue the run file: rows up to the checkpoint's step stay
                    return RunFile.open_for_restart(output, step=sim.c.step, job=job, ranks=self.comm.size,
                                                    restarted_from=str(restart))
                return RunFile(output, job=job, overwrite=overwrite, ranks=self.comm.size, extra_attrs=attrs)

            self.file = on_root(self.comm, open_file)
        self.events_written = len(sim.c.events)  # a restart's events are in the file already
        self.snapshots_kept = self.comm.bcast(len(self.file.snapshots) if self.file else 0)

    def series(self):
        """One /series row (collective); ``self.status`` is then the progress line's figures of it."""
        row = self.sim.series_row()  # collective
        self.row = row  # complete on rank 0, which holds the bodies
        self.status = progress_figures(self.sim, row)
        if self.mode == "mpio":  # collective
            self.file.append_series(row)
        else:
            self._write(lambda: self.file.append_series(row))

    def events(self):
        """The broken-bond events since the last call (collective)."""
        new = self.sim.c.events[self.events_written:]
        self.events_written = len(self.sim.c.events)
        if self.mode == "mpio":  # collective: the RunFile gathers and sorts them
            self.file.append_events(new)
            return
        gathered = self.comm.gather(new)
        self._write(lambda: self.file.append_events(sorted(e for part in gathered for e in part)))

    def snapshot(self, index):
        """Snapshot ``index`` of the particles, their intact bonds and rank 0's bodies (collective)."""
        self.sim.sync()
        p = self.sim.p
        n = p.nlocal
        part = dict(gid=p.gid[:n].copy(), x=p.x[:n].copy(), v=p.v[:n].copy(), w=p.w[:n].copy(),
                    radius=p.radius[:n].copy(), kind=p.kind[:n].copy(), crush_depth=crush_depth(p),
                    bonds=p.intact_bonds())
        extras = None  # small arrays written by rank 0: its bodies and lines, and the floes every rank holds
        if self.sim.platform is not None:
            extras = snapshot_arrays(self.sim.platform, self.sim.hulls, index == 0)
        if self.sim.floes is not None and self.comm.rank == 0:
            extras = {**(extras or {}), **self.sim.floes.snapshot_arrays(first=index == 0)}
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
        on_root(self.comm, write, here=bool(self.file))

    def checkpoint(self, path):
        """Events and rows so far into the run file, then the checkpoint, then the rebuild a restart does."""
        from .checkpoint import write_checkpoint

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
        """Record ``status`` in the file and close it (collective when every rank got here together)."""
        if self.file:
            if self.mode == "mpio" and not self._together(status):
                self.file.abandon()  # one rank's failure: no collective call; flushed rows stay
            else:
                self.file.close(status)

    def finish(self, status):
        """The end of a run, whatever ended it: the last events, the status, and on rank 0 the XDMF
        file beside the run file (ParaView opens it directly; a failure there only warns)."""
        try:
            if status == "finished":
                self.events()
            else:
                self.events_after_failure(status)
        finally:
            self.close(status)
            if self.comm.rank == 0:
                write_xdmf_quietly(self.path)


def progress_figures(sim, row) -> str:
    """The progress line's figures of a series row, for the physics the scene has: the broken bonds of a
    sheet, the rigid ice's contacts, the first body's ice load (its x component [kN]: a ship's resistance
    is minus it) on rank 0, which holds the bodies."""
    out = []
    if sim.has_sheet:
        out.append(f"broken bonds {int(row['broken_bonds'])}")
    if "floe_contacts" in row:
        out.append(f"{'block' if sim.job.keel is not None else 'floe'} contacts {int(row['floe_contacts']):,}")
    if "ice_force" in row and len(row["ice_force"]):
        force = row.get("ice_force_mean", row["ice_force"])
        out.append(f"ice load x on {sim.job.bodies[0].name} {force[0, 0] / 1e3:.4g} kN")
    return ", ".join(out)
