"""Particles.place_rows, the layout of a halo rebuild (parallel/halo.py): the same rows as
replace_rows of the kept rows and the arrivals in gid order followed by the ghosts, made in one
copy; a rebuild where nobody leaves or arrives writes only the ghosts (the owned rows stay in
their memory)."""

import numpy as np
import pytest
from scenes import slope_job, job_from_text

from pice import state
from pice.scenes.level_ice import build_level_ice
from pice.state import PER_PARTICLE, _runs


def _sheet():
    p, _ = build_level_ice(job_from_text(slope_job(duration=0.05, snapshots=1)))
    p.allocate_dynamic(1, 0)
    rng = np.random.default_rng(3)
    for name in PER_PARTICLE:  # distinct values in every row and column
        a = getattr(p, name)
        if a.dtype.kind == "f":
            a[...] = rng.normal(size=a.shape)
    return p


@pytest.mark.parametrize("run_copy_min", [1, 10**9])
def test_place_rows_lays_out_what_replace_rows_would(run_copy_min, monkeypatch):
    """Also whether the kept rows are copied by runs of rows (slices) or by fancy indexing."""
    monkeypatch.setattr(state, "RUN_COPY_MIN", run_copy_min)
    p, q = _sheet(), _sheet()
    n = p.n
    keep = np.sort(np.random.default_rng(1).choice(n, size=n - 5, replace=False))
    leaving = np.setdiff1d(np.arange(n), keep)
    arrivals = {name: getattr(p, name)[leaving[::-1]].copy() for name in PER_PARTICLE}  # as if sent back
    arrivals["gid"] = arrivals["gid"] + 1000  # new gids, after every kept one
    ghosts = [{name: getattr(p, name)[:3].copy() for name in PER_PARTICLE}]
    gids = np.concatenate([p.gid[keep], arrivals["gid"]])
    dest = np.empty(len(gids), np.int64)
    dest[np.argsort(gids, kind="stable")] = np.arange(len(gids))
    merged = {name: np.concatenate([getattr(q, name)[keep], arrivals[name]]) for name in PER_PARTICLE}
    order = np.argsort(merged["gid"], kind="stable")
    q.replace_rows([{k: v[order] for k, v in merged.items()}] + ghosts, len(gids))
    p.place_rows(keep, dest[:len(keep)], arrivals, dest[len(keep):], len(gids), ghosts)
    for name in PER_PARTICLE:
        np.testing.assert_array_equal(getattr(p, name), getattr(q, name), err_msg=name)
    assert p.nlocal == q.nlocal and np.all(p.bond_j == -1)


def test_a_rebuild_where_nobody_moves_writes_only_the_ghosts():
    p = _sheet()
    n = p.n
    ident = np.arange(n)
    ghosts = [{name: getattr(p, name)[:4].copy() for name in PER_PARTICLE}]
    p.place_rows(ident, ident, None, ident[:0], n, ghosts)  # first: the buffers are made
    owned_x = p.x[:n]
    before = owned_x.copy()
    fewer = [{name: g[:2] for name, g in ghosts[0].items()}]
    p.place_rows(ident, ident, None, ident[:0], n, fewer)
    assert np.shares_memory(p.x, owned_x) and p.n == n + 2
    np.testing.assert_array_equal(p.x[:n], before)
    np.testing.assert_array_equal(p.x[n:], ghosts[0]["x"][:2])
    p.x = p.x.copy()  # an array replaced by someone else: the next rebuild copies again, correctly
    p.place_rows(ident, ident, None, ident[:0], n, ghosts)
    assert not np.shares_memory(p.x, owned_x)
    np.testing.assert_array_equal(p.x[:n], before)
    np.testing.assert_array_equal(p.x[n:], ghosts[0]["x"])


def test_runs_of_rows_cover_the_kept_rows_once():
    """state._runs: the maximal runs in which source and destination rows both advance by one."""
    keep = np.array([0, 1, 2, 5, 6, 9])
    keep_to = np.array([0, 1, 3, 4, 5, 6])
    src, dst, length = _runs(keep, keep_to)
    assert src.tolist() == [0, 2, 5, 9] and dst.tolist() == [0, 3, 4, 6] and length.tolist() == [2, 1, 2, 1]
    assert [len(a) for a in _runs(keep[:0], keep_to[:0])] == [0, 0, 0]
