"""Rank 0 owns the bodies: each step the ice loads on them are reduced to rank 0, and the poses
rank 0 integrates are broadcast back. Fixed walls use the reduction only.
"""

from __future__ import annotations

import numpy as np


class BodyCoupling:
    """Per-step reduction of body loads to rank 0 and broadcast of body poses from it."""

    def __init__(self, comm, n_bodies: int):
        self.comm = comm
        self.n_bodies = n_bodies

    def reduce_loads(self, local: np.ndarray) -> np.ndarray | None:
        """(n_bodies, 6) force [N] and moment [N m] from this rank's ice -> the totals on rank 0."""
        return self.comm.reduce_sum(local.reshape(self.n_bodies, 6))

    def broadcast_poses(self, poses: np.ndarray) -> np.ndarray:
        """(n_bodies, k) poses set on rank 0 -> the same array on every rank."""
        return self.comm.bcast_array(poses)
