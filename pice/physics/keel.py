"""A ridge keel generated as seed 002 does it (Gong, Polojärvi & Tuhkuri 2017, section 2; issue 15):
blocks released under water beneath a rigid cover, packed by their buoyancy until the kinetic energy
has decayed, then trimmed to the keel's shape (scenes/rubble.py).

The blocks are the broken-ice issue's rigid convex pieces (physics/floes.py, physics/floe_system.py):
one code path, one contact law (seed 003's, [keel.contact]), the same MPI contract (every rank holds
every block, each computes its block of them; the same bits on any rank count). The basin is walls:
the cover (z >= keel.cover is solid, with the ice-ice friction: it holds the pile, seed 002), and the
ends of the keel's length (y = y0 and y0 + length), where seed 002's basin walls touch the pile; along
x, walls at the keel's top corners while it settles (``keel_walls``), and the trim cuts the slopes.

keel.settle_friction, when given, replaces the contact's friction while the blocks settle (the ship
run has the contact's): docs/ridge_keel.md, "Porosity". With keel.lock_speed the contact's friction
returns once the RMS speed falls below it, and locks the packed pile to rest (a staged settling: the
blocks pack without friction, then stop with it).

Settled: the RMS speed of the blocks below keel.settle_speed, checked every SETTLE_CHECK s of
simulated time; a generation that has not settled after keel.settle_time is refused with the speed it
reached.
"""

from __future__ import annotations

import dataclasses
import logging
import math
from dataclasses import dataclass

import numpy as np

from ..errors import JobError
from ..kernels.geometry import quat_mul
from ..scenes.rubble import inside_keel, porosity, release_blocks
from .floe_system import FloeSystem, add_body_structures, contact_steps
from .floes import FloeLaw, Floes, FloeWater

log = logging.getLogger("pice")

SETTLE_CHECK = 0.5  # [s] of simulated time between the checks of the blocks' speed


@dataclass
class Keel:
    """A generated keel: its blocks (rectangles (n, 4, 2) [m] in their frames, centres (n, 3) [m],
    attitudes (n, 4)), the time it took to settle [s], the RMS speed then [m/s], the released count
    and the porosity of the trimmed keel (whole prism and its core 0.5 m in from the slopes and the
    bottom); the time the staged settling's friction returned [s] (NaN: no keel.lock_speed)."""

    rects: np.ndarray
    x: np.ndarray
    q: np.ndarray
    settle_time: float
    rms_speed: float
    released: int
    porosity: float
    core_porosity: float
    locked_at: float = math.nan


def keel_law(keel) -> FloeLaw:
    return FloeLaw.from_spec(keel.contact)


def settling_law(keel) -> FloeLaw:
    """The contact law while the blocks settle: [keel.contact], with keel.settle_friction (between the
    blocks and with the cover and walls) in place of its friction when given."""
    law = keel_law(keel)
    return law if keel.settle_friction is None else dataclasses.replace(law, mu=keel.settle_friction)


def keel_water(job) -> FloeWater:
    """Still water for the blocks: drag on the relative velocity (the floes' skin drag, and form drag
    with keel.form_drag_coefficient) and no waves (a keel under a cover)."""
    w = job.water
    return FloeWater(density=w.density, level=w.level, gravity=job.gravity, current=tuple(w.current), sea=None,
                     form=job.keel.form_drag_coefficient)


def blocks_as_floes(keel, rects, x, q, law, water) -> Floes:
    """Floes (rigid prisms) for the blocks: each rectangle about its centre, turned by q."""
    b = keel.blocks
    polygons = rects + x[:, None, :2]
    floes = Floes(list(polygons), np.full(len(rects), b.thickness), density=b.density,
                  base=x[:, 2] - 0.5 * b.thickness, law=law, water=water)
    for i in range(len(rects)):  # the prism's principal frame, then the block's attitude
        floes.q[i] = quat_mul(q[i], floes.q[i])
    return floes


def keel_walls(floes: Floes, keel, *, generation: bool = False, symmetry: bool = False) -> None:
    """The cover and the basin's end walls as half-spaces (module docstring); for the generation also
    walls at the keel's top corners, x = x -+ w / 2, which hold the pile while it settles (without
    them it creeps outwards under the cover for minutes; the trim then cuts the slopes).
    ``symmetry``: the wall at y0 is a half model's symmetry plane, frictionless (the mirrored rubble
    would move with the rubble there: no shear acts across the plane); the others have the contact's
    friction (the cover holds the pile by it, as seed 002's does)."""
    floes.add_wall((0.0, 0.0, 1.0), keel.cover)                      # z >= cover: the cover
    floes.add_wall((0.0, -1.0, 0.0), -keel.y0, 0.0 if symmetry else None)  # y <= y0
    floes.add_wall((0.0, 1.0, 0.0), keel.y0 + keel.length)           # y >= y0 + length
    if generation:
        floes.add_wall((-1.0, 0.0, 0.0), -(keel.x - 0.5 * keel.width))  # x <= x - w / 2
        floes.add_wall((1.0, 0.0, 0.0), keel.x + 0.5 * keel.width)      # x >= x + w / 2


def keel_step(keel, floes: Floes) -> float:
    """The time step [s]: keel.step_fraction of the contact time m_eff / c_n of the two lightest blocks,
    within the contact's stability limit."""
    stable, accurate = contact_steps(floes.law, float(floes.mass.min()), keel.step_fraction)
    return min(0.5 * stable, accurate)


# a measured generation on the project's 2-core machine: blocks released, its step [s], wall time on 2 ranks
# [s]. The 80 m keel kept in jobs/keels/, at the jobs' step_fraction 0.3 (docs/ridge_keel.md, "The 80 m keel on
# the jobs' blocks": 2 h 33 min to t = 50.5 s and 910 s more from its checkpoint, less the 240 s its trim's
# porosity then took). The narrow kept keel's (10,750 blocks at 0.1, 2.914e-4 s, 7,346 s) gave 3.1 h for it,
# about 11 % high (the cause not traced); the jobs' keels are all generated at 0.3, as this one was
MEASURED_GENERATION = (49_707, 8.740e-4, 9850.0)


def generation_facts(job) -> dict:
    """What `pice check` says of a keel not yet generated: the blocks released, their mass range [kg],
    the settling's time step [s], the limit of the settling's time [s], and a rough wall time on 2
    ranks [h]: MEASURED_GENERATION's, in proportion to the blocks and to the steps (a pile settles in
    about the same simulated time at any width: its depth sets it)."""
    keel = job.keel
    rects, x, q = release_blocks(keel)
    floes = blocks_as_floes(keel, rects, x, q, settling_law(keel), keel_water(job))
    dt = keel_step(keel, floes)
    blocks, dt_measured, wall = MEASURED_GENERATION
    return dict(released=len(rects), mass_range=(float(floes.mass.min()), float(floes.mass.max())),
                dt=dt, settle_time=keel.settle_time, hours=wall / 3600.0 * len(rects) / blocks * dt_measured / dt)


def settle_steps(system: FloeSystem, n: int, t: float, dt: float) -> float:
    """``n`` velocity-Verlet steps of dt [s] of the settling blocks (no bodies), from time t; returns
    the time reached [s]."""
    none = np.zeros((0, 13))
    for _ in range(n):
        system.kick(0.5 * dt)
        system.drift(dt)
        t += dt
        system.compute_forces(none, t, dt)
        system.kick(0.5 * dt)
    return t


def generate_keel(job, comm, *, progress=None, resume=None, save=None) -> Keel:
    """Release, settle and trim the job's keel on the ranks of ``comm`` (module docstring).

    ``resume``: (t [s], FloeSystem.state()) of an unfinished generation of the same keel, to continue
    from (the same bits as a generation never stopped); ``save``: called with (t, state) at every
    check of the speed (collective: the state gathers the contact histories), so that a killed or
    unsettled generation can be continued (io/keel_file.py's generation checkpoint)."""
    keel = job.keel
    rects, x, q = release_blocks(keel)
    floes = blocks_as_floes(keel, rects, x, q, settling_law(keel), keel_water(job))
    keel_walls(floes, keel, generation=True, symmetry=job.half_model)
    system = FloeSystem(floes, comm, [])
    dt = keel_step(keel, floes)
    every = max(1, int(round(SETTLE_CHECK / dt)))
    none = np.zeros((0, 13))
    t, rms, locked, locked_at = 0.0, math.inf, False, math.nan
    if resume is not None:
        t = float(resume[0])
        system.set_state(resume[1], f"{job.source}: the keel's generation checkpoint")
        locked_at = float(resume[1].get("locked_at", math.nan))
        locked = math.isfinite(locked_at)
        if locked:
            floes.law = keel_law(keel)
    else:
        system.compute_forces(none, 0.0, dt)
    while t < keel.settle_time:
        t = settle_steps(system, every, t, dt)
        rms = math.sqrt(float((floes.v ** 2).sum(axis=1).mean()))
        lock = not locked and keel.lock_speed is not None and rms < keel.lock_speed
        if lock:  # the staged settling's second stage: the contact's friction stops the packed pile
            locked, locked_at, floes.law = True, t, keel_law(keel)
            log.info("keel: RMS speed %.3g m/s at %.4g s, below keel.lock_speed: friction %g from now on", rms, t,
                     floes.law.mu)
        if save is not None:
            save(t, {**system.state(), "locked_at": np.array(locked_at)})
        if progress is not None:
            progress(t, rms, system.contacts)
        if rms < keel.settle_speed and not lock:
            break
    else:
        raise JobError(f"{job.source}: keel.settle_time = {keel.settle_time:g}: the blocks still move at "
                       f"{rms:.3g} m/s RMS after {t:.4g} s, more than keel.settle_speed = {keel.settle_speed:g} "
                       "m/s; give a longer settle_time")
    rot = floes.q.copy()
    keep = inside_keel(keel, floes.x)
    body = np.array(floes.polygons)[keep]  # in each prism's principal frame, which rot turns
    centres, turned = floes.x[keep].copy(), rot[keep]
    p_all = porosity(keel, centres, turned, body, keel.blocks.thickness)
    p_core = porosity(keel, centres, turned, body, keel.blocks.thickness, core=0.5)
    log.info("keel: %d of %d blocks settled in %.4g s (RMS speed %.3g m/s) lie inside the keel; porosity %.3f "
             "(core %.3f)", int(keep.sum()), len(rects), t, rms, p_all, p_core)
    return Keel(body, centres, turned, t, rms, len(rects), p_all, p_core, locked_at)



def trim_keel(keel, wider: dict) -> Keel:
    """``keel`` (a KeelSpec) trimmed from the middle of a wider settled keel (``wider``: its file's blocks
    and records, io/keel_file.read_trim_source): the wider keel's blocks moved along x by keel.x minus
    its centre, those whose centres lie inside ``keel`` kept (the generation's own trim), the porosity
    measured again. The two trapezoids share depth and pile angle, so the narrower one, centred on the
    wider, lies inside it; its middle is the part of the settled pile farthest from the generation's end
    walls. Settling time, RMS speed, released count and lock time are the wider generation's."""
    centres = wider["x"] + np.array([keel.x - wider["x_centre"], 0.0, 0.0])
    keep = inside_keel(keel, centres)
    body, centres, turned = wider["rects"][keep], centres[keep], wider["q"][keep]
    p_all = porosity(keel, centres, turned, body, keel.blocks.thickness)
    p_core = porosity(keel, centres, turned, body, keel.blocks.thickness, core=0.5)
    log.info("keel: %d of the %d blocks of a %.4g m wide keel lie inside this %.4g m one; porosity %.3f (core %.3f)",
             int(keep.sum()), len(keep), wider["width"], keel.width, p_all, p_core)
    return Keel(body, centres, turned, wider["settle_time"], wider["rms_speed"], wider["released"], p_all, p_core,
                wider["locked_at"])


def keel_from_job(job, hulls, poses, *, comm, base_dir=None) -> FloeSystem:
    """The job's settled keel (its file, io/keel_file.py) as rigid pieces with the cover, the end walls
    and every body's hull (floe_system.add_body_structures), for a ship run; [keel.contact] may differ
    from the generation's (logged)."""
    from ..io.keel_file import keel_path, read_keel

    keel = job.keel
    path = keel_path(job, base_dir)
    data = read_keel(path, keel, job.source)
    if data["contact"] != keel.contact.model_dump(mode="json"):
        log.info("keel: %s was settled with another contact (%s); this run's is %s", path, data["contact"],
                 keel.contact.model_dump(mode="json"))
    floes = blocks_as_floes(keel, data["rects"], data["x"], data["q"], keel_law(keel), keel_water(job))
    pieces = add_body_structures(floes, job, hulls, poses)
    keel_walls(floes, keel, symmetry=job.half_model)
    log.info("keel: %d blocks from %s (porosity %.3f, its core %.3f)", len(data["x"]), path, data["porosity"],
             data["core_porosity"])
    return FloeSystem(floes, comm, pieces)
