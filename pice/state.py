"""Struct-of-arrays particle state.

Particles carry a global id (``gid``) that never changes, so bonds and contact histories can
refer to partners across ranks. Bonds are stored per particle in fixed slots: ``bond_gid`` holds
the partner's gid (-1 when the slot is empty or the bond is broken), ``bond_j`` its local index
(resolved from gids whenever the local ordering changes), ``bond_mate`` the slot that holds the
same bond in the partner's list, ``bond_L0`` the rest length [m] and ``bond_hist`` the bond's
history in the canonical orientation (lower gid first): shear force Fs [N] (0:3), twisting moment
Mt [N m] (3), bending moment Mb [N m] (4:7), normal force Fn [N] (7, tension > 0). Both ends of a
bond hold identical copies, updated with identical arithmetic.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

MAX_BONDS = 12     # HCP has at most 12 neighbours (a single layer 6: arrays are sized to the lattice)
MAX_CONTACTS = 16  # unbonded contacts tracked per particle (tangential history)
BOND_HIST = 8

KIND_ICE = 0


# arrays that travel with a particle when it migrates, and that a checkpoint holds (bond_j is
# re-resolved from bond_gid). force and torque travel too: the half-kick that opens the next step
# uses them, so a rebuild (or a restart) needs no force recomputation, which would advance the
# incremental bond and contact histories a second time.
PER_PARTICLE = ("gid", "x", "v", "w", "radius", "mass", "inertia", "kind", "volume", "cell_area",
                "half_height", "bond_gid", "bond_mate", "bond_L0", "bond_hist", "ext_force", "fix_mask",
                "fix_velocity", "contact_gid", "contact_stamp", "contact_hist", "wall_hist", "hull_hist", "heave_damping",
                "anchor", "anchor_k",
                "force", "torque")


ROW_HEADROOM = 1.1  # rows a rebuild allocates per row it needs (Particles.place_rows)


RUN_COPY_MIN = 64  # mean rows per run above which place_rows copies runs of rows as slices


def _runs(src: np.ndarray, dst: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The maximal runs in which the row indices ``src`` and ``dst`` both advance by one: (src start,
    dst start, length) of each, so that ``out[dst] = cur[src]`` is a few slice copies."""
    if len(src) == 0:
        return src[:0], dst[:0], src[:0]
    starts = np.concatenate([[0], np.nonzero((np.diff(src) != 1) | (np.diff(dst) != 1))[0] + 1])
    lengths = np.diff(np.concatenate([starts, [len(src)]]))
    return src[starts], dst[starts], lengths


def _prefix_of(array: np.ndarray, buf: np.ndarray | None) -> bool:
    """Is ``array`` the first rows of ``buf`` (a view that place_rows made and nobody replaced)?"""
    return (buf is not None and array.base is buf
            and array.__array_interface__["data"][0] == buf.__array_interface__["data"][0])


@dataclass
class Particles:
    """All per-particle arrays of one rank. The first ``nlocal`` entries are owned; the rest are ghosts."""

    gid: np.ndarray                 # (n,) int64
    x: np.ndarray                   # (n,3) position [m]
    v: np.ndarray                   # (n,3) velocity [m/s]
    w: np.ndarray                   # (n,3) angular velocity [rad/s]
    radius: np.ndarray              # (n,) [m]
    mass: np.ndarray                # (n,) [kg]
    inertia: np.ndarray             # (n,) moment of inertia about the centre [kg m^2]
    kind: np.ndarray                # (n,) int8
    volume: np.ndarray              # (n,) volume the element stands for [m^3]
    cell_area: np.ndarray           # (n,) waterplane footprint of a "cell" element [m^2] (0 for spheres)
    half_height: np.ndarray         # (n,) half the height of a "cell" element [m] (radius for spheres)
    bond_gid: np.ndarray            # (n,MAX_BONDS) int64
    bond_j: np.ndarray              # (n,slots) int32 local index
    bond_mate: np.ndarray           # (n,slots) int32
    bond_L0: np.ndarray             # (n,MAX_BONDS) [m]
    bond_hist: np.ndarray           # (n,MAX_BONDS,BOND_HIST)
    force: np.ndarray = field(default=None)     # (n,3) [N]
    torque: np.ndarray = field(default=None)    # (n,3) [N m]
    ext_force: np.ndarray = field(default=None)  # (n,3) constant applied load [N]
    fix_mask: np.ndarray = field(default=None)   # (n,3) bool: velocity component prescribed
    fix_velocity: np.ndarray = field(default=None)  # (n,3) prescribed velocity [m/s]
    contact_gid: np.ndarray = field(default=None)   # (n,MAX_CONTACTS) int64
    contact_stamp: np.ndarray = field(default=None)  # (n,MAX_CONTACTS) int64, step last touched
    contact_hist: np.ndarray = field(default=None)  # (n,MAX_CONTACTS,4) tangential force [N], plastic penetration [m]
    wall_hist: np.ndarray = field(default=None)     # (n,n_walls,4) the same for each wall
    hull_hist: np.ndarray = field(default=None)     # (n,n_bodies,4) the same for each hull
    heave_damping: np.ndarray = field(default=None)  # (n,) linear heave damping [N s/m]
    anchor: np.ndarray = field(default=None)         # (n,3) spring-boundary anchor at t = 0 [m]
    anchor_k: np.ndarray = field(default=None)       # (n,3) spring-boundary stiffness per direction [N/m] (0: free)
    nlocal: int = 0
    topology: int = 0  # raised whenever a bond is removed from these rows (the contact candidates change)
    # The bonds removed since the contact pair list last looked, one (k, 2) array of local (i, j) per raise
    # of ``topology`` (None where they were not logged); None while nobody keeps a list (physics/contact.py).
    unbonded: list | None = None

    @property
    def n(self) -> int:
        return len(self.gid)

    def allocate_dynamic(self, n_walls: int, n_bodies: int = 0) -> None:
        """Allocate force, constraint and contact-history arrays (zeroed)."""
        n = self.n
        self.force = np.zeros((n, 3))
        self.torque = np.zeros((n, 3))
        if self.ext_force is None:
            self.ext_force = np.zeros((n, 3))
        if self.fix_mask is None:
            self.fix_mask = np.zeros((n, 3), dtype=np.bool_)
            self.fix_velocity = np.zeros((n, 3))
        self.contact_gid = np.full((n, MAX_CONTACTS), -1, dtype=np.int64)
        self.contact_stamp = np.full((n, MAX_CONTACTS), -10, dtype=np.int64)
        self.contact_hist = np.zeros((n, MAX_CONTACTS, 4))
        self.wall_hist = np.zeros((n, max(n_walls, 1), 4))
        self.hull_hist = np.zeros((n, max(n_bodies, 1), 4))
        if self.heave_damping is None:
            self.heave_damping = np.zeros(n)
        self.anchor = self.x.copy()
        self.anchor_k = np.zeros((n, 3))

    def rows(self, idx: np.ndarray) -> dict[str, np.ndarray]:
        """Copies of every per-particle array at the indices ``idx`` (what migrates with a particle)."""
        return {name: getattr(self, name)[idx] for name in PER_PARTICLE}

    def replace_rows(self, parts: list[dict[str, np.ndarray]], nlocal: int) -> None:
        """Set every per-particle array to the concatenation of ``parts``; the first nlocal are owned.

        force/torque come with the rows (a ghost's copy is never read: compute_forces zeroes them);
        bond_j is left to be resolved from bond_gid.
        """
        for name in PER_PARTICLE:
            setattr(self, name, np.concatenate([part[name] for part in parts]))
        self.nlocal = nlocal
        self.bond_j = np.full(self.bond_gid.shape, -1, dtype=np.int32)

    def place_rows(self, keep: np.ndarray, keep_to: np.ndarray, arrivals: dict | None, arrive_to: np.ndarray,
                   nlocal: int, ghosts: list[dict[str, np.ndarray]]) -> None:
        """``replace_rows`` without the intermediate copies: every per-particle array is made once,
        owned rows ``keep`` of the current arrays going to rows ``keep_to``, the ``arrivals``' rows
        to ``arrive_to`` (0..nlocal-1 between them), then the ``ghosts`` blocks in order. A halo
        rebuild that migrates a row of elements copied the 1.6 kB of each of its 46,000 rows four
        times (parallel/halo.py): once now. The arrays are the first rows of buffers ROW_HEADROOM
        longer, so that a rebuild where nobody leaves or arrives writes the ghosts only."""
        identity = arrivals is None and len(keep) == nlocal and bool(np.all(keep_to == keep)) \
            and bool(np.all(keep == np.arange(nlocal)))
        total = nlocal + sum(len(g["gid"]) for g in ghosts)
        buffers = self.__dict__.setdefault("_buffers", {})  # name -> the array the rows are a prefix of
        # the kept rows keep their order (both sides sorted by gid): a migration of a few rows leaves
        # long runs, copied as slices (docs/performance.md, "The ghost update and the rebuild")
        runs = None if identity else _runs(keep, keep_to)
        by_runs = runs is not None and len(runs[2]) * RUN_COPY_MIN <= len(keep)
        for name in PER_PARTICLE:
            cur, buf = getattr(self, name), buffers.get(name)
            if identity and _prefix_of(cur, buf) and len(buf) >= total:
                out = buf[:total]  # the owned rows stay where they are: only the ghosts are written
            else:
                buf = np.empty((int(ROW_HEADROOM * total) + 16, *cur.shape[1:]), dtype=cur.dtype)
                buffers[name] = buf
                out = buf[:total]
                if identity:
                    out[:nlocal] = cur[:nlocal]
                elif by_runs:
                    for a, d, m in zip(*runs):
                        out[d:d + m] = cur[a:a + m]
                else:
                    out[keep_to] = cur[keep]
                if arrivals is not None:
                    out[arrive_to] = arrivals[name]
            at = nlocal
            for g in ghosts:
                out[at:at + len(g["gid"])] = g[name]
                at += len(g["gid"])
            setattr(self, name, out)
        self.nlocal = nlocal
        self.bond_j = np.full(self.bond_gid.shape, -1, dtype=np.int32)

    def intact_bonds(self) -> np.ndarray:
        """(m,2) int64 gid pairs of intact bonds among owned particles, each bond once (lower gid first)."""
        loc = slice(0, self.nlocal)
        g = self.gid[loc][:, None].repeat(self.bond_gid.shape[1], axis=1)
        p = self.bond_gid[loc]
        keep = (p >= 0) & (g < p)
        return np.stack([g[keep], p[keep]], axis=1)

    def bond_count(self) -> int:
        """Intact bonds whose lower-gid end is owned here: summed over ranks, each bond counts once."""
        loc = slice(0, self.nlocal)
        partner = self.bond_gid[loc]
        return int(np.count_nonzero((partner >= 0) & (partner > self.gid[loc][:, None])))
