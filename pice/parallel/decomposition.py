"""Spatial decomposition of the ice in x-y (pure functions, no MPI).

The plane is cut into ``px`` columns along x; each column is cut into ``py`` cells along y with
its own cut positions, so columns balance independently. Rank ``c * py + r`` owns column c, row r.
The outermost cuts are at +-inf: every point has exactly one owner, and a rank may own no ice.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..kernels.halo import owner_ranks


def grid_shape(size: int, *, lx: float, ly: float) -> tuple[int, int]:
    """(px, py) with px * py = size whose cells are closest to square for an lx x ly domain."""
    lx, ly = max(lx, 1e-9), max(ly, 1e-9)  # a one-row sheet has no extent in y
    best, best_cost = (size, 1), math.inf
    for px in range(1, size + 1):
        if size % px:
            continue
        py = size // px
        cost = abs(math.log((lx / px) / (ly / py)))
        if cost < best_cost - 1e-12:
            best, best_cost = (px, py), cost
    return best


@dataclass(frozen=True)
class Decomposition:
    """Cut positions [m]: x_cuts (px+1,), y_cuts (px, py+1), outer cuts infinite."""

    x_cuts: np.ndarray
    y_cuts: np.ndarray

    @property
    def px(self) -> int:
        return len(self.x_cuts) - 1

    @property
    def py(self) -> int:
        return self.y_cuts.shape[1] - 1

    @property
    def size(self) -> int:
        return self.px * self.py

    def owner(self, x: np.ndarray, y: np.ndarray) -> np.ndarray:
        """Rank owning each point (x, y [m]; kernels/halo.owner_ranks)."""
        return owner_ranks(np.asarray(x, float), np.asarray(y, float), np.asarray(self.x_cuts, float),
                           np.asarray(self.y_cuts, float))

    def box(self, rank: int) -> tuple[float, float, float, float]:
        """(xlo, xhi, ylo, yhi) of a rank's subdomain [m]."""
        c, r = divmod(rank, self.py)
        return (float(self.x_cuts[c]), float(self.x_cuts[c + 1]), float(self.y_cuts[c, r]),
                float(self.y_cuts[c, r + 1]))


def _quantile_cuts(hist: np.ndarray, edges: np.ndarray, parts: int) -> np.ndarray:
    """Inner cut positions splitting a histogram into ``parts`` of equal weight."""
    cum = np.concatenate([[0.0], np.cumsum(hist)])
    total = cum[-1]
    if total <= 0:
        return np.linspace(edges[0], edges[-1], parts + 1)[1:-1]
    targets = total * np.arange(1, parts) / parts
    return np.interp(targets, cum, edges)


def uniform(size: int, *, lo: tuple[float, float], hi: tuple[float, float]) -> Decomposition:
    """Equal-size cells over the box lo..hi (the initial layout before any balancing)."""
    px, py = grid_shape(size, lx=hi[0] - lo[0], ly=hi[1] - lo[1])
    xc = np.concatenate([[-np.inf], np.linspace(lo[0], hi[0], px + 1)[1:-1], [np.inf]])
    yin = np.linspace(lo[1], hi[1], py + 1)[1:-1]
    yc = np.tile(np.concatenate([[-np.inf], yin, [np.inf]]), (px, 1))
    return Decomposition(xc, yc)


def balanced_from_histograms(px: int, py: int, x_hist, x_edges, y_hists, y_edges) -> Decomposition:
    """Cuts at the weight quantiles: x from the global x histogram, y per column from its y histogram.

    y_hists is (px, nbins) built with the *new* x cuts (see parallel.balance).
    """
    xc = np.concatenate([[-np.inf], _quantile_cuts(x_hist, x_edges, px), [np.inf]])
    yc = np.empty((px, py + 1))
    for c in range(px):
        yc[c] = np.concatenate([[-np.inf], _quantile_cuts(y_hists[c], y_edges, py), [np.inf]])
    return Decomposition(xc, yc)
