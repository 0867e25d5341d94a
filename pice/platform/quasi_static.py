"""Quasi-static mooring lines: each line's pull on its fairlead from the elastic catenary (platform.catenary).

The cheap mooring model for a scene that needs only the restoring force: no line dynamics, no
drag; the line shape follows the fairlead instantly. A line is re-solved when its fairlead has
moved more than ``tol`` since its last solve (the pull is otherwise kept), so a platform that
hardly moves costs almost nothing. Interface as platform.mooring_lines.MooringLines (what
platform.platform.Platform uses): ``fairleads``, ``advance``, ``reactions``, tensions.
"""

from __future__ import annotations

import math

import numpy as np

from .catenary import Segment, profile, solve_line, strain_energy


class QuasiStaticLines:
    """Lines from fixed anchors to moving fairleads, each a multi-segment elastic catenary."""

    def __init__(self, anchors, fairleads_x, segments: list[list[Segment]], *, seabed: bool,
                 seabed_z: float | None = None, tol: float = 1.0e-3):
        """anchors, fairleads_x: (n_lines, 3) [m]; seabed=False: no seabed; seabed_z: its height [m]
        (None: at each anchor); tol: fairlead motion [m] below which a line keeps its last solve."""
        self.anchors_x = np.asarray(anchors, float).reshape(-1, 3)
        self.fairlead_x = np.asarray(fairleads_x, float).reshape(-1, 3).copy()
        self.segments = segments
        self.seabed = seabed
        # the anchors' heights above the seabed [m]
        self.anchor_height = (np.zeros(len(self.anchors_x)) if seabed_z is None else
                              np.maximum(self.anchors_x[:, 2] - seabed_z, 0.0))
        self.tol = tol
        n = len(self.anchors_x)
        self.fairleads = np.arange(n)        # "node" of each line's fairlead: the line index
        self.anchors = np.arange(n)
        self.solved_x = np.full((n, 3), np.nan)
        self.pull = np.zeros((n, 3))          # force of the line on its fairlead [N]
        self.anchor_pull = np.zeros((n, 3))   # force of the line on its anchor [N]
        self.states = [None] * n
        self.time = 0.0
        self._update()

    def _update(self) -> None:
        moved = np.linalg.norm(self.fairlead_x - self.solved_x, axis=1)
        for k in np.nonzero(~(moved <= self.tol))[0]:  # NaN (never solved) counts as moved
            d = self.fairlead_x[k] - self.anchors_x[k]
            h = math.hypot(d[0], d[1])
            e = d[:2] / h if h > 0 else np.array([1.0, 0.0])
            st = solve_line(self.segments[k], horizontal=h, vertical=float(d[2]), seabed=self.seabed,
                            anchor_height=float(self.anchor_height[k]))
            H = st.horizontal_tension
            self.pull[k] = [-H * e[0], -H * e[1], -st.fairlead_vertical]
            self.anchor_pull[k] = [H * e[0], H * e[1], st.anchor_vertical]
            self.states[k] = st
            self.solved_x[k] = self.fairlead_x[k]

    def stable_step(self) -> float:
        return math.inf

    def advance(self, dt: float, nsub: int, fairlead_x=None, fairlead_v=None, *, t_start: float | None = None) -> None:
        """Move the fairleads to ``fairlead_x`` (n_lines, 3) [m] and re-solve the lines that moved;
        ``time`` becomes t_start (default: the present ``time``) + nsub dt [s]. No drag, so no waves."""
        if fairlead_x is not None:
            self.fairlead_x[:] = np.asarray(fairlead_x, float).reshape(-1, 3)
        self._update()
        self.time = (self.time if t_start is None else float(t_start)) + dt * nsub

    def energies(self) -> tuple[float, float]:
        """(kinetic [J], elastic [J]): no line dynamics, so no kinetic energy; the elastic energy of
        each line's elastic catenary at its last solve (catenary.strain_energy, a closed form)."""
        return 0.0, float(sum(strain_energy(segs, st) for segs, st in zip(self.segments, self.states)))

    def reactions(self, nodes: np.ndarray) -> np.ndarray:
        """(k, 3) force [N] of the lines on their fairleads (``nodes`` are line indices)."""
        return self.pull[nodes].copy()

    def fairlead_tensions(self) -> np.ndarray:
        return np.linalg.norm(self.pull, axis=1)

    def anchor_tensions(self) -> np.ndarray:
        return np.linalg.norm(self.anchor_pull, axis=1)

    def polylines(self, points_per_segment: int = 10) -> tuple[np.ndarray, np.ndarray]:
        """(k, 3) points [m] along every line, anchor first, and (k,) the line index of each point."""
        pts, ids = [], []
        for k, st in enumerate(self.states):
            prof = profile(self.segments[k], st, points_per_segment)
            d = self.fairlead_x[k] - self.anchors_x[k]
            h = math.hypot(d[0], d[1])
            e = d[:2] / h if h > 0 else np.array([1.0, 0.0])
            a = self.anchors_x[k]
            pts.append(np.column_stack([a[0] + prof[:, 1] * e[0], a[1] + prof[:, 1] * e[1], a[2] + prof[:, 2]]))
            ids.append(np.full(len(prof), k))
        return np.vstack(pts), np.concatenate(ids)

    # -- checkpoint ----------------------------------------------------------------------------
    def state(self) -> dict[str, np.ndarray]:
        return dict(fairlead_x=self.fairlead_x, solved_x=self.solved_x, pull=self.pull,
                    anchor_pull=self.anchor_pull, time=np.array(self.time))

    def set_state(self, s: dict) -> None:
        self.fairlead_x[:] = s["solved_x"]  # re-solve at the positions of the last solves: line shapes
        self.solved_x[:] = np.nan
        self._update()
        self.fairlead_x[:] = s["fairlead_x"]
        self.time = float(s["time"])
        self.pull[:] = s["pull"]
        self.anchor_pull[:] = s["anchor_pull"]
