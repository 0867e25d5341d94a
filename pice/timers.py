"""Timers of the step, per rank: off by default, and then nothing reads a clock (pice bench, mpi/scaling.py).

A Simulation runs its plain step unless ``Simulation.enable_timers()`` has switched it to the timed
step, which calls the same functions in the same order and, between them, ``StepTimers.lap(part)``:
the wall time since the previous lap is charged to ``part``. The laps follow one another without
gaps, so over a window (``start`` to the last lap) the parts add up to the window's wall time; what
happens between two laps that is not the part named (loop control, a counter) goes to the later
lap's part and is microseconds a step.

``summary(comm)`` gathers every rank's figures on rank 0 at the end: per part the milliseconds per
step on each rank, their mean and maximum over ranks, and the mean's share of the step.
"""

from __future__ import annotations

from collections import deque
from time import perf_counter

import numpy as np

#: the steps' waits for the ghost update kept for the summary's distribution (the last ones)
GHOST_WAITS_KEPT = 100_000

#: the parts of a step, in the order they are reported, with what each holds
PARTS = {
    "bonds": "bond forces and failure (physics/bond.py)",
    "contacts": "ice-ice contacts with their neighbour search (cell list)",
    "walls": "contacts with [[walls]]",
    "hydro": "water (buoyancy, drag) or gravity",
    "boundary": "far-field springs of [ice.push]",
    "hull": "ice contacts with the hulls",
    "integration": "kicks and drift of the ice, zeroing of the forces",
    "halo": "ghost exchange, migration and halo rebuilds, load balance (local work and messages)",
    "waiting": "collectives: the loads' reduction, the poses' broadcast, the rebuild check, the health "
               "check's flags and bond lengths (where ranks wait for the slowest)",
    "platform": "rank 0: the bodies' and lines' kick, drift and loads",
    "floes": "the floes' water loads, contacts and their Allgatherv (physics/floe_system.py)",
    "checks": "the health check's local work, the removal of crushed-through elements",
    "output": "series rows and broken-bond events (pice bench writes them at the job's series_every)",
    "other": "force terms without a part of their own, the loads' assembly before the reduction",
}

#: force term name (``term.name``) -> the part its ``add_forces`` is charged to
TERM_PARTS = {"bonds": "bonds", "ice contacts": "contacts", "walls": "walls", "water": "hydro",
              "gravity": "hydro", "spring boundary": "boundary", "hull contact": "hull"}


def term_part(term) -> str:
    """The part a force term's time is charged to ("other" for a term this table does not know)."""
    return TERM_PARTS.get(getattr(term, "name", ""), "other")


class StepTimers:
    """Seconds per part of the step on this rank, over the window since ``start``."""

    def __init__(self):
        self.seconds = dict.fromkeys(PARTS, 0.0)  # [s] per part since start
        self.steps = 0                            # steps taken since start
        self.mark = perf_counter()                # [s] the clock at the last lap
        self.ghost_waits = deque(maxlen=GHOST_WAITS_KEPT)  # [s] each step's wait for the ghost update

    def start(self) -> None:
        """Zero the figures and start a window now."""
        self.seconds = dict.fromkeys(PARTS, 0.0)
        self.steps = 0
        self.mark = perf_counter()
        self.ghost_waits.clear()

    def lap(self, part: str) -> float:
        """Charge the wall time since the previous lap (or ``start``) to ``part``; returns it [s]."""
        now = perf_counter()
        spent = now - self.mark
        self.seconds[part] += spent
        self.mark = now
        return spent

    def total(self) -> float:
        """Wall seconds of the window so far (start to the last lap) on this rank [s]."""
        return sum(self.seconds.values())

    def summary(self, comm) -> dict | None:
        """Collective: every rank's milliseconds per step, gathered on rank 0 (None on the others).

        Returns {"ranks", "steps", "ms_per_step" (mean over ranks of the sum of the parts),
        "max_ms_per_step", "parts": {part: {"ms_per_step" (mean over ranks), "max_ms_per_step",
        "percent" (of the mean step), "per_rank_ms_per_step": [...]}}, "ghost_wait_ms": per rank, the
        median, 90th percentile and largest of its steps' waits for the ghost update (None where it
        received none)}. A wait's median against its mean tells a message that does not travel
        while the ranks compute (every step waits) from ranks held up now and then (a tail).
        """
        waits = np.asarray(self.ghost_waits) * 1e3  # [ms]
        tail = [float(np.median(waits)), float(np.percentile(waits, 90)), float(waits.max())] if len(waits) else None
        rows = comm.gather([self.seconds[k] for k in PARTS] + [float(self.steps)])
        tails = comm.gather(tail)
        if rows is None:
            return None
        table = np.asarray(rows, dtype=float)
        steps = np.maximum(table[:, -1], 1.0)
        ms = table[:, :-1] / steps[:, None] * 1e3  # [ms per step] per rank and part
        per_rank_total = ms.sum(axis=1)
        mean_total = float(per_rank_total.mean())
        parts = {}
        for k, name in enumerate(PARTS):
            mean = float(ms[:, k].mean())
            parts[name] = {"ms_per_step": mean, "max_ms_per_step": float(ms[:, k].max()),
                           "percent": 100.0 * mean / mean_total if mean_total > 0 else 0.0,
                           "per_rank_ms_per_step": [float(v) for v in ms[:, k]]}
        return {"ranks": len(rows), "steps": int(table[0, -1]), "ms_per_step": mean_total,
                "max_ms_per_step": float(per_rank_total.max()), "parts": parts,
                "ghost_wait_ms": [None if t is None else dict(zip(("median", "p90", "max"), t)) for t in tails]}
