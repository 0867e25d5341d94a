"""The scaling model's arithmetic (pice/bench/scaling_model.py; docs/performance.md, "Scaling"):
its limits, not its figures. No timing here."""

from __future__ import annotations

import math

import pytest

from pice.bench.scaling_model import (FULL, SHEET, Costs, expected_max_normal, ghost_counts, hcp_density,
                                      square_grid, step_terms, strong, weak, weak_scene, weak_sheet)
from pice.parallel.decomposition import grid_shape

COMM_TERMS = ("halo", "collectives", "rank_loops", "rebuild")
JITTERY = Costs(sigma=0.1)


@pytest.mark.parametrize("scene", [SHEET, FULL])
def test_one_rank_sends_nothing(scene):
    t = step_terms(scene, 1)
    assert all(t[k] == 0.0 for k in COMM_TERMS) and t["jitter"] == 0.0
    assert t["ghosts_max"] == 0.0 and t["neighbours"] == 0
    assert strong(scene, [1])[0]["efficiency"] == pytest.approx(1.0)


@pytest.mark.parametrize("costs", [Costs(), JITTERY])
def test_efficiency_never_above_one(costs):
    counts = [1, 2, 3, 4, 5, 7, 8, 13, 16, 32, 64]
    for scene in (SHEET, FULL):
        for row in strong(scene, counts, costs):
            assert 0.0 < row["efficiency"] <= 1.0 + 1e-12
            assert row["total"] > 0.0 and all(row[k] > 0.0 for k in COMM_TERMS if row["p"] > 1)
    for row in weak([1 << k for k in range(11)], costs):
        assert 0.0 < row["efficiency"] <= 1.0 + 1e-12


def test_weak_halo_constant_for_interior_ranks():
    s = math.sqrt(92_000.0 / hcp_density(1.0))
    gw = SHEET.ghost_width
    interior = hcp_density(1.0) * ((s + 2 * gw) ** 2 - s * s)
    for p in (16, 64, 256, 1024):  # grids of 4 x 4 and more: interior ranks with 8 neighbours
        row = weak([p])[0]
        assert row["ghosts_max"] == pytest.approx(interior, rel=1e-9)
        assert row["neighbours"] == 8 and row["owned"] == pytest.approx(92_000.0)
        assert row["halo"] == pytest.approx(weak([16])[0]["halo"])


def test_the_weak_sheet_is_cut_into_squares_by_the_code():
    for p in list(range(1, 65)) + [1024]:
        length, width = weak_sheet(p)
        assert grid_shape(p, lx=length, ly=width) == square_grid(p)
        px, py = square_grid(p)
        assert length / px == pytest.approx(width / py)
    assert weak_scene(1024).length == pytest.approx(9032.5, abs=1.0)  # ~9 km; 10 km at 112,800 a rank
    assert weak_sheet(1024, 112_800)[0] == pytest.approx(10_000.0, rel=1e-3)


def test_ghosts_of_two_halves_are_one_strip():
    g = ghost_counts(SHEET, 2, 1)
    assert g.shape == (2, 1)
    assert g[0, 0] == pytest.approx(hcp_density(1.0) * SHEET.width * SHEET.ghost_width)


def test_the_platform_bounds_the_speed_up():
    t1 = step_terms(FULL, 1)["total"]
    for row in strong(FULL, [2, 8, 64, 512]):
        assert row["speedup"] < t1 / FULL.platform


def test_expected_maximum_of_normals():
    assert expected_max_normal(1) == 0.0
    assert expected_max_normal(2) == pytest.approx(1.0 / math.sqrt(math.pi), abs=1e-6)
    values = [expected_max_normal(p) for p in (2, 4, 16, 64, 1024)]
    assert values == sorted(values) and values[-1] < math.sqrt(2.0 * math.log(1024))
