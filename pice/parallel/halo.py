"""Halo exchange and migration over a Decomposition.

Every few steps (when some particle has moved more than half the skin since the last rebuild, or
the cuts moved) particles migrate to the rank owning their centre, carrying their bond and contact
history, and each rank receives full copies of the particles within ``ghost_width`` of its
subdomain (ghosts, appended after the owned particles, ordered by source rank). In between, only
positions and velocities of those ghosts are sent, every step. With one rank nothing is sent.
"""

from __future__ import annotations

import numpy as np

from ..errors import PiceError
from ..kernels.bonds import sync_mate_history
from ..kernels.halo import (GHOST_DOUBLES, longest_bond, max_displacement, pack_kinematics,
                            resolve_bond_partners, unpack_kinematics)
from .decomposition import Decomposition


class GhostWidthError(PiceError):
    """A bond is longer than the halo can see: continuing would silently lose a partner."""

    exit_code = 3


class Halo:
    """Ghost lists of one rank and the exchanges that use them."""

    def __init__(self, comm, decomposition: Decomposition, *, ghost_width: float, skin: float):
        self.comm = comm
        self.decomp = decomposition
        self.ghost_width = ghost_width
        self.skin = skin
        self.send_idx: list[np.ndarray] = [np.zeros(0, np.int64) for _ in range(comm.size)]
        self.x_ref = None

    # -- infrequent: migration and ghost rebuild -----------------------------------------------
    def rebuild(self, p) -> None:
        """Migrate owned particles to their owners, then gather fresh ghosts and resolve bonds."""
        comm = self.comm
        if comm.size > 1:
            sync_mate_history(p.nlocal, p.gid, p.bond_j, p.bond_mate, p.bond_hist)
            n = p.nlocal
            owner = self.decomp.owner(p.x[:n, 0], p.x[:n, 1])
            stay = p.rows(np.nonzero(owner == comm.rank)[0])  # kept in place, not sent to ourselves
            outgoing = [p.rows(np.nonzero(owner == r)[0]) if r != comm.rank else None
                        for r in range(comm.size)]
            incoming = comm.alltoall(outgoing)
            local = [stay] + [blk for r, blk in enumerate(incoming) if r != comm.rank and len(blk["gid"])]
            # owned particles in gid order: the layout is then the same whatever the history
            merged = {k: np.concatenate([blk[k] for blk in local]) for k in local[0]}
            order = np.argsort(merged["gid"], kind="stable")
            merged = {k: v[order] for k, v in merged.items()}
            nlocal = len(merged["gid"])
            targets = self._ghost_targets(merged["x"])
            self.send_idx = targets
            ghost_blocks = comm.alltoall([{k: v[idx] for k, v in merged.items()} if len(idx) else None
                                          for idx in targets])
            ghost_blocks = [b for b in ghost_blocks if b is not None]
            p.replace_rows([merged] + ghost_blocks, nlocal)
        self.resolve(p)
        self.x_ref = p.x[:p.nlocal].copy()

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
        """Local indices of bond partners; a partner missing from owned + ghosts is an error."""
        missing, who, partner = resolve_bond_partners(p.gid, p.nlocal, p.bond_gid, p.bond_j)
        missing = self.comm.sum(int(missing))
        if missing:
            raise GhostWidthError(
                f"{missing} bond partner(s) not found within the ghost width {self.ghost_width:.4g} m "
                f"(e.g. element gid {who} -> gid {partner}): a bond is stretched beyond the halo; "
                "raise [parallel] skin or check for a runaway element")

    # -- every step ----------------------------------------------------------------------------
    def needs_rebuild(self, p, timers=None) -> bool:
        """True on every rank when any owned particle moved more than skin/2 since the last rebuild.

        ``timers`` (pice/timers.py, or None): the local scan is charged "halo", the reduction "waiting"."""
        if self.comm.size == 1:
            return False
        moved = max_displacement(p.x, self.x_ref, p.nlocal)
        if timers is not None:
            timers.lap("halo")
        far = self.comm.max(float(moved)) > 0.5 * self.skin
        if timers is not None:
            timers.lap("waiting")
        return far

    def update(self, p) -> None:
        """Send the current x, v, w of every ghost to the ranks that hold it."""
        if self.comm.size == 1:
            return
        counts = np.array([len(i) for i in self.send_idx], np.int64)
        idx = np.concatenate(self.send_idx) if counts.sum() else np.zeros(0, np.int64)
        buf = np.empty(GHOST_DOUBLES * len(idx))
        pack_kinematics(p.x, p.v, p.w, idx, buf)
        recv, _ = self.comm.exchange_doubles(buf, GHOST_DOUBLES * counts)
        unpack_kinematics(recv, p.x, p.v, p.w, p.nlocal)

    def check_bond_lengths(self, p, timers=None) -> None:
        """A bond longer than ghost_width - skin could lose its partner at the next rebuild.

        ``timers`` (pice/timers.py, or None): the local scan is charged "checks", the reduction "waiting"."""
        if self.comm.size == 1:
            return
        local = float(longest_bond(p.x, p.nlocal, p.bond_j))
        if timers is not None:
            timers.lap("checks")
        longest = self.comm.max(local)
        if timers is not None:
            timers.lap("waiting")
        if longest > self.ghost_width - self.skin:
            raise GhostWidthError(
                f"a bond is stretched to {longest:.4g} m, beyond the ghost width {self.ghost_width:.4g} m "
                f"less the skin {self.skin:.4g} m; raise [parallel] skin or check for a runaway element")
