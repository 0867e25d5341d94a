"""A job's broken ice: the rigid floes of [floes] on every rank, their work split over the ranks
(issue 14; the floes themselves: physics/floes.py).

Every rank holds the state of every floe (position, velocity, attitude, angular momentum: about
100 bytes a floe, plus its prism) and steps all of them alike. The forces are computed by each
floe's owner: the floes are dealt round the ranks in gid order, rank r owning r, r + size, ... (a
contiguous block each would hand one rank all the contacts of a keel's blocks released in shelves:
the top ones pack first; measured 26 against 10 ms on two ranks). It computes the
water's loads on its floes, their contacts with floes of higher gid and with the structures, as
records (kernels/floe_contact.py); one Allgatherv a step hands every rank every record, and a stable
merge by floe puts them in the order one rank computes them in. The forces, and so the whole run,
are then the same bits on any number of ranks. A contact's history lives with the owner of its
lower-gid floe.

Why not a spatial decomposition, as the level ice has: a floe field is small (seed 003's largest,
1.2 km x 2 km at 90 %, is about 2,300 floes: under a megabyte of state), so replicating the state
costs nothing, and the work, which is in the contacts and the water's clipping, still divides over
the ranks. A field of 10^5 floes or more would want the level ice's decomposition.

Structures: each body's hull (its convex pieces: a revolved hull's frusta, a box, a ship's bow,
midbody and stern) moves with the body's pose, which rank 0 broadcasts; a floe meets a hull of
several pieces as one contact (Floes.join_pieces: the pieces' overlaps summed), its force shared
among the pieces by their overlaps; the floes' loads on it are summed in record order and handed
to the platform with the level ice's. ``floes.sides = "confined"`` adds two fixed walls along the
drift (half-spaces beyond y0 and y1 of the field's area).
"""

from __future__ import annotations

import logging
import math

import numpy as np

from ..errors import JobError
from ..kernels.floe_contact import PAIR_RECORD, apply_pair_records
from ..kernels.structure_contact import STRUCTURE_RECORD, apply_structure_records
from ..kernels.floe_hydro import SEA_COLUMNS
from ..kernels.floe_motion import turn_all
from ..kernels.polyhedron_contact import contact_geometry
from .floes import FloeLaw, Floes, FloeWater, contact_step_limit
from .timestep import StepLimit


class FloeSystem:
    """The job's floes on one rank of ``comm`` (module docstring). ``body_pieces[k]``: the structure
    indices of body k's convex pieces; the structures after them are walls."""

    def __init__(self, floes: Floes, comm, body_pieces: list[list[int]]):
        self.f, self.comm, self.body_pieces = floes, comm, body_pieces
        n = len(floes.mass)
        self.lo, self.hi, self.stride = comm.rank, n, comm.size  # the owned floes: range(lo, hi, stride)
        self.owned = np.arange(self.lo, self.hi, self.stride)
        # every rank's floes one after the other (rank order), as the Allgatherv hands them
        self.dealt = np.concatenate([np.arange(r, n, comm.size) for r in range(comm.size)]).astype(np.int64)
        self.body_loads = np.zeros((len(body_pieces), 6))  # force [N], moment about the body's CG [N m]
        self.contacts = 0            # floe-floe contacts in the last step
        self.structure_contacts = 0  # floe-structure and floe-wall contacts (a hull of pieces: one a floe)
        self.plastic = 0             # contacts in plastic flow (crushing)
        self.water = np.zeros((n, 3))  # the water's force and gravity on each floe at the last step [N]

    @property
    def n(self) -> int:
        return len(self.f.mass)

    def kick(self, h: float) -> None:
        """Velocities and angular momenta by h [s] of the current forces."""
        f = self.f
        f.v += h * f.force / (f.mass[:, None] + f.added)
        f.L += h * f.torque

    def drift(self, dt: float) -> None:
        """Positions and attitudes over dt [s] (the exact free rotation)."""
        f = self.f
        f.x += dt * f.v
        turn_all(f.q, f.L, f.inertia, dt)
        f.step_count += 1

    def compute_forces(self, poses: np.ndarray, time: float, dt: float) -> None:
        """Forces and torques on every floe, and their loads on the bodies at ``poses`` (n_bodies, 13: x,
        q, v, omega), at ``time`` [s] (collective: one Allgatherv)."""
        f = self.f
        f.time = time
        for k, pieces in enumerate(self.body_pieces):
            for s in pieces:
                f.move_structure(s, x=poses[k, :3], q=poses[k, 3:7], v=poses[k, 7:10], w=poses[k, 10:13])
        pts, counts = f.world()
        omega = f.omega
        lo, hi, stride, own = self.lo, self.hi, self.stride, self.owned
        f.force[:] = 0.0
        f.torque[:] = 0.0
        f.water_loads(lo, hi, pts, counts, omega, dt, stride)
        water = f.force[own].ravel()  # the water's loads and gravity alone (a copy: fancy indexing)
        structure = f.all_structure_records(lo, hi, pts, counts, omega, dt, stride)
        pairs, npair, nplastic, _ = f.pair_records(lo, hi, pts, counts, omega, dt, stride)
        nplastic += sum(r[2] for r in structure)
        head = [len(own), npair, nplastic] + [r[1] for r in structure]
        message = np.concatenate([np.asarray(head, float), f.force[own].ravel(), f.torque[own].ravel(), water]
                                 + [r[0][:r[1]].ravel() for r in structure] + [pairs[:npair].ravel()])
        everything, counts_per_rank = self.comm.allgather_doubles(message)
        self._apply(everything, counts_per_rank)

    def _apply(self, everything: np.ndarray, counts_per_rank: np.ndarray) -> None:
        """Every rank's records, merged by floe, onto the floes and structures (module docstring)."""
        f, ns = self.f, len(self.f.structures)
        blocks, at = [], 0
        for count in counts_per_rank:
            blocks.append(everything[at:at + int(count)])
            at += int(count)
        parsed = []
        row = 0
        for b in blocks:
            own, npair, nplastic = int(b[0]), int(b[1]), int(b[2])
            nstruct = b[3:3 + ns].astype(np.int64)
            at = 3 + ns
            rows = self.dealt[row:row + own]
            f.force[rows] = b[at:at + 3 * own].reshape(own, 3)
            f.torque[rows] = b[at + 3 * own:at + 6 * own].reshape(own, 3)
            self.water[rows] = b[at + 6 * own:at + 9 * own].reshape(own, 3)
            at += 9 * own
            recs = []
            for k in range(ns):
                recs.append(b[at:at + STRUCTURE_RECORD * nstruct[k]].reshape(-1, STRUCTURE_RECORD))
                at += STRUCTURE_RECORD * nstruct[k]
            parsed.append((recs, b[at:at + PAIR_RECORD * npair].reshape(-1, PAIR_RECORD), nplastic))
            row += own
        f.structure_load[:] = 0.0
        hull_of = {k: h[0] for h in f.hull_pieces for k in h}  # a piece -> its hull's first piece
        touching, self.structure_contacts = {}, 0
        for k in range(ns):
            recs = _by_floe([p[0][k] for p in parsed], lambda r: r[:, 0])
            apply_structure_records(recs, len(recs), f.force, f.torque, f.structure_load[k])
            if k in hull_of:  # a floe across a seam has a record on each piece it overlaps: one contact
                touching.setdefault(hull_of[k], set()).update(recs[:, 0].astype(np.int64).tolist())
            else:
                self.structure_contacts += len(recs)
        self.structure_contacts += sum(len(floes) for floes in touching.values())
        pairs = _by_floe([p[1] for p in parsed], lambda r: np.minimum(r[:, 0], r[:, 1]))
        apply_pair_records(pairs, len(pairs), f.force, f.torque)
        self.contacts = len(pairs)
        self.plastic = sum(p[2] for p in parsed)
        self.body_loads[:] = 0.0
        for k, pieces in enumerate(self.body_pieces):
            for s in pieces:
                self.body_loads[k] += f.structure_load[s]

    # -- state for output and restarts ----------------------------------------------------------
    STATE = ("x", "v", "q", "L", "force", "torque", "structure_load")
    HISTORY = ("cgid", "stamp", "hist")

    def state(self) -> dict:
        """Everything a restart needs (collective: the contact histories come from their owners)."""
        f = self.f
        out = {name: getattr(f, name).copy() for name in self.STATE}
        for name in self.HISTORY:
            a = getattr(f, name)
            rows, _ = self.comm.allgather_doubles(a[self.owned].astype(np.float64).ravel())
            out[name] = np.empty_like(a)
            out[name][self.dealt] = rows.reshape(a.shape).astype(a.dtype)
        out["step_count"] = np.array(f.step_count)
        out["body_loads"] = self.body_loads.copy()
        out["water"] = self.water.copy()
        if f.wave_ends is not None:  # the sea at the floes at the current interval's ends (Floes.sea_at_floes)
            k, ends = f.wave_ends
            rows = [self.comm.allgather_doubles(ends[e, self.owned].ravel())[0] for e in range(2)]
            out["wave_interval"] = np.array(k)
            out["wave_ends"] = np.zeros_like(ends)
            for e in range(2):
                out["wave_ends"][e, self.dealt] = rows[e].reshape(ends.shape[1:])
        return out

    def set_state(self, state: dict, where: str) -> None:
        """The floes as ``state()`` wrote them (every rank); refuses a field of another size."""
        f = self.f
        if len(state["x"]) != self.n:
            raise JobError(f"{where}: holds {len(state['x'])} floes, the job's field has {self.n}; it was written "
                           "for another [floes] field")
        for name in self.STATE + self.HISTORY:
            getattr(f, name)[...] = state[name]
        f.step_count = int(state["step_count"])
        self.body_loads[...] = state["body_loads"]
        self.water[...] = state.get("water", 0.0)  # checkpoints before the column: zero until the next step
        f.wave_ends = (int(state["wave_interval"]), np.array(state["wave_ends"])) if "wave_interval" in state else None
        if f.wave_ends is not None and f.wave_ends[1].shape[-1] != SEA_COLUMNS:
            f.wave_ends = None  # a checkpoint from before u_z was kept: the next step sums the sea again

    def snapshot_arrays(self, first: bool) -> dict:
        """floe_pose (n, 7): x [m], q; floe_velocity (n, 3) [m/s]; the first snapshot also holds the
        floes' shapes: floe_polygon (m, 2) [m] every floe's polygon in its frame, floe_polygon_start
        (n + 1,) where each begins, floe_thickness (n,) [m]."""
        f = self.f
        out = {"floe_pose": np.hstack([f.x, f.q]), "floe_velocity": f.v.copy()}
        if first:
            sizes = [len(p) for p in f.polygons]
            out["floe_polygon"] = np.vstack(f.polygons) if sizes else np.zeros((0, 2))
            out["floe_polygon_start"] = np.concatenate([[0], np.cumsum(sizes)]).astype(np.int64)
            out["floe_thickness"] = f.thickness.copy()
        return out

    def check(self, step: int, time: float) -> None:
        """InstabilityError naming the floe, the step and the likely cause when a floe's state is not
        finite or it moves more than a tenth of its size in one step (every rank alike)."""
        f = self.f
        if not self.n:
            return
        speed = np.linalg.norm(f.v, axis=1)
        bad = ~np.isfinite(speed) | ~np.isfinite(f.x).all(axis=1)
        dt = time / step if step else 0.0
        runaway = speed * dt > 0.1 * f.bound
        if bad.any() or runaway.any():
            from ..errors import InstabilityError

            i = int(np.flatnonzero(bad | runaway)[0])
            what = "a non-finite state (NaN/inf)" if bad[i] else f"a speed of {speed[i]:.3g} m/s"
            raise InstabilityError(
                f"unstable at step {step} (t = {time:.6g} s): floe {i} at {np.array2string(f.x[i], precision=3)} m "
                f"shows {what}; likely cause: floes started overlapping each other or a hull, or a run.dt far "
                "above floes.step_fraction of the contact time (use dt = \"auto\")")

    def wall_loads(self) -> np.ndarray:
        """(n_walls, 6) the floes' load on each confining wall: force [N], moment about the origin [N m]."""
        first = sum(len(p) for p in self.body_pieces)
        return self.f.structure_load[first:].copy()

    def piece_forces(self) -> np.ndarray:
        """(n_bodies, most pieces, 3) the floes' force [N] on each convex piece of each body's hull, in
        the order of body_pieces (a ship's: bow, midbody, stern; platform/ship.py), zeros past a body's
        last piece. Their sum over the pieces is the body's load from the floes (``body_loads``)."""
        most = max((len(p) for p in self.body_pieces), default=0)
        out = np.zeros((len(self.body_pieces), most, 3))
        for k, pieces in enumerate(self.body_pieces):
            for j, s in enumerate(pieces):
                out[k, j] = self.f.structure_load[s, :3]
        return out

    def kinetic_energy(self) -> float:
        """Translational and rotational kinetic energy of all floes [J], with the water's added mass."""
        f = self.f
        return float(0.5 * np.sum((f.mass[:, None] + f.added) * f.v * f.v)
                     + 0.5 * np.sum(np.einsum("ij,ij->i", f.omega, f.L)))

    def series_entries(self) -> dict:
        """The floes' columns of a series row (the same on every rank)."""
        f = self.f
        row = {"floe_contacts": float(self.contacts), "floe_structure_contacts": float(self.structure_contacts),
               "floe_crushing_contacts": float(self.plastic), "floe_kinetic_energy": self.kinetic_energy(),
               "floe_mean_velocity": f.v.mean(axis=0) if self.n else np.zeros(3),
               "floe_wall_force": self.wall_loads()[:, :3],
               "floe_water_force": self.water.sum(axis=0)}
        if any(len(p) > 1 for p in self.body_pieces):  # a hull of several pieces: the load on each
            row["body_piece_force"] = self.piece_forces()
        return row


def _by_floe(parts: list[np.ndarray], floe) -> np.ndarray:
    """The records of every rank (``parts``, each in the order of its floes) merged into the order one
    rank computes them in: a stable sort by ``floe(records)``, the floe each record was computed for."""
    records = np.concatenate(parts) if parts else np.zeros((0, PAIR_RECORD))
    if len(parts) > 1 and len(records):
        records = records[np.argsort(floe(records), kind="stable")]
    return records


def floes_from_job(job, hulls, poses, *, comm) -> FloeSystem:
    """The job's [floes]: the field drawn from its seed, afloat at the Archimedes draft, moving at
    floes.velocity, with every body's hull as a moving structure and the confining walls; floes that
    overlap a hull at t = 0 are left out (logged)."""
    from ..scenes.floe_field import floe_field
    from .waves import sea_from_job

    spec, water = job.floes, job.water
    try:
        field = floe_field(area=spec.area, size=spec.size, thickness=spec.thickness,
                           concentration=spec.concentration, seed=spec.seed)
    except ValueError as exc:
        raise JobError(f"{job.source}: floes: {exc}") from None
    c = spec.contact
    law = FloeLaw.from_spec(c)
    fw = FloeWater(density=water.density, level=water.level, gravity=job.gravity, current=tuple(water.current),
                   skin=spec.skin_drag_coefficient, form=spec.form_drag_coefficient, damping_ratio=spec.damping_ratio,
                   sea=sea_from_job(job))
    thickness = np.asarray(field.thickness, float)
    base = water.level - thickness * spec.density / water.density
    floes = Floes(field.polygons, thickness, density=spec.density, base=base,
                  velocity=(spec.velocity[0], spec.velocity[1], 0.0), law=law, water=fw,
                  added_mass=spec.added_mass == "plate")
    body_pieces = add_body_structures(floes, job, hulls, poses)
    floes = _without_overlaps(floes, field, thickness, base, spec, law, fw, body_pieces, job)
    if spec.sides == "confined":
        x0, y0, x1, y1 = spec.area
        floes.add_wall((0.0, -1.0, 0.0), -y0)   # y <= y0 is wall
        floes.add_wall((0.0, 1.0, 0.0), y1)     # y >= y1 is wall
    return FloeSystem(floes, comm, body_pieces)


def add_body_structures(floes: Floes, job, hulls, poses) -> list[list[int]]:
    """Every body's hull as moving convex structures of ``floes`` (revolved hulls their frusta, a box
    itself, a ship its three pieces) at its pose; returns each body's structure indices."""
    from ..platform.hulls import revolved

    body_pieces = []
    for k, body in enumerate(job.bodies):
        hull = body.hull
        if hull.type == "revolved":
            prof = np.asarray(hull.profile, float)
            pieces = [revolved(prof[i:i + 2], min(hull.segments, 40)) for i in range(len(prof) - 1)]
        elif hull.type == "box":
            pieces = [(hulls[k].vertices, hulls[k].triangles)]
        elif hull.type == "ship":  # bow, midbody, stern (platform/ship.py)
            from ..platform.ship import ship_hull
            pieces = ship_hull(hull)[0]
        else:
            raise JobError(f"{job.source}: bodies[{k}].hull.type = {hull.type!r}: rigid ice (floes, keel blocks) "
                           "meets convex hulls only: a \"revolved\" hull (each ring to the next is a convex "
                           "frustum), a \"box\" or a \"ship\"; give the body such a hull")
        first = len(floes.structures)
        for v, t in pieces:
            floes.add_structure(v, t, centre=np.zeros(3), friction=body.friction)  # ice-hull friction
        body_pieces.append(list(range(first, first + len(pieces))))
        floes.join_pieces(body_pieces[-1])  # one contact per floe and hull, not one per piece
        for s in body_pieces[-1]:
            floes.move_structure(s, x=poses[k, :3], q=poses[k, 3:7], v=poses[k, 7:10], w=poses[k, 10:13])
    return body_pieces


def _without_overlaps(floes, field, thickness, base, spec, law, fw, body_pieces, job) -> Floes:
    """``floes`` rebuilt without the floes that overlap a body's hull at t = 0 (logged)."""
    if not floes.structures:
        return floes
    pts, counts = floes.world()
    from ..kernels.floe_motion import world_polyhedra

    hit = np.zeros(len(floes.mass), bool)
    for st in floes.structures:
        s_pts = world_polyhedra(st["local"][None], st["counts"][None], st["x"][None], st["q"][None])[0]
        for i in range(len(floes.mass)):
            if np.linalg.norm(floes.x[i] - st["x"]) < floes.bound[i] + st["bound"]:
                if contact_geometry(pts[i], counts[i], s_pts, st["counts"])[0] > 0.0:
                    hit[i] = True
    if not hit.any():
        return floes
    keep = np.flatnonzero(~hit)
    box_area = (spec.area[2] - spec.area[0]) * (spec.area[3] - spec.area[1])
    logging.getLogger("pice").info(
        "floes: %d of %d floes overlap a hull at t = 0 and are left out (concentration %.3f -> %.3f over the area)",
        int(hit.sum()), len(hit), floes.area.sum() / box_area, floes.area[keep].sum() / box_area)
    structures = floes.structures
    out = Floes([field.polygons[i] for i in keep], thickness[keep], density=spec.density, base=base[keep],
                velocity=(spec.velocity[0], spec.velocity[1], 0.0), law=law, water=fw,
                added_mass=spec.added_mass == "plate")
    out.structures = structures
    out.structure_load = np.zeros((len(structures), 6))
    return out


def contact_steps(law, m: float, fraction: float) -> tuple[float, float]:
    """(the stability limit [s] of the lightest contact: two pieces of mass m [kg], or one against a
    structure; ``fraction`` of that pair's contact time m_eff / c_n [s], inf without a dashpot)."""
    stable = min(contact_step_limit(law, 0.5 * m), contact_step_limit(law, m))
    cn = law.damping(0.5 * m)  # with a damping ratio, m_eff / c_n grows as sqrt(m_eff): the lightest pair's is least
    return stable, (fraction * 0.5 * m / cn if cn > 0 else math.inf)


def floe_time_step(job, system: FloeSystem | None) -> StepLimit:
    """The step of a scene without level ice: the floes' contact law sets it. The stability limit is
    that of the lightest contact (two of the smallest floes; one against a structure); "auto" takes
    the smaller of run.dt_safety of it and floes.step_fraction of that contact's duration m_eff / c_n
    (the dashpot's time; docs/broken_ice.md, "The time step"). A scene of bodies alone
    has no contact law: it needs run.dt."""
    from .timestep import choose_step

    run = job.run
    if system is None or system.n == 0:
        if run.dt == "auto":
            raise JobError(f"{job.source}: run.dt = \"auto\": a scene without ice has no contact law to set the step; "
                           "give run.dt [s] (the bodies' motions are slow: 0.01 s is typical)")
        return StepLimit(stable=math.inf, chosen=float(run.dt), safety=0.0, governed_by="given (no ice)")
    law, m = system.f.law, float(system.f.mass.min())
    key, fraction = ("floes", job.floes.step_fraction) if job.floes is not None else ("keel", job.keel.step_fraction)
    stable, accurate = contact_steps(law, m, fraction)
    limit = choose_step(requested=run.dt, safety=run.dt_safety, stable=stable,
                        governed_by=f"floe contact, k_n {law.kn:.3g} N/m, c_n {law.damping(0.5 * m):.3g} N s/m, "
                                    f"m_eff {0.5 * m:.4g} kg",
                        allow_unstable=run.allow_unstable_dt, source=job.source)
    if run.dt == "auto":
        if accurate < limit.chosen:
            return StepLimit(stable=stable, chosen=accurate, safety=accurate / stable,
                             governed_by=f"{key}.step_fraction {fraction:g} of the contact time "
                                         f"m_eff / c_n = {0.5 * m / law.damping(0.5 * m):.4g} s")
    return limit


