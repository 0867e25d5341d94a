"""Continue a simulation from a checkpoint (the dict that io.checkpoint.read_checkpoint returns).

The parameters are rebuilt from the job exactly as a fresh run builds them; the particles, the
counters and (on the same rank count) the cuts come from the checkpoint. A checkpoint that does not
fit the job (another time step, other physics, another sheet) is refused with what differs.
"""

from __future__ import annotations

import logging

import numpy as np

from .. import __version__
from ..parallel.decomposition import Decomposition, uniform
from .checkpoint import CheckpointError, keys_at_default, physics_differences, physics_text

log = logging.getLogger("pice")


def restore(sim, data) -> None:
    """Particles, cuts and counters of ``sim`` from ``data`` (rank 0's checkpoint dict, None elsewhere)."""
    comm, p, job = sim.comm, sim.p, sim.job
    meta = None
    if comm.rank == 0:
        x = data["particles"]["x"]
        meta = dict(attrs=data["attrs"], path=data.get("path", "checkpoint"), x_cuts=data["x_cuts"],
                    y_cuts=data["y_cuts"], counters=data["counters"], gid=data["particles"]["gid"],
                    lo=tuple(x[:, :2].min(axis=0)) if len(x) else (0.0, 0.0),
                    hi=tuple(x[:, :2].max(axis=0)) if len(x) else (0.0, 0.0))
    meta = comm.bcast(meta)
    a, where = meta["attrs"], meta["path"]
    _refuse_mismatch(sim, a, where, meta["gid"])
    if str(a.get("pice_version")) != __version__ and comm.rank == 0:
        log.warning("%s: written by pice %s, restarting with pice %s", where, a.get("pice_version"), __version__)
    same_layout = int(a["ranks"]) == comm.size
    if same_layout:
        decomp = Decomposition(np.asarray(meta["x_cuts"]), np.asarray(meta["y_cuts"]))
    else:
        par = job.parallel
        lo, hi = par.domain if par.domain is not None else (meta["lo"], meta["hi"])
        decomp = uniform(comm.size, lo=lo, hi=hi)
        if comm.rank == 0:
            log.info("%s: written on %d rank(s), continuing on %d: results agree to round-off, not bit "
                     "for bit", where, int(a["ranks"]), comm.size)
    blocks = None
    if comm.rank == 0:
        rows = data["particles"]
        owner = decomp.owner(rows["x"][:, 0], rows["x"][:, 1]) if comm.size > 1 else \
            np.zeros(len(rows["gid"]), np.int64)
        blocks = [{k: v[owner == r] for k, v in rows.items()} for r in range(comm.size)]
    mine = comm.alltoall(blocks if blocks is not None else [None] * comm.size)[0]
    p.replace_rows([mine], len(mine["gid"]))
    sim.domain.adopt(p, decomp)  # ghosts and bond partners, as the writing run rebuilt them at that step
    _restore_counters(sim, a, meta["counters"], same_layout, data)
    if sim.platform is not None:
        state = data.get("platform")
        if state is None:
            raise CheckpointError(f"{where}: holds no bodies, but {job.source} has [[bodies]]")
        sim.platform.set_state(state)
        sim.body_total = sim.platform.ice.copy()
        sim.peaks.set_state(data.get("peaks"))  # the next series row's mean over all its steps
    if sim.hulls:
        sim.broadcast_poses()
    if sim.floes is not None:
        state = comm.bcast(data.get("floes") if comm.rank == 0 else None)
        if state is None:
            raise CheckpointError(f"{where}: holds no floes, but {job.source} has [floes]")
        sim.floes.set_state(state, where)
    term = sim.boundary_term
    if term is not None and term.far_mass is not None:  # the finite far field's shift and speed
        state = comm.bcast(data.get("far_field") if comm.rank == 0 else None)
        if state is None:
            raise CheckpointError(f"{where}: holds no far field, but {job.source} gives ice.push.far_field_length")
        term.set_state(state)


def _refuse_mismatch(sim, a, where, gid) -> None:
    if float(a["dt"]) != sim.dt:
        raise CheckpointError(
            f"{where}: written with dt = {float(a['dt'])!r} s, but {sim.job.source} now gives "
            f"dt = {sim.dt!r} s; a restart must keep the time step: restore run.dt (and run.dt_safety) "
            "of the run that wrote it")
    diff = physics_differences(a["physics"], physics_text(sim.job), at_default=keys_at_default(sim.job))
    if diff:
        raise CheckpointError(f"{where}: the job's physics differs from the run that wrote this checkpoint: "
                              f"{'; '.join(diff)}; only [run] (duration, output schedule) and [parallel] may "
                              "change on a restart")
    if len(gid) > sim.p.n or not np.isin(gid, sim.p.gid).all():  # crushed elements may be gone
        raise CheckpointError(f"{where}: holds {len(gid)} particles whose ids do not match the "
                              f"{sim.p.n} of the job's sheet; it was written for another scene")


def _restore_counters(sim, a, k, same_layout: bool, data) -> None:
    """Step, time, this rank's counters and broken-bond events; rank 0's reduced wall loads."""
    comm, c, r = sim.comm, sim.c, sim.comm.rank
    c.step = int(a["step"])
    c.time = float(a["time"])
    c.wall_time = float(a.get("wall_time", float("nan")))  # checkpoints before it: unknown
    if same_layout:
        c.broken, c.contacts = int(k["broken"][r]), int(k["contacts"][r])
        c.contact_energy, c.wall_energy = float(k["contact_energy"][r]), float(k["wall_energy"][r])
    elif r == 0:
        c.broken, c.contacts = int(np.sum(k["broken"])), int(np.sum(k["contacts"]))
        c.contact_energy, c.wall_energy = float(np.sum(k["contact_energy"])), float(np.sum(k["wall_energy"]))
    ev = comm.bcast(data["events"] if r == 0 else None)
    keep = (ev["rank"] == r) if same_layout else np.full(len(ev["rank"]), r == 0)
    c.events = [(int(st), float(t), int(ga), int(gb), int(m)) for st, t, ga, gb, m in
                zip(ev["step"][keep], ev["time"][keep], ev["gid_a"][keep], ev["gid_b"][keep], ev["mode"][keep])]
    wt = comm.bcast(data["wall_total"] if r == 0 else None)
    sim.wall_total = None if (wt is None or r != 0) else np.array(wt)
