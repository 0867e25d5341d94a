"""Load balance: move the cuts so every rank owns about the same number of particles, or the same work
(particles weighted by their rank's measured cost, ``balance_by = "time"``, or by each one's modelled
work, ``balance_by = "work"``: parallel/domain.py)."""

from __future__ import annotations

import numpy as np

from .decomposition import Decomposition, balanced_from_histograms

BINS = 1024


def imbalance(comm, nlocal: int) -> float:
    """max/mean of the owned particle count over ranks (1.0 is perfect)."""
    total = comm.sum(int(nlocal))
    most = comm.max(int(nlocal))
    return most / (total / comm.size) if total else 1.0


def rebalanced(comm, decomp: Decomposition, x: np.ndarray, weight=None) -> Decomposition:
    """New cuts at the quantiles of the global particle distribution (histograms, no gather).

    x: (nlocal, 3) owned positions [m]; weight: what each of this rank's particles counts for, one
    number for all (their rank's measured cost) or one each ((nlocal,): their modelled work; whole
    numbers keep the sums, and so the cuts, independent of the order of the rows); None: 1 each
    (parallel/domain.py). Cost: two allreduces of BINS (and px * BINS) counts.
    """
    if comm.size == 1:
        return decomp
    lo = np.array([comm.min(float(x[:, 0].min()) if len(x) else np.inf),
                   comm.min(float(x[:, 1].min()) if len(x) else np.inf)])
    hi = np.array([comm.max(float(x[:, 0].max()) if len(x) else -np.inf),
                   comm.max(float(x[:, 1].max()) if len(x) else -np.inf)])
    pad = 1e-9 * max(1.0, float(np.abs(np.concatenate([lo, hi])).max()))
    x_edges = np.linspace(lo[0] - pad, hi[0] + pad, BINS + 1)
    y_edges = np.linspace(lo[1] - pad, hi[1] + pad, BINS + 1)
    w = None if weight is None else np.broadcast_to(np.asarray(weight, dtype=np.float64), (len(x),))
    x_hist = comm.sum(np.histogram(x[:, 0], bins=x_edges, weights=w)[0].astype(np.float64))
    px, py = decomp.px, decomp.py
    # x cuts first, then each column's y histogram under the new x cuts
    probe = balanced_from_histograms(px, 1, x_hist, x_edges, np.zeros((px, BINS)), y_edges)
    col = np.clip(np.searchsorted(probe.x_cuts, x[:, 0], side="right") - 1, 0, px - 1)
    y_hists = np.zeros((px, BINS))
    for c in range(px):
        y_hists[c] = np.histogram(x[col == c, 1], bins=y_edges, weights=None if w is None else w[col == c])[0]
    y_hists = comm.sum(y_hists)
    return balanced_from_histograms(px, py, x_hist, x_edges, y_hists, y_edges)
