"""One rank's simulation: set-up from a job, and the step (DESIGN.md "The step").

The step (velocity Verlet; docs/architecture.md "The step, in order"):
    half kick with F(t);  drift x(t+dt);  post the ghost update;  rank 0: the platform's kick and drift,
    post the poses;  the terms on owned elements (water, walls, far-field springs) while the ghosts
    travel;  receive them;  bonds and contacts;  receive the poses;  hulls;  the loads to rank 0, whose
    platform takes its loads and closing half kick;  half kick.  Bond and contact increments use the
    half-step velocities: the exact displacement increment.

The forces come from a list of force terms built at set-up (``self.terms``), one object per piece of
physics the job declares (bonds, ice contacts, walls, water or gravity, the spring boundary, hulls);
each has ``add_forces(particles, counters, dt)``. What the run reports is in diagnostics.py; the
decomposition and halo in parallel/domain.py; the restart in io/restore.py.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from . import diagnostics
from .io.output import refuse_outputs_beyond_run
from .kernels.bonds import sync_mate_history
from .kernels.integrate import drift, kick, max_step_displacement
from .memory import refuse_oversized
from .parallel.comm import on_root, refuse_mixed_arithmetic, world
from .parallel.domain import Domain, ghost_width
from .physics.bond import BondTerm
from .physics.bond_calibration import bond_params_from_job
from .physics.boundary import SpringBoundaryTerm
from .physics.contact import IceContactTerm, ice_contact_law
from .physics.crushing import crushed_through, remove_elements
from .physics.floe_system import floe_time_step
from .physics.rigid_ice import rigid_pieces_from_job
from .physics.hydro import GravityTerm, WaterTerm, heave_damping, water_from_job
from .physics.timestep import sheet_time_step
from .physics.walls import WallTerm
from .physics.work import element_work
from .scenes.level_ice import build_level_ice
from .scenes.loads import apply_loads_and_fixes
from .timers import StepTimers, term_part

RUNAWAY_STEP_FRACTION = 0.05  # an element moving more than 5 % of its radius in one step has run away
CONTACT_SKIN = 0.3  # the contact neighbour list's skin, of the largest element diameter (kernels/pair_list.py)


@dataclass
class Counters:
    """Running totals of one rank's simulation (checkpointed)."""

    step: int = 0
    time: float = 0.0
    broken: int = 0
    contacts: int = 0
    contact_energy: float = 0.0
    wall_energy: float = 0.0
    events: list = field(default_factory=list)  # (step, time, gid_a, gid_b, mode)
    # [s] the time loop's wall time to this step over all the run's calls (runner.run_job; rank 0's is
    # checkpointed); NaN when the run continued from a checkpoint that did not keep it (pice before 2026-12-07)
    wall_time: float = 0.0


class Simulation:
    """Particles, force terms and the time loop of one job on one rank."""

    def __init__(self, job, *, base_dir=None, comm=None, restart=False, checkpoint=None):
        self.job = job
        self.comm = comm if comm is not None else world()
        refuse_mixed_arithmetic(self.comm)
        refuse_oversized(job, self.comm, base_dir)  # every rank builds the whole sheet, then keeps its part
        self.p, self.sheet = build_level_ice(job)  # no elements without [ice]
        p = self.p
        self.n_initial = p.n  # elements of the whole sheet (crushed ones are removed)
        self.has_sheet = job.ice is not None
        self.bond = self.contact_law = None
        if self.has_sheet:
            self.bond = bond_params_from_job(job, n_layers=self.sheet.n_layers, spacing=self.sheet.spacing)
            self.contact_law = ice_contact_law(job, bond_kn=self.bond.kn)
        self.gravity = job.gravity
        self.walls = WallTerm(job, default_kn=self.contact_law.kn, base_dir=base_dir) if job.walls else None
        self._set_up_bodies(base_dir)
        # rigid floes or a keel's blocks (breakable floes are elements of the sheet)
        self.floes = rigid_pieces_from_job(job, self.hulls, self.poses, comm=self.comm, base_dir=base_dir)
        p.allocate_dynamic(len(self.walls.kinds) if self.walls else 0, len(self.hulls))
        p.heave_damping = heave_damping(job, p)
        apply_loads_and_fixes(job, p, spacing=self.sheet.spacing)
        if self.walls is not None:
            self.walls.refuse_initial_overlap(job, p)
        self.limit = self._time_step()
        self.dt = self.limit.chosen
        refuse_outputs_beyond_run(job, self.total_steps, self.dt)
        self.terms = self._force_terms()
        self.wall_total = self.body_total = None  # rank 0: the reduced load on each [[walls]] entry, each body
        self.c = Counters()
        self.timers = None  # pice/timers.py StepTimers once enable_timers() has switched to the timed step
        width = ghost_width(p, self.bond, job.parallel.skin) if self.has_sheet else job.parallel.skin
        self.domain = Domain(self.comm, job.parallel, ghost_width=width, dt=self.dt, work=element_work)
        if not restart:
            self.domain.distribute(p)
            self.compute_forces()
        else:
            from .io.restore import restore

            restore(self, checkpoint)

    @classmethod
    def from_checkpoint(cls, job, data, *, base_dir=None, comm=None) -> "Simulation":
        """Continue from a checkpoint (io.checkpoint.read_checkpoint's dict on rank 0, None elsewhere)."""
        return cls(job, base_dir=base_dir, comm=comm, restart=True, checkpoint=data)

    # -- set-up -------------------------------------------------------------------------------
    def _set_up_bodies(self, base_dir) -> None:
        """Hull geometry on every rank; rank 0 builds the bodies and lines; the poses reach every rank."""
        self.hulls, self.platform, self.coupling, self.hull_term = [], None, None, None
        self.poses = np.zeros((0, 13))
        n_loads = len(self.job.walls) + len(self.job.bodies)
        if n_loads:  # one reduction per step carries the loads on every wall entry and every body
            from .parallel.coupling import BodyCoupling

            self.coupling = BodyCoupling(self.comm, n_loads)
        if not self.job.bodies:
            return
        from .platform.build import build_platform, hulls_from_job, initial_poses, refuse_initial_overlap
        from .platform.hull_contact import HullContactTerm
        from .platform.output import Peaks

        law = self.contact_law
        self.hulls = hulls_from_job(self.job, default_kn=law.kn if law is not None else 1.0,
                                    reach=float(self.p.radius.max()) if self.p.n else 0.0, base_dir=base_dir)
        self.poses = initial_poses(self.job)
        refuse_initial_overlap(self.job, self.p, self.hulls, self.poses)
        self.platform = on_root(self.comm, lambda: build_platform(self.job, self.hulls))
        self.peaks = Peaks()  # rank 0: load extremes since the last series row
        self.hull_term = HullContactTerm(self.hulls)
        self.broadcast_poses()

    def _force_terms(self) -> list:
        """The force terms the job declares, in the order the step applies them."""
        job, p = self.job, self.p
        terms, self.bond_term, self.ice_contact_term = [], None, None
        if self.has_sheet:
            self.bond_term = BondTerm(self.bond.kernel_law(mass=float(p.mass.min()), inertia=float(p.inertia.min())))
            self.ice_contact_term = IceContactTerm(self.contact_law, skin=CONTACT_SKIN * 2.0 * float(p.radius.max()))
            terms = [self.bond_term, self.ice_contact_term]
        self.n_ghost_terms = len(terms)  # the first terms read ghosts; the rest act on owned elements only
        if self.walls is not None:
            terms.append(self.walls)
        water = water_from_job(job)
        self.water_term = WaterTerm(water, job.gravity) if water is not None else None
        if self.water_term is not None:
            terms.append(self.water_term)
        elif job.gravity != 0.0:
            terms.append(GravityTerm(job.gravity))
        push = job.ice.push if self.has_sheet else None
        self.boundary_term = None
        if push is not None and push.stiffness is not None:
            self.boundary_term = SpringBoundaryTerm.of_ice(job.ice, comm=self.comm)
            terms.append(self.boundary_term)
        if self.hull_term is not None and self.has_sheet:
            terms.append(self.hull_term)
        return terms

    def _time_step(self):
        if not self.has_sheet:  # floes and bodies alone: the floes' contact law sets the step
            return floe_time_step(self.job, self.floes)
        return sheet_time_step(self.job, self.p, self.sheet, self.bond, self.contact_law,
                               self.walls.params if self.walls else [], [h.law for h in self.hulls])

    def broadcast_poses(self) -> None:
        """Rank 0's body poses (x, q, v, omega per body) onto every rank, and into the hull term."""
        self.start_poses()
        self.finish_poses()

    def start_poses(self) -> None:
        """Post the poses' broadcast (non-blocking): the bonds are computed while it travels, so the
        other ranks need not wait for rank 0's platform step (``finish_poses`` receives it)."""
        poses = self.platform.poses() if self.platform is not None else np.zeros((len(self.hulls), 13))
        self._poses_pending = self.comm.start_bcast_array(poses)

    def finish_poses(self) -> None:
        if getattr(self, "_poses_pending", None) is not None:
            self.poses = self.comm.finish_bcast_array(self._poses_pending)
            self.hull_term.poses = self.poses
            self._poses_pending = None

    # -- the step ------------------------------------------------------------------------------
    def compute_forces(self, finish_half: float | None = None) -> None:
        """Forces and torques at the current positions (half-step velocities for the rate terms):
        the terms on owned elements while the ghost update travels, then the bonds and contacts,
        then the terms that read the body poses (``reads_poses``: the hulls) once they are here.
        ``finish_half`` [s]: in a step, rank 0's platform takes its closing half kick with its loads."""
        p = self.p
        p.force[:] = 0.0
        p.torque[:] = 0.0
        owned = self.terms[self.n_ghost_terms:]
        for term in owned:  # owned elements only: the ghost update travels
            if not getattr(term, "reads_poses", False):
                term.add_forces(p, self.c, self.dt)
        self.domain.finish_exchange(p)
        for term in self.terms[:self.n_ghost_terms]:  # bonds and contacts read the ghosts
            term.add_forces(p, self.c, self.dt)
        self.finish_poses()
        for term in owned:
            if getattr(term, "reads_poses", False):
                term.add_forces(p, self.c, self.dt)
        if self.floes is not None:  # every rank: the floes' forces and their loads on the bodies
            self.floes.compute_forces(self.poses, self.c.time, self.dt)
        if self.coupling is not None:
            self._reduce_loads(finish_half=finish_half)

    def _reduce_loads(self, lap=None, finish_half: float | None = None) -> None:
        """The ice loads on walls and hulls to rank 0 (one reduction); rank 0 hands the bodies theirs
        and, in a step (``finish_half`` [s], not None), the platform finishes its step with them.

        ``lap``: the timed step's StepTimers.lap (None in the plain step: no clock is read)."""
        nw = len(self.job.walls)
        local = np.zeros((nw + len(self.hulls), 6))
        if self.walls is not None:
            local[:nw] = self.walls.local_loads()
        if self.hull_term is not None:
            local[nw:] = self.hull_term.loads
        if lap is not None:
            lap("other")
        total = self.coupling.reduce_loads(local)  # on rank 0, None elsewhere
        if lap is not None:
            lap("waiting")
        if total is not None:
            self.wall_total, self.body_total = total[:nw], total[nw:]
            if self.floes is not None:  # the same on every rank: not reduced
                self.body_total = self.body_total + self.floes.body_loads
        if self.platform is not None:
            if finish_half is None:  # the loads alone (at the start of a run)
                self.platform.loads(self.body_total)
                tensions = self.platform.fairlead_tensions()
            else:  # the loads and the step's closing half kick (the same bits as after the ice's kick)
                tensions = self.platform.finish_step(self.body_total, finish_half)
            self.peaks.track(self.body_total[:, :3], tensions)
            if lap is not None:
                lap("platform")

    def step(self) -> None:
        """One step of dt (the module docstring). ``_timed_step`` is its twin with timers: a change
        here is made there too (tests/unit/test_bench.py checks that both give the same bits)."""
        p, dt, c = self.p, self.dt, self.c
        half = 0.5 * dt
        platform = self.platform
        kick(p.nlocal, p.v, p.w, p.force, p.torque, p.ext_force, p.mass, p.inertia, p.fix_mask, p.fix_velocity, half)
        drift(p.nlocal, p.x, p.v, dt)
        if self.floes is not None:  # every rank: all floes
            self.floes.kick(half)
            self.floes.drift(dt)
        c.step += 1
        c.time = c.step * dt
        if self.has_sheet:  # the ghosts' update first: it does not wait for rank 0's platform
            self.domain.exchange(p, c.step)
        if platform is not None:  # rank 0: bodies and lines to t + dt
            platform.begin_step(half, dt)
        if self.hulls:
            self.start_poses()
        self.compute_forces(finish_half=half)  # rank 0's platform: its loads and closing half kick
        kick(p.nlocal, p.v, p.w, p.force, p.torque, p.ext_force, p.mass, p.inertia, p.fix_mask, p.fix_velocity, half)
        if self.floes is not None:
            self.floes.kick(half)

    # -- the timed step (pice/timers.py) --------------------------------------------------------
    def enable_timers(self):
        """Switch to the timed step and return its StepTimers (pice/timers.py); the plain step reads no clock."""
        self.timers = StepTimers()
        self.step = self._timed_step  # this instance only; disable_timers() restores the plain step
        return self.timers

    def disable_timers(self) -> None:
        """Back to the plain step, which reads no clock."""
        self.timers = None
        self.__dict__.pop("step", None)

    def _timed_step(self) -> None:
        """``step`` with each part timed: the same calls on the same arrays in the same order."""
        p, dt, c, timers = self.p, self.dt, self.c, self.timers
        lap = timers.lap
        half = 0.5 * dt
        platform = self.platform
        kick(p.nlocal, p.v, p.w, p.force, p.torque, p.ext_force, p.mass, p.inertia, p.fix_mask, p.fix_velocity, half)
        drift(p.nlocal, p.x, p.v, dt)
        if self.floes is not None:
            self.floes.kick(half)
            self.floes.drift(dt)
        lap("integration")
        c.step += 1
        c.time = c.step * dt
        if self.has_sheet:
            self.domain.exchange(p, c.step, timers)  # laps "halo" and "waiting"
        if platform is not None:
            platform.begin_step(half, dt)
            lap("platform")
        if self.hulls:
            self.start_poses()
            lap("waiting")
        self._timed_forces(lap, finish_half=half)
        kick(p.nlocal, p.v, p.w, p.force, p.torque, p.ext_force, p.mass, p.inertia, p.fix_mask, p.fix_velocity, half)
        if self.floes is not None:
            self.floes.kick(half)
        lap("integration")
        timers.steps += 1

    def _timed_forces(self, lap, finish_half: float | None = None) -> None:
        """``compute_forces`` with each force term timed (pice/timers.py TERM_PARTS)."""
        p = self.p
        p.force[:] = 0.0
        p.torque[:] = 0.0
        lap("integration")
        owned = self.terms[self.n_ghost_terms:]
        for term in owned:
            if not getattr(term, "reads_poses", False):
                term.add_forces(p, self.c, self.dt)
                lap(term_part(term))
        self.domain.finish_exchange(p, self.timers)  # laps "waiting"
        for term in self.terms[:self.n_ghost_terms]:
            term.add_forces(p, self.c, self.dt)
            lap(term_part(term))
        self.finish_poses()
        lap("waiting")
        for term in owned:
            if getattr(term, "reads_poses", False):
                term.add_forces(p, self.c, self.dt)
                lap(term_part(term))
        if self.floes is not None:
            self.floes.compute_forces(self.poses, self.c.time, self.dt)
            lap("floes")
        if self.coupling is not None:
            self._reduce_loads(lap, finish_half)

    def advance(self, nsteps: int) -> None:
        """Take ``nsteps`` steps, checking for runaway motion every ``run.check_every`` steps."""
        every = self.job.run.check_every
        for k in range(nsteps):
            self.step()
            if (k + 1) % every == 0 or k == nsteps - 1:
                self.check_health()

    def check_health(self) -> None:
        """Raise InstabilityError naming the step, the element and the likely cause on NaN or runaway."""
        p, timers = self.p, self.timers
        if self.floes is not None:  # the same on every rank: no reduction needed
            self.floes.check(self.c.step, self.c.time)
        ratio, i, nonfinite = max_step_displacement(p.nlocal, p.v, p.w, p.radius, self.dt)
        bad = 1.0 if (nonfinite or ratio > RUNAWAY_STEP_FRACTION) else 0.0
        crushed = crushed_through(p) if self.job.crushing is not None else ()
        if timers is not None:
            timers.lap("checks")
        flags = self.comm.max(np.array([bad, 1.0 if len(crushed) else 0.0]))  # the one reduction
        if timers is not None:
            timers.lap("waiting")
        if flags[0] == 0.0:
            if flags[1]:
                self._remove_crushed(crushed)
            if timers is not None:
                timers.lap("checks")
            return
        raise diagnostics.runaway(self, i if bad else None, ratio, nonfinite)

    def _remove_crushed(self, crushed) -> None:
        """Remove the elements crushed through on every rank (physics/crushing.py; collective)."""
        parts = self.comm.gather(self.p.gid[crushed])
        gone = self.comm.bcast(np.concatenate(parts) if parts is not None else None)
        events = remove_elements(self.p, gone, step=self.c.step, time=self.c.time)
        self.c.broken += len(events)
        self.c.events.extend(events)
        self.domain.rebuild(self.p)

    # -- state for output ----------------------------------------------------------------------
    def sync(self) -> None:
        """Bring both copies of every owned bond's history up to date (before output or inspection)."""
        p = self.p
        sync_mate_history(p.nlocal, p.gid, p.bond_j, p.bond_mate, p.bond_hist)

    def rebuild_for_checkpoint(self) -> None:
        """Migrate and rebuild the ghosts now, as a restart from a checkpoint of this step does, so that
        the run that goes on and one restarted from it agree bit for bit on the same rank count."""
        self.domain.rebuild(self.p)

    def wall_loads(self) -> np.ndarray | None:
        """(n_wall_entries, 6) force [N] and moment about the origin [N m] of the ice on each wall,
        reduced on rank 0 every step (None on other ranks)."""
        if not len(self.job.walls):
            return np.zeros((0, 6)) if self.comm.rank == 0 else None
        return self.wall_total

    def energies(self) -> dict[str, float]:
        return diagnostics.energies(self)

    def series_row(self) -> dict:
        return diagnostics.series_row(self)

    def describe(self) -> dict:
        return diagnostics.describe(self)

    @property
    def total_steps(self) -> int:
        return int(math.ceil(self.job.run.duration / self.dt - 1e-9))
