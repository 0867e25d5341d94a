"""Pure decomposition functions: every point has one owner, any rank count works, cuts balance."""

import numpy as np
import pytest

from pice.parallel.decomposition import balanced_from_histograms, grid_shape, uniform

pytestmark = pytest.mark.nojit


@pytest.mark.parametrize("size", [1, 2, 3, 4, 5, 6, 7, 8, 12])
def test_any_rank_count_tiles_the_plane(size):
    d = uniform(size, lo=(0.0, 0.0), hi=(400.0, 200.0))
    assert d.px * d.py == size
    rng = np.random.default_rng(size)
    pts = rng.uniform(-100, 500, size=(5000, 2))
    owner = d.owner(pts[:, 0], pts[:, 1])
    assert owner.min() >= 0 and owner.max() < size
    for r in range(size):  # the owner's box contains the point; boxes do not overlap
        xlo, xhi, ylo, yhi = d.box(r)
        mine = pts[owner == r]
        assert np.all((mine[:, 0] >= xlo) & (mine[:, 0] < xhi) & (mine[:, 1] >= ylo) & (mine[:, 1] < yhi))


def test_grid_shape_follows_the_aspect_ratio():
    assert grid_shape(2, lx=400, ly=200) == (2, 1)
    assert grid_shape(2, lx=200, ly=400) == (1, 2)
    assert grid_shape(8, lx=400, ly=200) == (4, 2)
    assert grid_shape(7, lx=1, ly=1) in ((7, 1), (1, 7))  # primes: a strip decomposition
    assert grid_shape(2, lx=10, ly=0) == (2, 1)  # a one-row sheet


def test_balanced_cuts_split_the_weight_evenly():
    """Cuts at histogram quantiles: 3 columns x 2 rows over a non-uniform cloud, counts within 2 %."""
    rng = np.random.default_rng(0)
    x = np.concatenate([rng.uniform(0, 10, 60000), rng.uniform(10, 100, 30000)])
    y = rng.uniform(0, 50, len(x)) ** 1.5
    edges_x = np.linspace(x.min(), x.max() + 1e-9, 2049)
    edges_y = np.linspace(y.min(), y.max() + 1e-9, 2049)
    hx = np.histogram(x, edges_x)[0].astype(float)
    probe = balanced_from_histograms(3, 1, hx, edges_x, np.zeros((3, 2048)), edges_y)
    col = np.clip(np.searchsorted(probe.x_cuts, x, side="right") - 1, 0, 2)
    hy = np.array([np.histogram(y[col == c], edges_y)[0] for c in range(3)], float)
    d = balanced_from_histograms(3, 2, hx, edges_x, hy, edges_y)
    counts = np.bincount(d.owner(x, y), minlength=6)
    assert counts.max() / counts.mean() < 1.02


@pytest.mark.parametrize("size", [2, 6, 8])
def test_owner_is_the_searchsorted_rule_on_and_off_the_cuts(size):
    """Decomposition.owner (kernels/halo.owner_ranks, a loop) gives the rule it replaced:
    clip(searchsorted(cuts, value, "right") - 1) per axis, so a point on a cut belongs to the cell
    above it, points beyond the outer cuts to the outer cells, and a NaN to the last cell."""
    d = uniform(size, lo=(0.0, 0.0), hi=(400.0, 200.0))
    rng = np.random.default_rng(size)
    x = np.concatenate([rng.uniform(-50, 450, 3000), d.x_cuts[1:-1], [-np.inf, np.inf, np.nan, 1e300]])
    y = np.concatenate([rng.uniform(-50, 250, 3000), np.resize(d.y_cuts[0][1:-1], d.px - 1) if d.py > 1
                        else rng.uniform(0, 200, d.px - 1), [0.0, 1.0, 2.0, np.nan]])
    col = np.clip(np.searchsorted(d.x_cuts, x, side="right") - 1, 0, d.px - 1)
    row = np.empty(len(x), np.int64)
    for c in range(d.px):
        sel = col == c
        row[sel] = np.clip(np.searchsorted(d.y_cuts[c], y[sel], side="right") - 1, 0, d.py - 1)
    assert np.array_equal(d.owner(x, y), col * d.py + row)
    strided = np.stack([x, y, x], axis=1)  # as the halo asks: columns of the particles' (n, 3) positions
    assert np.array_equal(d.owner(strided[:, 0], strided[:, 1]), col * d.py + row)
