"""One rank's simulation: set-up from a job, the step (DESIGN.md "The step"), diagnostics.

The step (velocity Verlet):
    half kick with F(t);  drift x(t+dt);  forces F(t+dt) from bonds, contacts, walls, water;
    half kick.  Bond and contact increments use the half-step velocities, i.e. the exact
    displacement increment over the step.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field
from time import perf_counter

import numpy as np

from .errors import InstabilityError
from .kernels.bonds import bond_energy, bond_forces, sync_mate_history
from .kernels.contacts import contact_forces
from .kernels.boundary import spring_boundary
from .kernels.hydro import buoyancy_potential
from .kernels.integrate import drift, kick, max_step_displacement
from .kernels.walls import wall_forces
from .kernels.hydro import gravity_forces, hydro_forces
from .physics.bond import bond_params_from_job
from .physics.contact import ice_contact_law
from .physics.hydro import heave_damping, water_from_job
from .physics.timestep import choose_step, stable_step
from .physics.walls import build_walls
from .platform import output as platform_output
from .platform.hull_contact import hull_forces
from .scenes.level_ice import build_level_ice

log = logging.getLogger("pice")

MAX_EVENTS = 100_000
RUNAWAY_STEP_FRACTION = 0.05  # an element moving more than 5 % of its radius in one step has run away


@dataclass
class Counters:
    """Running totals of one simulation."""

    step: int = 0
    time: float = 0.0
    broken: int = 0
    contacts: int = 0
    contact_energy: float = 0.0
    wall_energy: float = 0.0
    events: list = field(default_factory=list)  # (step, time, gid_a, gid_b, mode)


class Simulation:
    """Particles, parameters and the time loop of one job on one rank."""

    def __init__(self, job, *, base_dir=None, comm=None, restart=False, checkpoint=None):
        from .parallel.comm import world

        self.job = job
        self.comm = comm if comm is not None else world()
        # every rank builds the same whole sheet (deterministic), then keeps its own part
        self.p, self.sheet = build_level_ice(job)
        p = self.p
        m0, i0 = float(p.mass.min()), float(p.inertia.min())
        self.bond = bond_params_from_job(job, n_layers=self.sheet.n_layers, spacing=self.sheet.spacing)
        self.bond_law = self.bond.kernel_law(mass=m0, inertia=i0)
        self.contact_law = ice_contact_law(job, bond_kn=self.bond.kn)
        kinds, geom, wparams, names, owner = build_walls(job, default_kn=self.contact_law.kn, base_dir=base_dir)
        self.wall_kinds, self.wall_geometry, self.wall_params = kinds, geom, wparams
        self.wall_names, self.wall_owner = names, owner
        self.wall_force = np.zeros((len(kinds), 3))
        self.wall_moment = np.zeros((len(kinds), 3))
        self.water = water_from_job(job)
        from .parallel.coupling import BodyCoupling

        self._set_up_bodies(base_dir)
        # one reduction per step carries the loads on every [[walls]] entry and every body
        self.coupling = BodyCoupling(self.comm, len(job.walls) + len(self.hulls))
        self.wall_total = None
        self.body_total = None
        self.peaks = platform_output.Peaks()  # rank 0: load extremes since the last series row
        self.gravity = job.gravity
        p.allocate_dynamic(len(kinds), len(self.hulls))
        p.heave_damping = heave_damping(job, p)
        self._apply_loads_and_fixes()
        self._refuse_initial_wall_overlap()
        self.cell_size = 2.0 * float(p.radius.max()) * 1.0001
        self.limit = self._time_step()
        self.dt = self.limit.chosen
        self.c = Counters()
        self.wall_clock = {"exchange": 0.0, "forces": 0.0}  # seconds spent per phase (for mpi/scaling.py)
        self._events = np.zeros((MAX_EVENTS, 4), dtype=np.int64)
        if not restart:
            self._distribute()
            self.compute_forces()
        else:
            self._restore(checkpoint)

    @classmethod
    def from_checkpoint(cls, job, data, *, base_dir=None, comm=None) -> "Simulation":
        """Continue from a checkpoint (io.checkpoint.read_checkpoint's dict on rank 0, None elsewhere).

        The parameters are rebuilt from ``job`` exactly as a fresh run builds them; the particles,
        counters and (on the same rank count) the cuts come from the checkpoint.
        """
        return cls(job, base_dir=base_dir, comm=comm, restart=True, checkpoint=data)

    # -- set-up -------------------------------------------------------------------------------
    def _apply_loads_and_fixes(self) -> None:
        p, job = self.p, self.job
        x0 = p.x

        def select(region):
            sel = np.ones(p.n, bool)
            for k, (lo, hi) in enumerate(((region.xmin, region.xmax), (region.ymin, region.ymax),
                                          (region.zmin, region.zmax))):
                sel &= (x0[:, k] >= lo) & (x0[:, k] <= hi)
            return sel

        from .errors import JobError

        def selects_nothing(key, region):
            given = ", ".join(f"{b} = {v}" for b, v in region.model_dump(exclude_defaults=True).items())
            lo, hi = x0.min(axis=0), x0.max(axis=0)
            span = ", ".join(f"{a} {lo[d]:.4g} .. {hi[d]:.4g}" for d, a in enumerate("xyz"))
            return JobError(f"{job.source}: {key} = {{{given}}}: selects no element; the box must contain some "
                            f"initial element centres, which span {span} m")

        for k, load in enumerate(job.loads):
            sel = select(load.region)
            if not sel.any():
                raise selects_nothing(f"loads[{k}].region", load.region)
            p.ext_force[sel] += np.asarray(load.force) / np.count_nonzero(sel)
        for k, fix in enumerate(job.fixes):
            sel = select(fix.region)
            if not sel.any():
                raise selects_nothing(f"fixes[{k}].region", fix.region)
            for d, comp in enumerate(fix.velocity):
                if comp != "free":
                    p.fix_mask[sel, d] = True
                    p.fix_velocity[sel, d] = float(comp)
        if job.ice.push is not None:
            rows = job.ice.push.rows
            xmin = x0[:, 0].min()
            sel = x0[:, 0] < xmin + (rows - 1e-6) * self.sheet.spacing  # odd rows sit d/2 further in
            p.v[sel, 0] = job.ice.push.speed
            if job.ice.push.stiffness is not None:  # a spring boundary
                p.anchor_k[sel] = job.ice.push.stiffness
            else:
                p.fix_mask[sel, 0] = True
                p.fix_velocity[sel, 0] = job.ice.push.speed

    def _set_up_bodies(self, base_dir) -> None:
        """Hull geometry on every rank; rank 0 builds the bodies and lines; the poses reach every rank."""
        from .errors import PiceError

        self.hulls, self.platform = [], None
        self.poses = np.zeros((0, 13))
        if not self.job.bodies:
            return
        from .platform.build import build_platform, hulls_from_job, initial_poses, refuse_initial_overlap

        self.hulls = hulls_from_job(self.job, default_kn=self.contact_law.kn,
                                    reach=float(self.p.radius.max()), base_dir=base_dir)
        self.poses = initial_poses(self.job)
        refuse_initial_overlap(self.job, self.p, self.hulls, self.poses)
        error = None
        if self.comm.rank == 0:
            try:
                self.platform = build_platform(self.job, self.hulls)
            except PiceError as exc:
                error = exc
        error = self.comm.bcast(error)
        if error is not None:
            raise error
        self.broadcast_poses()

    def broadcast_poses(self) -> None:
        """Rank 0's body poses (x, q, v, omega per body) onto every rank."""
        poses = self.platform.poses() if self.platform is not None else np.zeros((len(self.hulls), 13))
        self.poses = self.comm.bcast_array(poses)

    def _refuse_initial_wall_overlap(self) -> None:
        """A wall that cuts into the ice at t = 0 would fire elements off: refuse it with the fix."""
        from .errors import JobError

        if not len(self.wall_kinds):
            return
        p = self.p
        f, t, wf = np.zeros((p.n, 3)), np.zeros((p.n, 3)), np.zeros((len(self.wall_kinds), 3))
        params = self.wall_params.copy()
        params["kt"], params["zeta"], params["mu"] = 0.0, 0.0, 0.0  # elastic normal force only
        wall_forces(p.nlocal, p.x, np.zeros_like(p.v), np.zeros_like(p.w), p.radius * 0.99, p.mass, self.wall_kinds,
                    self.wall_geometry, params, np.zeros_like(p.wall_hist), 0.0, f, t, wf, np.zeros_like(wf))
        hit = np.nonzero(np.abs(wf).sum(axis=1) > 0)[0]
        if len(hit):
            k = int(self.wall_owner[hit[0]])
            n_el = int(np.count_nonzero(np.abs(f).sum(axis=1) > 0))
            raise JobError(f"{self.job.source}: walls[{k}] ({self.wall_names[k]}): overlaps {n_el} ice "
                           "element(s) at t = 0; move the wall clear of the sheet (or the sheet's origin)")

    def _distribute(self) -> None:
        """Decompose the sheet over the ranks and set up the halo (a no-op on one rank)."""
        from .parallel.decomposition import uniform
        from .parallel.halo import Halo

        p, par = self.p, self.job.parallel
        if par.domain is not None:
            lo, hi = par.domain
        else:
            lo, hi = tuple(p.x[:, :2].min(axis=0)), tuple(p.x[:, :2].max(axis=0))
        self.decomp = uniform(self.comm.size, lo=lo, hi=hi)
        self.halo = Halo(self.comm, self.decomp, ghost_width=self.ghost_width(), skin=par.skin)
        if self.comm.size > 1:
            mine = np.nonzero(self.decomp.owner(p.x[:, 0], p.x[:, 1]) == self.comm.rank)[0]
            p.replace_rows([p.rows(mine)], len(mine))
        self.halo.rebuild(p)

    def _restore(self, data) -> None:
        """Particles, cuts and counters from a checkpoint; refuse one that does not fit this job."""
        from . import __version__
        from .io.checkpoint import CheckpointError, physics_differences, physics_text
        from .parallel.decomposition import Decomposition, uniform
        from .parallel.halo import Halo

        comm, p = self.comm, self.p
        meta = None
        if comm.rank == 0:
            x = data["particles"]["x"]
            meta = dict(attrs=data["attrs"], path=data.get("path", "checkpoint"), x_cuts=data["x_cuts"],
                        y_cuts=data["y_cuts"], counters=data["counters"], gid=data["particles"]["gid"],
                        lo=tuple(x[:, :2].min(axis=0)) if len(x) else (0.0, 0.0),
                        hi=tuple(x[:, :2].max(axis=0)) if len(x) else (0.0, 0.0))
        meta = comm.bcast(meta)
        a, where = meta["attrs"], meta["path"]
        if float(a["dt"]) != self.dt:
            raise CheckpointError(
                f"{where}: written with dt = {float(a['dt'])!r} s, but {self.job.source} now gives "
                f"dt = {self.dt!r} s; a restart must keep the time step: restore run.dt (and run.dt_safety) "
                "of the run that wrote it")
        diff = physics_differences(a["physics"], physics_text(self.job))
        if diff:
            raise CheckpointError(f"{where}: the job's physics differs from the run that wrote this checkpoint: "
                                  f"{'; '.join(diff)}; only [run] (duration, output schedule) and [parallel] may "
                                  "change on a restart")
        if not np.array_equal(meta["gid"], p.gid):  # the fresh sheet is in gid order
            raise CheckpointError(f"{where}: holds {len(meta['gid'])} particles whose ids do not match the "
                                  f"{p.n} of the job's sheet; it was written for another scene")
        if str(a.get("pice_version")) != __version__ and comm.rank == 0:
            log.warning("%s: written by pice %s, restarting with pice %s", where, a.get("pice_version"), __version__)
        same_layout = int(a["ranks"]) == comm.size
        width = self.ghost_width()  # from the whole sheet, as a fresh run computes it
        if same_layout:
            self.decomp = Decomposition(np.asarray(meta["x_cuts"]), np.asarray(meta["y_cuts"]))
        else:
            par = self.job.parallel
            lo, hi = par.domain if par.domain is not None else (meta["lo"], meta["hi"])
            self.decomp = uniform(comm.size, lo=lo, hi=hi)
            if comm.rank == 0:
                log.info("%s: written on %d rank(s), continuing on %d: results agree to round-off, not bit "
                         "for bit", where, int(a["ranks"]), comm.size)
        blocks = None
        if comm.rank == 0:
            rows = data["particles"]
            owner = self.decomp.owner(rows["x"][:, 0], rows["x"][:, 1]) if comm.size > 1 else \
                np.zeros(len(rows["gid"]), np.int64)
            blocks = [{k: v[owner == r] for k, v in rows.items()} for r in range(comm.size)]
        mine = comm.alltoall(blocks if blocks is not None else [None] * comm.size)[0]
        p.replace_rows([mine], len(mine["gid"]))
        self.halo = Halo(comm, self.decomp, ghost_width=width, skin=self.job.parallel.skin)
        self.halo.rebuild(p)  # ghosts and bond partners, as the writing run rebuilt them at that step
        c, k = self.c, meta["counters"]
        c.step = int(a["step"])
        c.time = float(a["time"])
        r = comm.rank
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
        self.wall_total = None if (wt is None or r != 0) else np.array(wt)
        if self.platform is not None:
            state = data.get("platform")
            if state is None:
                raise CheckpointError(f"{where}: holds no bodies, but {self.job.source} has [[bodies]]")
            self.platform.set_state(state)
            self.body_total = self.platform.ice.copy()
        if self.hulls:
            self.broadcast_poses()

    def rebuild_for_checkpoint(self) -> None:
        """Migrate and rebuild the ghosts now, as a restart from a checkpoint of this step does.

        Called whenever a checkpoint is written, so that the layout (owned rows in gid order, ghosts)
        after the checkpoint is the same in the run that goes on and in one restarted from it: the
        two then agree bit for bit on the same rank count. Forces travel with the rows (state.py).
        """
        self.halo.rebuild(self.p)

    def ghost_width(self) -> float:
        """Halo width [m]: the contact reach or the longest bond at its breaking stretch, plus the skin."""
        p, b = self.p, self.bond
        reach = 2.0 * float(p.radius.max())
        longest = float(p.bond_L0.max()) if p.bond_L0.size else 0.0
        if np.isfinite(b.normal_strength):
            longest += b.normal_strength * b.area / b.kn  # stretch at which tension alone breaks it
        else:
            longest *= 1.5  # unbreakable bonds: allow 50 % stretch; the run checks it
        return max(reach, longest) + self.job.parallel.skin

    def exchange(self) -> None:
        """After the drift: rebalance on schedule, else rebuild the halo if needed, else update ghosts."""
        p, every = self.p, self.job.parallel.balance_every
        if self.comm.size > 1 and every and self.c.step % every == 0 and self.rebalance():
            return
        if self.halo.needs_rebuild(p):
            self.halo.rebuild(p)
        else:
            self.halo.update(p)

    def rebalance(self) -> bool:
        """Move the cuts if max/mean particles per rank exceeds the threshold; True if it did (and rebuilt)."""
        from .parallel.balance import imbalance, rebalanced

        self.imbalance = imbalance(self.comm, self.p.nlocal)
        if self.imbalance <= self.job.parallel.imbalance_threshold:
            return False
        self.decomp = rebalanced(self.comm, self.decomp, self.p.x[:self.p.nlocal])
        self.halo.decomp = self.decomp
        self.halo.rebuild(self.p)
        after = imbalance(self.comm, self.p.nlocal)
        if self.comm.rank == 0:
            log.info("step %d: load balance %.3f -> %.3f (max/mean particles per rank)",
                     self.c.step, self.imbalance, after)
        self.imbalance = after
        return True

    def _time_step(self):
        p, b = self.p, self.bond
        push = self.job.ice.push
        kw = max([0.0] + [float(k) for k in self.wall_params["kn"]] + [float(h.params[0]) for h in self.hulls] +
                 [push.stiffness if push is not None and push.stiffness is not None else 0.0])
        i = int(np.argmin(p.mass))
        stable, why = stable_step(mass=float(p.mass[i]), inertia=float(p.inertia[i]), d=self.sheet.spacing,
                                  n_layers=self.sheet.n_layers, bond=(b.kn, b.ks, b.kt, b.kb),
                                  contact=(self.contact_law.kn, self.contact_law.kt),
                                  wall_stiffness=kw, damping_ratio=b.damping_ratio,
                                  contact_damping_ratio=self.contact_law.zeta)
        run = self.job.run
        return choose_step(requested=run.dt, safety=run.dt_safety, stable=stable, governed_by=why,
                           allow_unstable=run.allow_unstable_dt, source=self.job.source)

    # -- the step ------------------------------------------------------------------------------
    def compute_forces(self) -> None:
        """Forces and torques at the current positions (half-step velocities for the rate terms)."""
        p, c = self.p, self.c
        p.force[:] = 0.0
        p.torque[:] = 0.0
        nb = bond_forces(p.nlocal, p.gid, p.x, p.v, p.w, p.radius, p.bond_j, p.bond_mate, p.bond_gid,
                         p.bond_L0, p.bond_hist, self.bond_law, self.dt, p.force, p.torque,
                         self._events, MAX_EVENTS)
        if nb:
            c.broken += nb
            for a, b, mode, _ in self._events[:min(nb, MAX_EVENTS)]:
                c.events.append((c.step, c.time, int(a), int(b), int(mode)))
        c.contacts, c.contact_energy = contact_forces(
            p.nlocal, p.n, p.gid, p.x, p.v, p.w, p.radius, p.mass, p.bond_j, p.contact_gid, p.contact_stamp,
            p.contact_hist, self.contact_law, self.dt, c.step, self.cell_size, p.force, p.torque)
        self.wall_force[:] = 0.0
        self.wall_moment[:] = 0.0
        if len(self.wall_kinds):
            c.wall_energy = wall_forces(p.nlocal, p.x, p.v, p.w, p.radius, p.mass, self.wall_kinds,
                                        self.wall_geometry, self.wall_params, p.wall_hist, self.dt,
                                        p.force, p.torque, self.wall_force, self.wall_moment)
        if self.water is not None:
            hydro_forces(p.nlocal, p.x, p.v, p.radius, p.mass, p.cell_area, p.half_height, self.gravity,
                         self.water, p.heave_damping, p.force)
        else:
            gravity_forces(p.nlocal, p.mass, self.gravity, p.force)
        push = self.job.ice.push
        if push is not None and push.stiffness is not None:
            self.boundary_force = spring_boundary(p.nlocal, p.x, p.v, p.mass, p.anchor, p.anchor_k,
                                                  push.damping_ratio, np.array([push.speed, 0.0, 0.0]),
                                                  c.time, p.force)
        nw = len(self.job.walls)
        if nw or self.hulls:
            local = np.zeros((nw + len(self.hulls), 6))
            local[:nw] = self._local_wall_loads()
            for k, h in enumerate(self.hulls):
                local[nw + k] = hull_forces(p.nlocal, p.x, p.v, p.w, p.radius, p.mass, self.poses[k], h.vertices,
                                            h.triangles, *h.grid, h.params, p.hull_hist[:, k, :], self.dt,
                                            p.force, p.torque)
            total = self.coupling.reduce_loads(local)  # on rank 0, None elsewhere
            if total is not None:
                self.wall_total, self.body_total = total[:nw], total[nw:]
            if self.platform is not None:
                self.platform.loads(self.body_total)
                self.peaks.track(self.body_total[:, :3], self.platform.fairlead_tensions())

    def step(self) -> None:
        p, dt = self.p, self.dt
        half = 0.5 * dt
        platform = self.platform
        kick(p.nlocal, p.v, p.w, p.force, p.torque, p.ext_force, p.mass, p.inertia, p.fix_mask, p.fix_velocity, half)
        drift(p.nlocal, p.x, p.v, dt)
        if platform is not None:  # rank 0: bodies and lines to t + dt
            platform.kick(half)
            platform.drift(dt)
        self.c.step += 1
        self.c.time = self.c.step * dt
        t0 = perf_counter()
        if self.hulls:
            self.broadcast_poses()
        self.exchange()
        t1 = perf_counter()
        self.compute_forces()
        self.wall_clock["exchange"] += t1 - t0
        self.wall_clock["forces"] += perf_counter() - t1
        kick(p.nlocal, p.v, p.w, p.force, p.torque, p.ext_force, p.mass, p.inertia, p.fix_mask, p.fix_velocity, half)
        if platform is not None:
            platform.kick(half)

    def advance(self, nsteps: int) -> None:
        """Take ``nsteps`` steps, checking for runaway motion every ``run.check_every`` steps."""
        every = self.job.run.check_every
        for k in range(nsteps):
            self.step()
            if (k + 1) % every == 0 or k == nsteps - 1:
                self.check_health()

    def check_health(self) -> None:
        """Raise InstabilityError naming the step, the element and the likely cause on NaN or runaway."""
        p = self.p
        ratio, i, nonfinite = max_step_displacement(p.nlocal, p.v, p.w, p.radius, self.dt)
        bad = 1.0 if (nonfinite or ratio > RUNAWAY_STEP_FRACTION) else 0.0
        if self.comm.max(bad) == 0.0:
            self.halo.check_bond_lengths(p)
            return
        if not bad:  # another rank holds the runaway element: it reports, we stop with it
            raise InstabilityError(f"unstable at step {self.c.step}: reported by another rank")
        what = "a non-finite velocity (NaN/inf)" if nonfinite else \
            f"a displacement of {ratio:.3g} radii in one step"
        if self.dt > self.limit.stable:
            cause = (f"run.dt = {self.dt:.4g} s is above the stability limit {self.limit.stable:.4g} s "
                     f"({self.limit.governed_by}); use dt = \"auto\"")
        else:
            cause = ("a force spike: overlapping elements in the initial geometry, a load too large for "
                     "the elements, or a wall/contact stiffness far above the bond stiffness")
        raise InstabilityError(
            f"unstable at step {self.c.step} (t = {self.c.time:.6g} s): element gid {int(p.gid[i])} at "
            f"{np.array2string(p.x[i], precision=3)} m shows {what}; likely cause: {cause}")

    # -- diagnostics ---------------------------------------------------------------------------
    def sync(self) -> None:
        """Bring both copies of every owned bond's history up to date (before output or inspection)."""
        p = self.p
        sync_mate_history(p.nlocal, p.gid, p.bond_j, p.bond_mate, p.bond_hist)

    def energies(self) -> dict[str, float]:
        """Energy budget [J] of the owned particles."""
        p, n = self.p, self.p.nlocal
        ke = 0.5 * float(np.sum(p.mass[:n] * np.einsum("ij,ij->i", p.v[:n], p.v[:n])))
        kr = 0.5 * float(np.sum(p.inertia[:n] * np.einsum("ij,ij->i", p.w[:n], p.w[:n])))
        pg = float(np.sum(p.mass[:n] * self.gravity * p.x[:n, 2]))
        pb = 0.0
        if self.water is not None:
            level, rho = self.water.level, self.water.density
            pb = float(sum(buoyancy_potential(p.x[i, 2], p.radius[i], p.cell_area[i], p.half_height[i],
                                              level, rho, self.gravity) for i in range(n)))
        eb = bond_energy(n, p.gid, p.bond_gid, p.bond_hist, self.bond_law)
        parts = self.comm.sum(np.array([ke, kr, pg, pb, eb, self.c.contact_energy, self.c.wall_energy]))
        names = ("kinetic_energy", "rotational_energy", "gravity_energy", "buoyancy_energy", "bond_energy",
                 "contact_energy", "wall_energy")
        out = {k: float(v) for k, v in zip(names, parts)}
        out["total_energy"] = float(parts.sum())
        return out

    def _local_wall_loads(self) -> np.ndarray:
        """(n_wall_entries, 6): force [N] of this rank's ice on each [[walls]] entry, and its moment
        about the origin [N m] (each contact force acts at the sphere's contact point)."""
        out = np.zeros((len(self.job.walls), 6))
        if len(self.wall_owner):
            np.add.at(out[:, :3], self.wall_owner, self.wall_force)
            np.add.at(out[:, 3:], self.wall_owner, self.wall_moment)
        return out

    def wall_loads(self) -> np.ndarray | None:
        """(n_wall_entries, 6) force [N] and moment about the origin [N m] of the ice on each wall,
        reduced on rank 0 every step (None on other ranks)."""
        if not len(self.job.walls):
            return np.zeros((0, 6)) if self.comm.rank == 0 else None
        return self.wall_total

    def series_row(self) -> dict[str, np.ndarray | float]:
        counts = self.comm.sum(np.array([self.p.bond_count(), self.c.broken, self.c.contacts], dtype=np.float64))
        row = dict(time=self.c.time, step=float(self.c.step), bonds=counts[0], broken_bonds=counts[1],
                   contacts=counts[2])
        row.update(self.energies())
        loads = self.wall_loads()
        if loads is not None:
            row["wall_force"] = loads[:, :3]
            row["wall_moment"] = loads[:, 3:]
        push = self.job.ice.push
        if push is not None and push.stiffness is not None:  # the far field's push on the sheet [N]
            row["boundary_force"] = self.comm.sum(self.boundary_force)
        if self.platform is not None:
            row.update(self.platform_row())
        return row

    def platform_snapshot(self, first: bool = False) -> dict | None:
        """Rank 0's snapshot arrays of the bodies and lines (pice.platform.output.snapshot_arrays); None elsewhere."""
        return None if self.platform is None else platform_output.snapshot_arrays(self.platform, self.hulls, first)

    def platform_row(self) -> dict[str, np.ndarray]:
        """Rank 0's series entries of the bodies and lines, with the peaks since the previous row."""
        return platform_output.series_entries(self.platform, self.body_total, self.peaks.take())

    def describe(self) -> dict:
        """Facts for `pice check` and the run file's attributes."""
        p = self.p
        nbytes = sum(a.nbytes for a in vars(p).values() if isinstance(a, np.ndarray))
        return dict(elements=int(self.comm.sum(p.nlocal)), bonds=int(self.comm.sum(p.bond_count())), layers=self.sheet.n_layers,
                    thickness_modelled=self.sheet.actual_thickness, memory_bytes=nbytes,
                    dt_stable=self.limit.stable, dt=self.dt, dt_safety=self.limit.safety,
                    dt_governed_by=self.limit.governed_by, steps_per_second=1.0 / self.dt,
                    bond_kn=self.bond.kn, bond_ks=self.bond.ks, bond_kb=self.bond.kb, bond_kt=self.bond.kt,
                    normal_strength=self.bond.normal_strength, shear_strength=self.bond.shear_strength,
                    bond_friction=self.bond.friction, element_mass=float(p.mass[0]), 
                    **(platform_output.describe(self.platform, self.dt) if self.platform is not None else {}))

    @property
    def total_steps(self) -> int:
        return int(math.ceil(self.job.run.duration / self.dt - 1e-9))
