"""The floating bodies inside a simulation: set-up checks and what rank 0 records of them.

pice.simulation owns the coupling (hull contact on every rank, one reduction, rank 0's step and
the pose broadcast); this module holds the pieces around it: the poses a job starts from, the
refusal of a hull that starts inside the ice, the peaks between series rows, and the series,
snapshot and `pice check` entries of the bodies and their lines.
"""

from __future__ import annotations

import math

import numpy as np

from .errors import JobError
from .kernels.hull_contact import hull_forces


def initial_poses(job) -> np.ndarray:
    """(n_bodies, 13) x, q, v, omega at t = 0 as the job gives them (at rest)."""
    from .job_platform import heading_quaternion

    poses = np.zeros((len(job.bodies), 13))
    for k, b in enumerate(job.bodies):
        poses[k, :3] = b.position
        poses[k, 3:7] = heading_quaternion(b.heading)
    return poses


def refuse_initial_overlap(job, p, hulls, poses) -> None:
    """A hull that cuts into the ice at t = 0 would fire elements off: refuse it with the fix.
    Called on the whole sheet, before it is distributed."""
    for k, h in enumerate(hulls):
        f, t = np.zeros((p.n, 3)), np.zeros((p.n, 3))
        params = h.params.copy()
        params[1:] = 0.0  # elastic normal force only
        pose = poses[k].copy()
        pose[7:] = 0.0
        hull_forces(p.nlocal, p.x, np.zeros_like(p.v), np.zeros_like(p.w), p.radius * 0.99, p.mass, pose,
                    h.vertices, h.triangles, *h.grid, params, np.zeros((p.n, 3)), 0.0, f, t)
        n_el = int(np.count_nonzero(np.abs(f).sum(axis=1) > 0))
        if n_el:
            raise JobError(f"{job.source}: bodies[{k}] ({h.name}): its hull overlaps {n_el} ice element(s) at "
                           "t = 0; move the body (bodies.position) or the sheet (ice.origin) so that they start "
                           "apart")


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
        d["ice_sum"] += ice
        np.maximum(d["ice_max"], ice, out=d["ice_max"])
        np.minimum(d["ice_min"], ice, out=d["ice_min"])
        np.maximum(d["tension_max"], tension, out=d["tension_max"])

    def take(self) -> dict | None:
        """The statistics so far (None if nothing was tracked), and start again."""
        d, self.data = self.data, None
        return d


def series_entries(platform, ice_total, peaks: dict | None) -> dict[str, np.ndarray]:
    """Rank 0's series entries of the bodies and lines (SI units, angles in rad)."""
    from .physics.body import euler_angles

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
    """Bodies, their masses [kg], lines, DEM nodes and line sub-steps per ice step (0: quasi-static)."""
    nodes = sum(len(g.lines.x) for g in platform.groups if hasattr(g.lines, "x"))
    sub = max(1, int(math.ceil(dt / platform.line_dt - 1e-12))) if math.isfinite(platform.line_dt) else 0
    return dict(bodies=len(platform.bodies), body_mass=[b.mass for b in platform.bodies],
                mooring_lines=platform.n_lines, mooring_nodes=nodes, mooring_substeps=sub)
