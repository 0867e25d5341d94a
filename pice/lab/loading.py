"""Quasi-static loading of a lab specimen: the displacement program and the recorded run.

The driven elements (a platen, a load or tip line) move with a prescribed velocity. The program:

1. a smooth start, v(t) = V (1 - cos(pi t / t_r)) / 2 over t_r = 2 T, T the specimen's fundamental
   period: a ramp lasting a whole number of periods leaves no free vibration in the modes whose
   frequencies are integer multiples of the fundamental (the axial modes of the block, the bending
   modes of the simply supported beam), and little in the others;
2. the constant speed V = delta_ref / (periods T): the displacement delta_ref at which the specimen
   would carry the intended strength is reached after ``periods`` fundamental periods;
3. beyond delta_ref, v = delta / tau with tau = delta_ref / V (the speed grows with the displacement):
   a specimen stronger than intended still fails after a few tau, and stays as quasi-static as at
   delta_ref (the inertia force ~ m delta / tau^2 keeps its ratio (T / (2 pi tau))^2 to the elastic
   one).

Every step the forces on each held set (the sum of ``p.force`` [N], the reaction the specimen
exerts on them) and the displacement of the driven set [m] are recorded. ``Run.inertia`` measures
how quasi-static the loading was where it is measured (the fit window and the first break): the sum
of the forces on all held sets is minus the inertia force of the free elements (the bonds' forces
cancel in pairs), reported as a fraction of the load.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

RAMP_PERIODS = 2.0  # smooth start over this many fundamental periods


@dataclass(frozen=True)
class Program:
    """Prescribed speed [m/s] of the driven elements against time t [s] and displacement delta [m]."""

    speed: float        # V [m/s]
    ramp: float         # t_r [s]
    tau: float          # delta_ref / V [s]

    def velocity(self, t: float, delta: float) -> float:
        if t < self.ramp:
            return self.speed * 0.5 * (1.0 - math.cos(math.pi * t / self.ramp))
        return max(self.speed, delta / self.tau)

    @classmethod
    def for_specimen(cls, *, reference: float, period: float, periods: float,
                     ramp_periods: float = RAMP_PERIODS) -> "Program":
        """The program reaching ``reference`` [m] after ``periods`` fundamental periods ``period`` [s],
        starting smoothly over ``ramp_periods`` of them."""
        tau = periods * period
        return cls(speed=reference / tau, ramp=ramp_periods * period, tau=tau)


@dataclass
class Run:
    """The record of a loaded specimen: time [s], driven displacement [m], forces on each held set [N]
    along the driven axis, broken bonds, and snapshots of the positions (for profiles and gauges)."""

    time: list = field(default_factory=list)
    delta: list = field(default_factory=list)
    forces: dict = field(default_factory=dict)
    broken: list = field(default_factory=list)
    gauges: dict = field(default_factory=dict)
    snapshots: list = field(default_factory=list)   # (record index, positions (n, 3) [m], rotations (n, 3) [rad])
    first_break: int | None = None                  # record index of the step that broke the first bond
    first_modes: dict = field(default_factory=dict)  # failure mode -> bonds broken at the first break
    modes: dict = field(default_factory=dict)        # failure mode -> bonds broken over the run
    stopped: str = ""
    steps: int = 0

    def array(self, key: str) -> np.ndarray:
        return np.asarray(self.forces[key] if key in self.forces else getattr(self, key), dtype=float)

    def inertia(self, sets, load: str, indices) -> float:
        """Largest |sum of the forces on all held ``sets``| / |force on the ``load`` set| [-] over the
        record ``indices`` (those a measurement uses)."""
        idx = np.asarray(indices, dtype=int)
        total = np.abs(sum(self.array(k) for k in sets))[idx]
        f = np.abs(self.array(load))[idx]
        keep = f > 0.0
        return float((total[keep] / f[keep]).max()) if keep.any() else 0.0


def load_specimen(spec, *, driven: str, axis: int, sign: float, program: Program, sets: list[str],
                  stop, gauges=None, snapshot_every: float = 0.0, max_time: float = math.inf) -> Run:
    """Run the specimen under the program until ``stop(run, i)`` says so (checked every step, i the
    record index) or ``max_time`` [s].

    driven: the held set that moves, along ``axis`` (0 x, 2 z) in the direction ``sign`` (+-1);
    sets: the held sets whose forces are recorded (component ``axis``); gauges: name -> function(p)
    returning a float, recorded every step; snapshot_every: record the positions every this many
    seconds (0: never).
    """
    sim = spec.sim
    p = sim.p
    idx = spec.sets[driven]
    run = Run(forces={k: [] for k in sets}, gauges={k: [] for k in (gauges or {})})
    check_every = sim.job.run.check_every
    next_snap = 0.0
    broken0 = sim.c.broken
    rotation = np.zeros((p.nlocal, 3))  # the elements' rotation [rad]: the time integral of p.w (small angles)
    delta = 0.0  # the driven elements move by exactly their prescribed velocity times dt each step
    while True:
        v = program.velocity(sim.c.time, delta)
        p.fix_velocity[idx, axis] = sign * v
        delta += v * sim.dt
        n_events = len(sim.c.events)
        sim.step()
        for k in spec.held_rotation:  # a rotation fix: no spin now, none from this step's torque next step
            p.w[spec.sets[k]] = 0.0
            p.torque[spec.sets[k]] = 0.0
        run.steps += 1
        rotation += p.w[:p.nlocal] * sim.dt
        if run.steps % check_every == 0:
            sim.check_health()
        run.time.append(sim.c.time)
        run.delta.append(delta)
        for k in sets:
            run.forces[k].append(float(p.force[spec.sets[k], axis].sum()))
        for k, g in (gauges or {}).items():
            run.gauges[k].append(g(p))
        run.broken.append(sim.c.broken - broken0)
        i = len(run.time) - 1
        if len(sim.c.events) > n_events:
            new = [ev[-1] for ev in sim.c.events[n_events:]]
            for mode in new:
                run.modes[mode] = run.modes.get(mode, 0) + 1
            if run.first_break is None:
                run.first_break = i
                run.first_modes = {m: new.count(m) for m in set(new)}
        if snapshot_every > 0 and sim.c.time >= next_snap:
            run.snapshots.append((i, p.x[:p.nlocal].copy(), rotation.copy()))
            next_snap += snapshot_every
        why = stop(run, i)
        if why:
            run.stopped = why
            return run
        if sim.c.time >= max_time:
            run.stopped = f"time limit {max_time:.3g} s"
            return run
