"""Halo exchange and migration over a Decomposition.

Every few steps (when some particle has moved more than half the skin since the last rebuild, or
the cuts moved) particles migrate to the rank owning their centre, carrying their bond and contact
history, and each rank receives full copies of the particles within ``ghost_width`` of its
subdomain (ghosts, appended after the owned particles, ordered by source rank). In between, only
positions and velocities of those ghosts are sent, every step. With one rank nothing is sent.

Whether a rebuild is due is not asked every step: a check (one reduction of three doubles) bounds
how far any element can move before the next one, and skips the steps in between
(``steps_to_next_check``).
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import PiceError
from ..kernels.bonds import sync_leaving_history
from ..kernels.halo import (GHOST_DOUBLES, longest_bond, motion_bounds, pack_kinematics,
                            resolve_bond_partners, unpack_kinematics)
from ..state import PER_PARTICLE
from .decomposition import Decomposition

#: at most this many steps [-] between two rebuild checks, whatever the bound allows
CHECK_INTERVAL_CAP = 50
#: the motion bound is doubled [-]: speeds and accelerations may grow between two checks
GROWTH_SAFETY = 2.0


def steps_to_next_check(budget: float, speed: float, accel: float, dt: float,
                        cap: int = CHECK_INTERVAL_CAP) -> int:
    """Steps N [-] from this rebuild check to the next one, 1 <= N <= cap.

    budget: half the skin less the largest displacement since the last rebuild [m]; speed: the
    largest element speed [m/s]; accel: the largest acceleration (F + F_ext)/m [m/s^2]; dt [s].

    The bound. After the drift of step s the velocity is v(s - 1/2); the next drifts move an
    element by dt (v(s + k - 1/2)) with |v(s + k - 1/2)| <= speed + k dt a when its acceleration
    stays below a. Over n steps it moves at most n dt speed + dt^2 a n (n + 1)/2 <= tau speed +
    tau^2 a with tau = n dt. The speeds and accelerations of this check may grow before the next
    one (a contact forms, a wall or hull arrives), so the bound is doubled (GROWTH_SAFETY): the n
    unchecked steps after this one are allowed only while GROWTH_SAFETY (tau speed + tau^2 a) <=
    budget, i.e. while both may double. The cap (CHECK_INTERVAL_CAP, 50) limits what growth beyond
    that could do: an element at rest must reach (skin/2)/(50 dt), 10 m/s for the 0.3 m skin at
    dt = 3e-4 s, within 50 steps to cross half the skin unseen. Near the threshold N falls to 1,
    so a rebuild happens on the very step where some element has moved half the skin, as when the
    check ran every step: the step's numbers do not depend on the checks skipped.
    A non-finite input (a NaN velocity: the health check reports it) gives N = 1."""
    if not (math.isfinite(budget) and math.isfinite(speed) and math.isfinite(accel)) or budget <= 0.0:
        return 1
    b = budget / GROWTH_SAFETY
    if accel > 0.0:
        tau = 2.0 * b / (speed + math.sqrt(speed * speed + 4.0 * accel * b))  # root of a tau^2 + v tau = b
    elif speed > 0.0:
        tau = b / speed
    else:
        return cap
    unchecked = math.floor(tau / dt) if tau < cap * dt else cap
    return int(max(1, min(cap, 1 + unchecked)))


class _MergedRows:
    """The owned rows a rebuild is about to lay out (kept rows of ``p`` and arrivals, in gid order),
    read without making them: ``take(idx)`` copies the rows ``idx`` of that layout."""

    def __init__(self, p, keep, keep_to, arrivals, arrive_to, nlocal):
        self.p, self.arrivals = p, arrivals
        self.from_kept = np.full(nlocal, -1, np.int64)
        self.from_kept[keep_to] = keep
        self.from_arrivals = np.full(nlocal, -1, np.int64)
        self.from_arrivals[arrive_to] = np.arange(len(arrive_to))

    def take(self, idx: np.ndarray) -> dict[str, np.ndarray]:
        kept = self.from_kept[idx]
        if self.arrivals is None or bool(np.all(kept >= 0)):
            return self.p.rows(kept)
        out = {}
        came = kept < 0
        for name, cur in ((name, getattr(self.p, name)) for name in PER_PARTICLE):
            rows = np.empty((len(idx), *cur.shape[1:]), dtype=cur.dtype)
            rows[~came] = cur[kept[~came]]
            rows[came] = self.arrivals[name][self.from_arrivals[idx[came]]]
            out[name] = rows
        return out


class GhostWidthError(PiceError):
    """A bond is longer than the halo can see: continuing would silently lose a partner."""

    exit_code = 3


class Halo:
    """Ghost lists of one rank and the exchanges that use them."""

    def __init__(self, comm, decomposition: Decomposition, *, ghost_width: float, skin: float, dt: float):
        """ghost_width, skin [m]; dt: the time step [s] (the rebuild check's motion bound)."""
        self.comm = comm
        self.decomp = decomposition
        self.ghost_width = ghost_width
        self.skin = skin
        self.dt = dt
        self.check_cap = CHECK_INTERVAL_CAP  # 1: check every step (as before the bound; tests compare)
        self.skip = 0  # exchanges left before the next rebuild check
        self.send_idx: list[np.ndarray] = [np.zeros(0, np.int64) for _ in range(comm.size)]
        self.recv_counts: list[int] = [0] * comm.size  # ghosts from each rank, fixed between rebuilds
        self._pending = None  # a ghost update posted and not yet received
        self._plan = None  # the ghost updates' buffers and lists, made again after each rebuild
        self.x_ref = None

    # -- infrequent: migration and ghost rebuild -----------------------------------------------
    def rebuild(self, p) -> None:
        """Migrate owned particles to their owners, then gather fresh ghosts and resolve bonds."""
        comm = self.comm
        if comm.size > 1:
            n = p.nlocal
            owner = self.decomp.owner(p.x[:n, 0], p.x[:n, 1])
            mine = owner == comm.rank
            leaving = not mine.all()
            if leaving:  # the histories the rows that leave take, and leave behind, agree at both ends
                sync_leaving_history(np.nonzero(~mine)[0], n, p.gid, p.bond_j, p.bond_mate, p.bond_hist)
            keep = np.nonzero(mine)[0] if leaving else np.arange(n)
            outgoing = [p.rows(np.nonzero(owner == r)[0]) if r != comm.rank and leaving else None
                        for r in range(comm.size)]
            incoming = comm.alltoall(outgoing)
            blocks = [blk for r, blk in enumerate(incoming) if r != comm.rank and blk is not None and len(blk["gid"])]
            arrivals = {k: np.concatenate([blk[k] for blk in blocks]) for k in blocks[0]} if blocks else None
            gid = p.gid[:n]
            if arrivals is None and not leaving and bool(np.all(gid[1:] > gid[:-1])):
                # nobody crossed a cut and the rows are in gid order already: they stay where they are
                nlocal, keep_to, arrive_to, x, take = n, keep, keep[:0], p.x[:n], p.rows
            else:
                # owned particles in gid order: the layout is then the same whatever the history. Where
                # each kept and each arriving row goes (the inverse of the stable sort of their gids)
                gids = p.gid[keep] if arrivals is None else np.concatenate([p.gid[keep], arrivals["gid"]])
                nlocal = len(gids)
                dest = np.empty(nlocal, np.int64)
                dest[np.argsort(gids, kind="stable")] = np.arange(nlocal)
                keep_to, arrive_to = dest[:len(keep)], dest[len(keep):]
                x = np.empty((nlocal, 3))
                x[keep_to] = p.x[keep]
                if arrivals is not None:
                    x[arrive_to] = arrivals["x"]
                take = _MergedRows(p, keep, keep_to, arrivals, arrive_to, nlocal).take
            targets = self._ghost_targets(x)
            self.send_idx = targets
            ghost_blocks = comm.alltoall([take(idx) if len(idx) else None for idx in targets])
            self.recv_counts = [len(b["gid"]) if b is not None else 0 for b in ghost_blocks]
            p.place_rows(keep, keep_to, arrivals, arrive_to, nlocal, [b for b in ghost_blocks if b is not None])
        self.resolve(p)
        self.x_ref = p.x[:p.nlocal].copy()
        self.skip = 0  # check at the next exchange: the schedule restarts from every rebuild (and restart)

    def _ghost_targets(self, x: np.ndarray) -> list[np.ndarray]:
        """For each rank, the indices of owned particles within ghost_width of its subdomain."""
        gw = self.ghost_width
        out = []
        for r in range(self.comm.size):
            if r == self.comm.rank:
                out.append(np.zeros(0, np.int64))
                continue
            xlo, xhi, ylo, yhi = self.decomp.box(r)
            sel = (x[:, 0] >= xlo - gw) & (x[:, 0] < xhi + gw) & (x[:, 1] >= ylo - gw) & (x[:, 1] < yhi + gw)
            out.append(np.nonzero(sel)[0].astype(np.int64))
        return out

    def resolve(self, p) -> None:
        """Local indices of bond partners; a partner missing from owned + ghosts is an error, and so is
        a bond longer than ghost_width - skin: before the next rebuild its ends may move apart by up to
        the skin (each by half of it, or a rebuild comes first), and then its partner would be lost.
        One reduction of two doubles (the rebuild is rare: nothing is checked between rebuilds, when
        the ghosts hold every partner found here)."""
        missing, who, partner = resolve_bond_partners(p.gid, p.nlocal, p.bond_gid, p.bond_j)
        longest = float(longest_bond(p.x, p.nlocal, p.bond_j)) if self.comm.size > 1 else 0.0
        worst_missing, worst_longest = self.comm.max(np.array([float(missing), longest]))
        if worst_missing:
            raise GhostWidthError(
                f"bond partner(s) not found within the ghost width {self.ghost_width:.4g} m (up to "
                f"{int(worst_missing)} on a rank; here: {missing}, e.g. element gid {who} -> gid {partner}): a "
                "bond is stretched beyond the halo; raise [parallel] skin or check for a runaway element")
        self.refuse_long_bond(float(worst_longest))

    # -- every step ----------------------------------------------------------------------------
    def needs_rebuild(self, p, timers=None) -> bool:
        """True on every rank when any owned particle moved more than skin/2 since the last rebuild.

        Asked on every exchange, it reduces only on the steps of a check: a check finds the largest
        displacement, speed and acceleration over all ranks (one Allreduce of 3 doubles) and from
        them the steps until the next check (``steps_to_next_check``); the exchanges in between
        return False without a message. The schedule depends only on the state, so that a restart
        (which rebuilds, as the checkpointed run did) keeps it.

        ``timers`` (pice/timers.py, or None): the local scan is charged "halo", the reduction "waiting"."""
        if self.comm.size == 1:
            return False
        if self.skip > 0:
            self.skip -= 1
            return False
        local = np.array(motion_bounds(p.x, self.x_ref, p.v, p.force, p.ext_force, p.mass, p.fix_mask, p.nlocal))
        if timers is not None:
            timers.lap("halo")
        moved, speed, accel = self.comm.max(local)
        if timers is not None:
            timers.lap("waiting")
        budget = 0.5 * self.skin - moved
        if budget < 0.0:
            return True
        self.skip = steps_to_next_check(budget, speed, accel, self.dt, self.check_cap) - 1
        return False

    def update(self, p) -> None:
        """Send the current x, v, w of every ghost to the ranks that hold it, and receive ours."""
        self.start_update(p)
        self.finish_update(p)

    def start_update(self, p) -> None:
        """Post the ghost update: one message to each rank that holds ghosts of ours and one receive
        from each rank whose ghosts we hold (the counts are known since the rebuild: no collective).
        Work on owned elements may go on until ``finish_update``."""
        if self.comm.size == 1:
            return
        if self._pending is not None:  # its send buffer is about to be packed again
            raise RuntimeError("a ghost update was posted before the previous one was received (finish_update)")
        plan = self._plan
        if plan is None or plan[0] is not self.send_idx:
            plan = self._plan = self._plan_update()
        _, idx, buf, sends, recvs = plan
        pack_kinematics(p.x, p.v, p.w, idx, buf)
        self._pending = self.comm.start_neighbour_exchange(sends, recvs)

    def _plan_update(self) -> tuple:
        """What every ghost update until the next rebuild sends and receives (the lists are fixed
        between rebuilds): (send_idx it was made for, the rows packed, the send buffer, [(rank, its
        part of the buffer)], [(rank, doubles to receive)]). The buffer is reused: the previous
        update has been received (``finish_update``) before the next is posted."""
        counts = [len(i) for i in self.send_idx]
        idx = np.concatenate(self.send_idx) if sum(counts) else np.zeros(0, np.int64)
        buf = np.empty(GHOST_DOUBLES * len(idx))
        sends, start = [], 0
        for r, n in enumerate(counts):
            if n:
                sends.append((r, buf[start:start + GHOST_DOUBLES * n]))
                start += GHOST_DOUBLES * n
        recvs = [(r, GHOST_DOUBLES * n) for r, n in enumerate(self.recv_counts) if n]
        return self.send_idx, idx, buf, sends, recvs

    @property
    def pending(self) -> bool:
        """A ghost update is posted and not yet received."""
        return self._pending is not None

    def finish_update(self, p) -> None:
        """Receive the ghost update posted by ``start_update`` (nothing when none is pending); ghosts
        are stored by source rank, as the rebuild laid them out."""
        if self._pending is None:
            return
        bufs = self.comm.finish_neighbour_exchange(self._pending)
        self._pending = None
        start = p.nlocal
        for b in bufs:
            unpack_kinematics(b, p.x, p.v, p.w, start)
            start += len(b) // GHOST_DOUBLES

    def refuse_long_bond(self, longest: float) -> None:
        """A bond longer [m] than ghost_width - skin could lose its partner at the next rebuild."""
        if longest > self.ghost_width - self.skin:
            raise GhostWidthError(
                f"a bond is stretched to {longest:.4g} m, beyond the ghost width {self.ghost_width:.4g} m "
                f"less the skin {self.skin:.4g} m; raise [parallel] skin or check for a runaway element")
