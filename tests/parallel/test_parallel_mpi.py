"""MPI behaviour on 2 ranks (run under `mpiexec -n 2 python -m pytest -m mpi`).

Conservation: particles and bonds are counted exactly, never approximately. Balance: max/mean
owned particles per rank <= 1.1 after the cuts move. Reduction: rank 0 receives the sum.
"""

import numpy as np
import pytest

from pice.job import parse_job
from pice.parallel.comm import world
from pice.parallel.coupling import BodyCoupling
from pice.simulation import Simulation

pytestmark = pytest.mark.mpi

TABLE4_BONDS = {"normal_stiffness": 1.72e7, "shear_stiffness": 1.72e6, "normal_strength": 1.5e6,
                "shear_strength": 1.5e6, "friction": 0.3}


@pytest.fixture(scope="module")
def comm():
    c = world()
    if c.size != 2:
        pytest.skip("needs exactly 2 ranks: mpiexec -n 2 python -m pytest -m mpi")
    return c


def _small_sheet(parallel: dict):
    """A 20 m x 10 m sheet of 1 m elements at rest in water (215 elements), with ``parallel``."""
    return parse_job({"run": {"duration": 1.0}, "water": {"density": 1035.0},
                      "ice": {"length": 20.0, "width": 10.0, "density": 920.0}, "bond": TABLE4_BONDS,
                      "parallel": parallel})


def _owned_gids(sim):
    parts = sim.comm.gather(sim.p.gid[:sim.p.nlocal].copy())
    return sim.comm.bcast(None if parts is None else np.concatenate(parts))


def test_drifting_sheet_keeps_every_particle_and_bond(comm):
    """A sheet drifting at 2 m/s across the rank boundary: particle and bond counts conserved exactly."""
    job = parse_job({
        "run": {"duration": 10.0},
        "water": {"density": 1035.0, "current": [2.0, 0.0]},
        "ice": {"length": 10.0, "width": 6.0, "density": 920.0, "velocity": [2.0, 0.0]},
        "bond": {**TABLE4_BONDS, "breakable": False},
        "parallel": {"domain": [[0.0, 0.0], [30.0, 6.0]], "balance_every": 0},
    })
    sim = Simulation(job, comm=comm)
    assert sim.domain.decomp.px == 2 and sim.domain.decomp.box(0)[1] == pytest.approx(15.0)
    n0 = comm.sum(sim.p.nlocal)
    b0 = comm.sum(sim.p.bond_count())
    all_gids = np.arange(n0)
    owners_seen = set()
    while sim.c.time < 8.0:  # 16 m of drift: every particle crosses x = 15 m
        sim.advance(500)
        assert comm.sum(sim.p.nlocal) == n0
        assert comm.sum(sim.p.bond_count()) == b0
        assert np.array_equal(np.sort(_owned_gids(sim)), all_gids)  # each particle owned exactly once
        xlo, xhi, _, _ = sim.domain.decomp.box(comm.rank)
        x = sim.p.x[:sim.p.nlocal, 0]
        half_skin = 0.5 * job.parallel.skin  # owned particles may stray this far before a rebuild
        assert np.all((x >= xlo - half_skin) & (x < xhi + half_skin))
        owners_seen.add(int(comm.sum(int(sim.p.nlocal > 0) << comm.rank)))
    # the sheet lived on rank 0 only, then on both, then on rank 1 only: its particles migrated
    assert {1, 3, 2} <= owners_seen


def test_sheet_inside_one_subdomain_gets_balanced(comm):
    """All ice starts in rank 0's half of the domain; after rebalancing max/mean <= 1.1."""
    job = _small_sheet({"domain": [[0.0, 0.0], [100.0, 10.0]], "balance_every": 10})
    sim = Simulation(job, comm=comm)
    n0 = comm.sum(sim.p.nlocal)
    assert comm.max(sim.p.nlocal) == n0  # everything on one rank at the start
    sim.advance(10)
    counts = comm.gather(sim.p.nlocal)
    counts = comm.bcast(counts)
    assert sum(counts) == n0
    assert max(counts) / (n0 / 2) <= 1.1
    assert sim.domain.imbalance <= 1.1
    b = comm.sum(sim.p.bond_count())
    sim.advance(50)  # keeps running with bonds across the new cut
    assert comm.sum(sim.p.bond_count()) == b


def test_rank0_reduction_and_pose_broadcast(comm):
    """Loads from every rank sum on rank 0; poses set on rank 0 reach every rank unchanged."""
    coupling = BodyCoupling(comm, 2)
    local = np.full((2, 6), comm.rank + 1.0)
    total = coupling.reduce_loads(local)
    if comm.rank == 0:
        assert np.array_equal(total, np.full((2, 6), 3.0))
    else:
        assert total is None
    poses = np.arange(14.0).reshape(2, 7) if comm.rank == 0 else np.zeros((2, 7))
    assert np.array_equal(coupling.broadcast_poses(poses), np.arange(14.0).reshape(2, 7))


def test_weighted_cuts_even_out_the_weight(comm):
    """rebalanced() with each rank's particles weighing its cost: the cut moves to the weighted
    quantile. A uniform 40 x 10 row of points cut at x = 20; rank 0's points weigh 3, rank 1's 1:
    the total weight 3 * 200 + 200 = 800 splits at 400, i.e. at x = 20 * 400 / 600 = 13.3 m
    (within a histogram bin of 40/1024 m and the points' 1 m spacing)."""
    from pice.parallel.balance import rebalanced
    from pice.parallel.decomposition import uniform

    decomp = uniform(2, lo=(0.0, 0.0), hi=(40.0, 10.0))
    gx, gy = np.meshgrid(np.arange(40) + 0.5, np.arange(10) + 0.5, indexing="ij")
    pts = np.column_stack([gx.ravel(), gy.ravel(), np.zeros(gx.size)])
    mine = pts[(pts[:, 0] < 20.0) == (comm.rank == 0)]
    new = rebalanced(comm, decomp, mine, weight=3.0 if comm.rank == 0 else 1.0)
    assert abs(new.x_cuts[1] - 40.0 / 3.0) <= 1.0
    assert rebalanced(comm, decomp, mine).x_cuts[1] == pytest.approx(20.0, abs=1.0)  # unweighted: the middle


class _SlowOnRankZero:
    """A force term that does nothing but take 2 ms a step on rank 0: the work of a platform."""

    name = "slow"

    def __init__(self, rank):
        self.rank = rank

    def add_forces(self, p, c, dt):
        if self.rank == 0:
            import time

            time.sleep(2e-3)


def test_balance_by_time_gives_the_slow_rank_fewer_elements(comm):
    """balance_by = "time": rank 0 takes 2 ms a step more (a sleeping term) than the ~0.1 ms of its
    half of a 20 m x 10 m sheet (215 elements). The first check (step 10) only starts the clock;
    each check after it weighs every element by its rank's busy time per element, and the cut
    moves to the weighted median: with busy times B0 >> B1, rank 0 keeps k (B0 + B1) / (2 B0), about
    half its k elements, per check (a damped step towards even busy times, which holds as the
    sleep does not scale with k): 107 -> ~55 -> ~30 -> ~16 at steps 20, 30, 40. Checked: rank 0
    at most 15 % of the elements at step 45, every element and bond kept. With balance_by =
    "elements" the counts stay even (max 55 %)."""
    def run(by):
        job = _small_sheet({"balance_every": 10, "balance_by": by})
        sim = Simulation(job, comm=comm)
        sim.terms.append(_SlowOnRankZero(comm.rank))
        n0, b0 = comm.sum(sim.p.nlocal), comm.sum(sim.p.bond_count())
        sim.advance(45)
        assert comm.sum(sim.p.nlocal) == n0 and comm.sum(sim.p.bond_count()) == b0
        return comm.bcast(comm.gather(sim.p.nlocal)), n0

    (counts, n0) = run("time")
    assert counts[0] <= 0.15 * n0, counts
    (counts, n0) = run("elements")
    assert max(counts) <= 0.55 * n0, counts


def test_balance_by_work_evens_out_the_modelled_work(comm):
    """balance_by = "work": the elements of the 20 m x 10 m sheet with x < 4 m are marked as touching a
    hull (their hull contact history set), so each weighs ELEMENT + HULL = 220 against 10 for the rest
    (physics/work.py). The weighted median then lies inside the marked strip: after the check at step
    10 the two ranks' modelled work is within the threshold (1.05) plus one lattice column (the cut
    moves by whole columns of about 10 elements, 10 x 220 = 2,200 of a total near 13,000), the rank
    holding the strip has few elements, and every element and bond is kept. "elements" keeps the
    counts even (reference: the weights' sum, counted exactly in whole numbers)."""
    from pice.physics.work import element_work

    def run(by):
        sim = Simulation(_small_sheet({"balance_every": 10, "balance_by": by}), comm=comm)
        p = sim.p
        n0, b0 = comm.sum(p.nlocal), comm.sum(p.bond_count())
        p.hull_hist[:p.nlocal, 0, 1] = np.where(p.x[:p.nlocal, 0] < 4.0, 1.0, 0.0)
        total = comm.sum(float(element_work(p).sum()))
        sim.advance(10)
        p = sim.p
        assert comm.sum(p.nlocal) == n0 and comm.sum(p.bond_count()) == b0
        work = comm.bcast(comm.gather(float(element_work(p).sum())))
        assert sum(work) == total  # the marks moved with their elements
        return work, comm.bcast(comm.gather(p.nlocal)), n0

    work, counts, n0 = run("work")
    column = 10 * 220.0
    assert max(work) <= 1.05 * sum(work) / 2 + column, work
    assert min(counts) <= 0.35 * n0, counts
    work, counts, n0 = run("elements")
    assert max(counts) <= 0.55 * n0 and max(work) > 1.5 * sum(work) / 2, (counts, work)


def test_ranks_that_would_round_differently_are_refused(comm, monkeypatch):
    """A rank whose CPU fuses multiply-adds and one whose CPU does not would compute the bond across
    their cut to different bits and could break it on one side only: refused on every rank, with the
    fix named; ranks alike pass."""
    import pice.parallel.comm as C
    from pice.errors import PiceError

    monkeypatch.setattr(C, "compiles_fused_multiply_add", lambda: comm.rank == 0)
    with pytest.raises(PiceError, match=r"ranks \[0\] run on CPUs with fused multiply-add.*NUMBA_CPU_NAME=generic"):
        C.refuse_mixed_arithmetic(comm)
    monkeypatch.setattr(C, "compiles_fused_multiply_add", lambda: False)
    C.refuse_mixed_arithmetic(comm)


def test_a_bond_the_halo_could_lose_stops_the_run_at_the_rebuild_on_every_rank(comm):
    """parallel/halo.py Halo.resolve, at every rebuild: a bond longer than ghost_width - skin (its ends
    may move apart by the skin before the next rebuild, and its partner would leave the halo unseen)
    and a partner beyond the halo already stop the run on both ranks (one reduction), each with a
    GhostWidthError that names the length or the missing partner and the fix. The sheet's bonds are
    1 m long; the threshold is 1.068 m (Table 4's breaking stretch; domain.ghost_width)."""
    from pice.parallel.halo import GhostWidthError

    sim = Simulation(_small_sheet({"balance_every": 0}), comm=comm)
    p, halo = sim.p, sim.domain.halo
    limit = halo.ghost_width - halo.skin
    halo.rebuild(p)  # the sheet as built passes
    if comm.rank == 0:  # an element 2 m or more from the cut, pulled from an owned partner to 0.05 m past the limit
        cut = sim.domain.decomp.x_cuts[1]
        i = next(k for k in range(p.nlocal) if cut - p.x[k, 0] > 2.0 and (p.bond_j[k] >= 0).any())
        j = int(p.bond_j[i][p.bond_j[i] >= 0][0])
        d = p.x[i] - p.x[j]
        p.x[i] = p.x[j] + d / np.linalg.norm(d) * (limit + 0.05)
    with pytest.raises(GhostWidthError, match=r"a bond is stretched to 1\.1\d* m, beyond the ghost width .* "
                                              r"less the skin .*raise \[parallel\] skin"):
        halo.rebuild(p)

    sim = Simulation(_small_sheet({"balance_every": 0}), comm=comm)
    p, halo = sim.p, sim.domain.halo
    gid = None
    if comm.rank == 0:  # a bond across the cut: its partner on rank 1 is a ghost here
        i = next(k for k in range(p.nlocal) if (p.bond_j[k] >= p.nlocal).any())
        gid = int(p.gid[p.bond_j[i][p.bond_j[i] >= p.nlocal][0]])
    gid = comm.bcast(gid)
    if comm.rank == 1:  # rank 1 moves that partner 3 m further into its side: out of rank 0's halo
        p.x[np.nonzero(p.gid[:p.nlocal] == gid)[0][0], 0] += 3.0
    with pytest.raises(GhostWidthError, match=r"bond partner\(s\) not found within the ghost width .*"
                                              r"raise \[parallel\] skin"):
        halo.rebuild(p)
