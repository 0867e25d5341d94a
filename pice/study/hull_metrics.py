"""The design criteria of a moored buoy (Cai 2018, seed 004, section 6.1) as study metrics of body 0.

From each series row's pose of the body (``body_position``, ``body_rotation`` as roll phi, pitch
theta, yaw psi of R = Rz(psi) Ry(theta) Rx(phi), platform.rigid_body.euler_angles), its hull in the
body frame (``hull0_vertices`` of the run's first snapshot) and the water of the job the run file
keeps (its level and depth). The body's z axis points along e = R e_z, whose vertical component is
e_z = cos(theta) cos(phi).

* ``max_heel`` [deg]: the largest angle arccos(e_z) between the body's axis and the vertical over
  the rows, roll and pitch together. Criterion (1), no overturning: max_heel_deg < 90.
* ``draft`` [m]: the depth of the hull's lowest point below the water level in the first row (a body
  that starts afloat: its stationary draft); ``min_draft``, ``max_draft`` [m]: over the rows with
  t >= settle. The lowest point is the lowest vertex, z = x_z + (R v)_z, with (R v)_z =
  -sin(theta) v_x + cos(theta) sin(phi) v_y + e_z v_z. Criterion (3): draft_m in [0.6, 2.4].
* ``min_rim_freeboard`` [m]: for a hull of revolution (types "buoy" and "revolved"), the height
  above the water of the lowest point of its widest ring (radius r at height h in the body frame:
  the vertices farthest from the axis, the highest ring of them), x_z + h e_z - r sqrt(1 - e_z^2),
  smallest over the rows. Below 0 the water passes the widest section onto the upward-sloping cone:
  the "submerged" upward slope of criterion (4), whose onset the thesis's Table 6-4 gives as a
  critical pitch angle. NaN for any other hull.
* ``max_offset_of_depth`` [%]: 100 max_offset / water.depth (criteria (5) and (7): at most 15 % and
  25 % of the depth).

Every one is NaN when the run has no body, no hull in its first snapshot or no job text.
"""

from __future__ import annotations

import math

import numpy as np

#: (name, unit, label) of the metrics of this module, after those of study/metrics.py
HULL_METRICS = (("max_heel", "deg", "max heel"), ("draft", "m", "draft at rest"), ("min_draft", "m", "min draft"),
                ("max_draft", "m", "max draft"), ("min_rim_freeboard", "m", "min freeboard of the widest section"),
                ("max_offset_of_depth", "pct", "max offset of the depth"))

REVOLVED = ("buoy", "revolved")  # hull types whose widest ring is a circle about the body's z axis


def lowest_points(position: np.ndarray, rotation: np.ndarray, vertices: np.ndarray) -> np.ndarray:
    """(n,) height [m] of the lowest of the hull's ``vertices`` (k, 3) [m, body frame] in each of n
    poses: ``position`` (n, 3) [m] and ``rotation`` (n, 3) roll, pitch, yaw [rad]."""
    roll, pitch = rotation[:, 0], rotation[:, 1]
    row = np.column_stack([-np.sin(pitch), np.cos(pitch) * np.sin(roll), np.cos(pitch) * np.cos(roll)])
    return position[:, 2] + (row @ vertices.T).min(axis=1)


def widest_ring(vertices: np.ndarray) -> tuple[float, float]:
    """(h, r) [m] of a hull of revolution's widest ring: the largest distance r of a vertex from the
    body's z axis, and the highest z of the vertices at that distance (to 1e-9 r)."""
    radius = np.hypot(vertices[:, 0], vertices[:, 1])
    r = float(radius.max())
    return float(vertices[radius >= r * (1.0 - 1e-9), 2].max()), r


def hull_metrics(run, *, settle: float, max_offset: float) -> dict[str, float]:
    """The metrics of the module docstring for body 0 of the open ``run`` (io.run_reader.Run);
    ``settle`` [s]: min_draft and max_draft over the rows with t >= settle; ``max_offset`` [m]: the
    run's max_offset (study/metrics.py)."""
    out = dict.fromkeys((m[0] for m in HULL_METRICS), math.nan)
    time, position, rotation = run.series("time"), run.series("body_position"), run.series("body_rotation")
    job = run.job
    if job is None or job.water is None or not job.bodies:
        return out
    if job.water.depth:
        out["max_offset_of_depth"] = 100.0 * max_offset / job.water.depth
    if position is None or rotation is None or position.shape[1] == 0 or not len(position) or not run.snapshots:
        return out
    snap = run.snapshot(0)
    if "hull0_vertices" not in snap:
        return out
    vertices = snap["hull0_vertices"][()]
    x, angles = position[:, 0], rotation[:, 0]
    ez = np.clip(np.cos(angles[:, 1]) * np.cos(angles[:, 0]), -1.0, 1.0)
    out["max_heel"] = float(np.degrees(np.arccos(ez)).max())
    draft = job.water.level - lowest_points(x, angles, vertices)
    out["draft"] = float(draft[0])
    later = draft[time >= settle]
    if later.size:
        out["min_draft"], out["max_draft"] = float(later.min()), float(later.max())
    if job.bodies[0].hull.type in REVOLVED:
        h, r = widest_ring(vertices)
        rim = x[:, 2] + h * ez - r * np.sqrt(1.0 - ez * ez) - job.water.level
        out["min_rim_freeboard"] = float(rim.min())
    return out
