"""The domain of one rank: its subdomain of the decomposition, its halo, and keeping both current.

The ice is cut in x-y into one subdomain per rank (decomposition.py). Each step the ghosts are
refreshed (halo.py): their positions and velocities only, or a full migration and rebuild when some
particle has moved half the skin (checked every few steps, as a bound on the motion allows); every
``balance_every`` steps the cuts move when the ranks' particle counts drift apart (balance.py), or,
with ``balance_by = "time"``, when their busy times do: each rank's wall time since the last check
minus what it spent waiting inside MPI calls (``comm.blocked``, parallel/comm.py); its particles then
weigh its busy time per particle, so the cuts even out the work. The first check after a start or a
restart only starts the clock (it would count numba's compilation) and balances the elements. With
``balance_by = "work"`` each particle weighs its own modelled work (``Domain.work``, given by the
simulation: its contacts, which sit where the ice is broken, cost more than its bonds), a function
of the state alone, so that the cuts, and a run, stay repeatable bit for bit.
"""

from __future__ import annotations

import logging
from time import perf_counter

import numpy as np

from .balance import imbalance, rebalanced
from .decomposition import Decomposition, uniform
from .halo import Halo

log = logging.getLogger("pice")


def ghost_width(p, bond, skin: float) -> float:
    """Halo width [m]: the contact reach or the longest bond at its breaking stretch, plus the skin.

    p: the whole sheet's particles (as every rank builds it); bond: physics.bond.BondParams.
    """
    reach = 2.0 * float(p.radius.max())
    longest = float(p.bond_L0.max()) if p.bond_L0.size else 0.0
    if np.isfinite(bond.normal_strength):
        longest += bond.normal_strength * bond.area / bond.kn  # stretch at which tension alone breaks it
    else:
        longest *= 1.5  # unbreakable bonds: allow 50 % stretch; the run checks it
    return max(reach, longest) + skin


class Domain:
    """The decomposition and halo of one rank, and the exchanges of the step."""

    def __init__(self, comm, parallel, *, ghost_width: float, dt: float, work=None):
        """parallel: the job's [parallel] section (skin, balance_every, imbalance_threshold, domain);
        ghost_width [m]; dt: the time step [s] (the halo's rebuild check bounds the motion with it);
        work: p -> (nlocal,) the modelled work of each owned particle in whole numbers, for
        ``balance_by = "work"`` (physics/work.py; None: 1 each)."""
        self.comm, self.parallel, self.ghost_width, self.dt = comm, parallel, ghost_width, dt
        self.decomp: Decomposition | None = None
        self.halo: Halo | None = None
        self.imbalance = 1.0
        self._clock = None  # (wall time [s], comm.blocked [s]) at the last balance check (balance_by "time")
        self.work = work

    def distribute(self, p) -> None:
        """Decompose the whole sheet ``p`` over the ranks, keep this rank's part, build the halo."""
        par = self.parallel
        if par.domain is not None:
            lo, hi = par.domain
        elif p.n == 0:  # no level ice (floes, bodies): a nominal domain with nothing in it
            lo, hi = (0.0, 0.0), (1.0, 1.0)
        else:
            lo, hi = tuple(p.x[:, :2].min(axis=0)), tuple(p.x[:, :2].max(axis=0))
        self.decomp = uniform(self.comm.size, lo=lo, hi=hi)
        self.halo = Halo(self.comm, self.decomp, ghost_width=self.ghost_width, skin=par.skin, dt=self.dt)
        if self.comm.size > 1:
            mine = np.nonzero(self.decomp.owner(p.x[:, 0], p.x[:, 1]) == self.comm.rank)[0]
            p.replace_rows([p.rows(mine)], len(mine))
        self.halo.rebuild(p)

    def adopt(self, p, decomp: Decomposition) -> None:
        """Take ``decomp`` (from a checkpoint) for particles ``p`` already placed on their ranks."""
        self.decomp = decomp
        self.halo = Halo(self.comm, decomp, ghost_width=self.ghost_width, skin=self.parallel.skin,
                         dt=self.dt)
        self.halo.rebuild(p)

    def exchange(self, p, step: int, timers=None) -> None:
        """After the drift: rebalance on schedule, else rebuild the halo if needed (both at once),
        else post the ghost update, which ``finish_exchange`` receives: the forces on owned elements
        that need no ghost are computed in between, while the messages travel.

        ``timers``: the timed step's StepTimers (pice/timers.py), charged "halo" for the exchange and
        "waiting" for the rebuild check's reduction; None in the plain step (no clock is read)."""
        every = self.parallel.balance_every
        if self.comm.size > 1 and every and step % every == 0 and self.rebalance(p, step):
            if timers is not None:
                timers.lap("halo")
            return
        if self.halo.needs_rebuild(p, timers):
            self.halo.rebuild(p)
        else:
            self.halo.start_update(p)
        if timers is not None:
            timers.lap("halo")

    def finish_exchange(self, p, timers=None) -> None:
        """Receive the ghost update that ``exchange`` posted (a no-op when none is pending); the time
        is charged "waiting"."""
        pending = self.halo.pending
        self.halo.finish_update(p)
        if timers is not None:
            spent = timers.lap("waiting")
            if pending:
                timers.ghost_waits.append(spent)

    def rebalance(self, p, step: int) -> bool:
        """Move the cuts if max/mean particles per rank (``balance_by = "time"``: busy time per rank;
        "work": modelled work per rank) exceeds the threshold; True if it did (and rebuilt)."""
        by = self.parallel.balance_by
        busy = self._busy_time() if by == "time" else None
        weight, what = None, "particles"
        if by == "work" and self.work is not None:
            weight, what = self.work(p), "modelled work"
            mine = float(weight.sum())
            self.imbalance = self.comm.max(mine) / max(self.comm.sum(mine) / self.comm.size, 1.0)
        elif busy is None:
            self.imbalance = imbalance(self.comm, p.nlocal)
        else:
            self.imbalance = self.comm.max(busy) / (self.comm.sum(busy) / self.comm.size)
            weight, what = busy / max(p.nlocal, 1), "busy time"
        if self.imbalance <= self.parallel.imbalance_threshold:
            return False
        before = self.imbalance
        self.decomp = rebalanced(self.comm, self.decomp, p.x[:p.nlocal], weight)
        self.halo.decomp = self.decomp
        self.halo.rebuild(p)
        self.imbalance = imbalance(self.comm, p.nlocal)
        if self.comm.rank == 0:
            log.info("step %d: load balance of the %s %.3f; max/mean particles per rank now %.3f", step, what,
                     before, self.imbalance)
        if busy is not None:
            self._busy_time()  # the next window starts after the rebuild
        return True

    def _busy_time(self) -> float | None:
        """This rank's busy time [s] since the last call (None at the first: the clock starts)."""
        now = (perf_counter(), self.comm.blocked)
        last, self._clock = self._clock, now
        return None if last is None else (now[0] - last[0]) - (now[1] - last[1])

    def rebuild(self, p) -> None:
        """Migrate and rebuild the ghosts now (as a restart from a checkpoint of this step does)."""
        self.halo.rebuild(p)
