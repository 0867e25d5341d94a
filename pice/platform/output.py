"""What rank 0 records of the platform: load peaks between series rows, the series and snapshot
entries of the bodies and their lines, and the facts `pice check` prints and the run file keeps
(``describe``: among them each body's resolved mass, ``body_mass``)."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..kernels import JIT
from .rigid_body import euler_angles


@njit(**JIT)
def _track(ice, tension, ice_sum, ice_max, ice_min, tension_max):
    """The running sum and extremes of the loads ``ice`` (n, 3) [N] and tensions (k,) [N], in place; a
    NaN sticks, as with np.maximum (the health check names it)."""
    for i in range(ice.shape[0]):
        for j in range(ice.shape[1]):
            x = ice[i, j]
            ice_sum[i, j] += x
            if x > ice_max[i, j] or x != x:
                ice_max[i, j] = x
            if x < ice_min[i, j] or x != x:
                ice_min[i, j] = x
    for k in range(len(tension)):
        if tension[k] > tension_max[k] or tension[k] != tension[k]:
            tension_max[k] = tension[k]


class Peaks:
    """Rank 0: mean and extremes of the ice loads [N] and the largest line tensions [N] since the
    last series row, so that rows every N steps still report the peaks designers need."""

    def __init__(self):
        self.data = None

    def track(self, ice: np.ndarray, tension: np.ndarray) -> None:
        d = self.data
        if d is None:
            self.data = dict(n=1, ice_sum=ice.copy(), ice_max=ice.copy(), ice_min=ice.copy(),
                             tension_max=tension.copy())
            return
        d["n"] += 1
        _track(ice, tension, d["ice_sum"], d["ice_max"], d["ice_min"], d["tension_max"])

    def state(self) -> dict[str, np.ndarray]:
        """The sums and extremes so far as arrays for a checkpoint ({} when nothing was tracked), so that
        a restart between two series rows gives the next row the mean and extremes of all its steps."""
        return {} if self.data is None else {k: np.asarray(v).copy() for k, v in self.data.items()}

    def set_state(self, s: dict | None) -> None:
        self.data = None
        if s:
            self.data = {k: np.asarray(v, float).copy() for k, v in s.items() if k != "n"}
            self.data["n"] = int(s["n"])

    def take(self) -> dict | None:
        """The statistics so far (None if nothing was tracked), and start again."""
        d, self.data = self.data, None
        return d


def series_entries(platform, ice_total, peaks: dict | None) -> dict[str, np.ndarray]:
    """Rank 0's series entries of the bodies and lines (SI units, angles in rad)."""
    bodies = platform.bodies
    ice = ice_total if ice_total is not None else np.zeros((len(bodies), 6))
    row = dict(body_position=np.array([b.x for b in bodies]),
               body_rotation=np.array([euler_angles(b.q) for b in bodies]),
               body_velocity=np.array([b.v for b in bodies]),
               body_angular_velocity=np.array([b.omega for b in bodies]),
               ice_force=ice[:, :3].copy(), ice_moment=ice[:, 3:].copy(),
               mooring_force=platform.mooring_force.copy())
    if peaks is not None:  # over the steps since the previous row (this row's step included)
        row.update(ice_force_mean=peaks["ice_sum"] / peaks["n"], ice_force_max=peaks["ice_max"],
                   ice_force_min=peaks["ice_min"])
    if platform.n_lines:
        row["fairlead_tension"] = platform.fairlead_tensions()
        row["anchor_tension"] = platform.anchor_tensions()
        if peaks is not None:
            row["fairlead_tension_max"] = peaks["tension_max"]
    return row


def snapshot_arrays(platform, hulls, first: bool) -> dict[str, np.ndarray]:
    """body_pose (n_bodies, 13), mooring_x (k, 3) points along the lines [m] and mooring_line (k,)
    the line of each; the first snapshot also holds each hull in its body frame (hull<k>_vertices,
    hull<k>_triangles)."""
    out = {"body_pose": platform.poses()}
    if first:
        for k, h in enumerate(hulls):
            out[f"hull{k}_vertices"] = h.vertices
            out[f"hull{k}_triangles"] = h.triangles
    if platform.n_lines:
        x, line = platform.polylines()
        out.update(mooring_x=x, mooring_line=line)
    return out


def describe(platform, dt: float) -> dict:
    """Bodies, their masses [kg] (a "balance" mass as resolved at set-up), lines, DEM nodes and line
    sub-steps per ice step of dt [s] (0: quasi-static)."""
    nodes = sum(len(g.lines.x) for g in platform.groups if hasattr(g.lines, "x"))
    sub = max(1, int(math.ceil(dt / platform.line_dt - 1e-12))) if math.isfinite(platform.line_dt) else 0
    return dict(bodies=len(platform.bodies), body_mass=[b.mass for b in platform.bodies],
                mooring_lines=platform.n_lines, mooring_nodes=nodes, mooring_substeps=sub)
