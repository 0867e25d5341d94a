"""A model of pice's parallel scaling: the step time of a sheet on P ranks from its parts
(docs/performance.md, "Scaling"; mpi/scaling.py measures it, mpi/comm_volume.py and mpi/pingpong.py
measure the inputs).

    python -m pice.bench.scaling_model [--bench runs/bench_<commit>_1ranks.json] [--sigma 0.02]

It follows the code as it is: the ice is cut into a px x py grid of equal rectangles as close to
square as P allows (parallel/decomposition.py: a prime P gives slabs); each rank receives as ghosts
the particles within the ghost width of its rectangle (parallel/halo.py), 9 doubles each every step;
one rank owns no particle twice. Per step on P > 1 ranks (counted by mpi/comm_volume.py):

* the ghost update: one message to and from each neighbour, point to point, the counts known since
  the rebuild (Halo.start_update, Halo.finish_update);
* every ``motion_check_every`` steps the rebuild check's Allreduce of 3 doubles (Halo.needs_rebuild:
  the motion bound skips the steps in between);
* every ``check_every`` steps, the health check's Allreduce of 3 doubles;
* with bodies, the poses' Bcast and the loads' Reduce (log2 P rounds each), and rank 0's platform
  and lines, which every other rank waits for (an Amdahl term: it does not shrink with P);
* every ``rebuild_every`` steps a migration and ghost rebuild: two pickled alltoalls (P - 1
  messages each), the rows copied and sorted, and a scan of the owned particles for every rank
  (Halo._ghost_targets: P x n operations).

On one rank none of this exists (SerialComm: no message, no rebuild). Compute is the owned
particles over the one-rank rate, plus a fraction of a particle's cost for each ghost. The slowest
rank sets the step: rank-to-rank jitter of relative size ``sigma`` adds sigma x E[max of P standard
normals] to the compute of a step (0: a perfectly quiet machine).
"""

from __future__ import annotations

import argparse
import glob
import json
import math
import os
from dataclasses import dataclass, replace

import numpy as np

GHOST_BYTES = 72  # [B] a ghost's x, v, w every step (kernels/halo.GHOST_DOUBLES doubles of 8 B)


def hcp_density(d: float) -> float:
    """Elements per square metre [1/m^2] of the one-layer HCP lattice of diameter d [m]."""
    return 2.0 / (math.sqrt(3.0) * d * d)


def log2_rounds(p: int) -> int:
    """Rounds [-] of a tree collective on p ranks."""
    return int(math.ceil(math.log2(p))) if p > 1 else 0


def expected_max_normal(p: int) -> float:
    """E[max of p standard normal variables] [-] (0 for p = 1; 0.564 for 2; ~sqrt(2 ln p) for large p)."""
    if p <= 1:
        return 0.0
    from scipy.special import ndtr

    x = np.linspace(-12.0, 12.0, 48001)
    pdf = np.exp(-0.5 * x * x) / math.sqrt(2.0 * math.pi)
    return float(np.trapezoid(x * p * pdf * ndtr(x) ** (p - 1), x))


def grid(p: int, lx: float, ly: float) -> tuple[int, int]:
    """(px, py) of pice's decomposition for a sheet lx x ly [m] (parallel/decomposition.grid_shape)."""
    from ..parallel.decomposition import grid_shape

    return grid_shape(p, lx=lx, ly=ly)


@dataclass(frozen=True)
class Costs:
    """Unit costs of a step. Defaults: measured on this machine (loaded; docs/performance.md)."""

    rate: float = 3.1e6           # [particle-steps/s] of one rank on the 92k sheet (README "Speed")
    latency: float = 2.5e-6       # [s] per message (mpi/pingpong.py: fastest half round trip of 8 B)
    bandwidth: float = 2.0e9      # [B/s] (mpi/pingpong.py: 1.6-5.7 GB/s, loaded)
    call: float = 2.0e-6          # [s] Python and mpi4py per collective call (mpi/pingpong.py, pice calls)
    pickle_round: float = 1.5e-6  # [s] pickling per round of a pickled collective
    ghost_fraction: float = 0.1   # a ghost's cost as a fraction of an owned particle's (assumed)
    rank_loop: float = 0.15e-6    # [s] per rank per step: Halo.update's lists over all P ranks (measured)
    target_scan: float = 5.1e-9   # [s] per owned particle per rank at a rebuild (_ghost_targets, measured)
    rebuild_row: float = 0.37e-6  # [s] per owned particle per rebuild: rows copied, bonds resolved (measured, below)
    sigma: float = 0.0            # relative jitter of a rank's step time [-]


@dataclass(frozen=True)
class Scene:
    """A sheet and what its step does besides the ice."""

    name: str
    length: float            # [m] along x
    width: float             # [m] along y
    d: float = 1.0           # [m] element diameter
    ghost_width: float = 1.3685  # [m] (parallel/domain.ghost_width: bond at break + skin; 92k sheet)
    rebuild_every: float = 160.0  # [steps] skin / 2 over the distance a step moves the ice
    motion_check_every: float = 17.9  # [steps] between rebuild checks (sheet: 27 checks in 3 x 161 steps)
    check_every: int = 10    # [steps] the health check
    bodies: int = 0          # bodies (poses broadcast, loads reduced every step)
    platform: float = 0.0    # [s] rank 0's platform and lines per step
    bytes_per_element: float = 1644.0  # [B] every per-particle array at set-up (pice/memory.py)

    @property
    def elements(self) -> float:
        return hcp_density(self.d) * self.length * self.width


#: the 92k benchmark sheet (pice/bench/sheet.py): dt 9.35e-4 s at 1 m/s -> a rebuild each 160 steps
SHEET = Scene("92k sheet", 400.0, 200.0)
#: the full reference scene: dt 1.46e-4 s -> 1,027 steps a rebuild; one body, 12 lines on rank 0 (0.49 ms a step:
#: pice bench, 2 ranks, commit dcf33c4)
FULL = Scene("full scene", 400.0, 200.0, ghost_width=1.3006, rebuild_every=1027.0, motion_check_every=37.0,
             check_every=50, bodies=1, platform=0.49e-3)


def square_grid(p: int) -> tuple[int, int]:
    """(px, py) with px * py = p, px >= py, as close to square as p allows (a prime p gives slabs)."""
    py = max(k for k in range(1, math.isqrt(p) + 1) if p % k == 0)
    return p // py, py


def weak_sheet(p: int, per_rank: float = 92_000.0, d: float = 1.0) -> tuple[float, float]:
    """(length, width) [m] of the weak series' sheet on p ranks (mpi/scaling.py --weak): px x py squares
    (square_grid) of side s [m], each holding ``per_rank`` elements of diameter d [m] of the one-layer
    HCP lattice, so that pice's decomposition (parallel/decomposition.grid_shape) cuts it into p squares."""
    px, py = square_grid(p)
    s = math.sqrt(per_rank / hcp_density(d))
    return px * s, py * s


def weak_scene(p: int, per_rank: float = 92_000.0, base: Scene = SHEET) -> Scene:
    """The weak series' sheet on p ranks as a Scene (weak_sheet)."""
    length, width = weak_sheet(p, per_rank, base.d)
    return replace(base, name=f"weak {p}", length=length, width=width)


def ghost_counts(scene: Scene, px: int, py: int) -> np.ndarray:
    """(px, py) ghosts [-] each rank receives: its rectangle grown by the ghost width, within the sheet,
    less itself, times the lattice density (with the ghost width above a rectangle's side, ghosts
    come from beyond the next rank: the grown rectangle still counts them)."""
    gw, rho = scene.ghost_width, hcp_density(scene.d)
    xs, ys = np.linspace(0.0, scene.length, px + 1), np.linspace(0.0, scene.width, py + 1)
    wx = np.minimum(xs[1:] + gw, scene.length) - np.maximum(xs[:-1] - gw, 0.0)
    wy = np.minimum(ys[1:] + gw, scene.width) - np.maximum(ys[:-1] - gw, 0.0)
    own = np.outer(np.diff(xs), np.diff(ys))
    return rho * (np.outer(wx, wy) - own)


def neighbours(scene: Scene, px: int, py: int) -> int:
    """Ranks [-] the most connected rank sends ghosts to (8 in a grid of cells wider than the ghost width)."""
    reach_x = min(px - 1, math.ceil(scene.ghost_width / (scene.length / px)))
    reach_y = min(py - 1, math.ceil(scene.ghost_width / (scene.width / py)))
    span_x, span_y = min(2 * reach_x + 1, px), min(2 * reach_y + 1, py)
    return span_x * span_y - 1


def collective(c: Costs, rounds: int, pickled: bool = False, nbytes: float = 0.0) -> float:
    """[s] of one collective call of ``rounds`` rounds carrying ``nbytes`` per round."""
    return c.call + rounds * (c.latency + (c.pickle_round if pickled else 0.0) + nbytes / c.bandwidth)


def step_terms(scene: Scene, p: int, c: Costs = Costs()) -> dict:
    """The parts of the slowest rank's step [s] on p ranks, their "total" and the facts behind them."""
    px, py = grid(p, scene.length, scene.width)
    n = scene.elements / p
    g = ghost_counts(scene, px, py)
    gmax = float(g.max())
    t = {"compute": n / c.rate, "ghosts": gmax * c.ghost_fraction / c.rate}
    t["jitter"] = c.sigma * expected_max_normal(p) * t["compute"]
    t["platform"] = scene.platform
    if p == 1:  # SerialComm: no message, no collective, no rebuild
        t.update(halo=0.0, collectives=0.0, rank_loops=0.0, rebuild=0.0)
    else:
        lg = log2_rounds(p)
        k = neighbours(scene, px, py)
        t["halo"] = k * c.latency + GHOST_BYTES * gmax / c.bandwidth + 2 * c.call
        coll = collective(c, lg) / scene.motion_check_every                     # Halo.needs_rebuild
        coll += collective(c, lg) / scene.check_every                            # health check
        if scene.bodies:
            coll += 2 * collective(c, lg)                                         # poses Bcast, loads Reduce
        t["collectives"] = coll
        t["rank_loops"] = c.rank_loop * p
        alltoall = 2 * (c.call + (p - 1) * (c.latency + c.pickle_round)
                        + gmax * scene.bytes_per_element / c.bandwidth)
        local = n * (c.target_scan * p + c.rebuild_row)
        t["rebuild"] = (alltoall + local + collective(c, 2 * lg, pickled=True)) / scene.rebuild_every
    t["total"] = sum(t.values())
    t.update(p=p, px=px, py=py, owned=n, ghosts_max=gmax, neighbours=neighbours(scene, px, py) if p > 1 else 0,
             ghost_bytes=GHOST_BYTES * gmax if p > 1 else 0.0, setup_bytes=scene.elements * scene.bytes_per_element)
    return t


def strong(scene: Scene, counts, c: Costs = Costs()) -> list[dict]:
    """Step terms on each rank count of ``counts`` for the same scene, with "speedup" and "efficiency"."""
    rows = [step_terms(scene, p, c) for p in counts]
    t1 = step_terms(scene, 1, c)["total"]
    for r in rows:
        r["speedup"] = t1 / r["total"]
        r["efficiency"] = r["speedup"] / r["p"]
    return rows


def weak(counts, c: Costs = Costs(), per_rank: float = 92_000.0) -> list[dict]:
    """Step terms with per_rank elements on each rank (weak_scene), with "efficiency" = T(1) / T(P)."""
    t1 = step_terms(weak_scene(1, per_rank), 1, c)["total"]
    rows = []
    for p in counts:
        r = step_terms(weak_scene(p, per_rank), p, c)
        r["efficiency"] = t1 / r["total"]
        rows.append(r)
    return rows


def slab_ghosts(scene: Scene, p: int) -> float:
    """Ghosts [-] of the most connected rank if the code cut slabs across x instead of a grid: both
    sides of an interior slab (one side on 2 ranks)."""
    return float(ghost_counts(scene, p, 1).max()) if p > 1 else 0.0


# -- the measurements the model is checked against (README "Speed", docs/reference_scene.md "Cost",
#    mpi/comm_volume.py on 2 ranks here) ----------------------------------------------------------
MEASURED = {
    "sheet_rate_1": (5.8e6, 6.0e6),      # [particle-steps/s] one rank, pice bench (issue 12, commit dcf33c4)
    "sheet_efficiency_2": (0.855, 0.891),  # 2 ranks, three interleaved pairs (docs/performance.md)
    "sheet_comm_share_2": (0.08, 0.09),  # halo and waiting over the step, 2 ranks, pice bench
    "sheet_ghosts_2": (303, 345),        # per rank, counted: mean over the window, at its end
    "sheet_bytes_2": 21_818,             # [B] ghost update per step and rank, counted
    "full_ms_2": 10.2,                   # [ms] per step of the full scene, 2 ranks (pice bench, dcf33c4)
    # a halo rebuild of the sheet on 2 ranks (docs/performance.md, "The ghost update and
    # the rebuild"): 12 ms without migrants, ~17 ms with, for 46,000 owned elements: 0.26-0.37 us each
    "sheet_rebuild_us_per_owned": 0.37,
}


def fit_sigma(scene: Scene, p: int, efficiency: float, c: Costs = Costs()) -> float:
    """The jitter sigma [-] at which the model gives ``efficiency`` on p ranks (bisection)."""
    lo, hi = 0.0, 10.0
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if strong(scene, [p], replace(c, sigma=mid))[0]["efficiency"] > efficiency:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def costs_from_bench(path: str | None, c: Costs = Costs()) -> tuple[Costs, Scene, str]:
    """Costs (the one-rank rate) and the full scene (rank 0's platform) from a `pice bench` JSON of one
    rank: ``path``, else the newest runs/bench_*_1ranks.json; README's figures when there is none."""
    found = sorted(glob.glob("runs/bench_*_1ranks.json"), key=os.path.getmtime) if path is None else [path]
    if not found:
        return c, FULL, "README 'Speed' (3.1e6 particle-steps/s per rank) and docs/reference_scene.md (platform 1.7 ms)"
    data = json.loads(open(found[-1]).read())
    c = replace(c, rate=data["sheet"]["particle_steps_per_second_per_rank"])
    full = FULL
    if data.get("full"):
        full = replace(FULL, platform=data["full"]["split"]["parts"]["platform"]["ms_per_step"] * 1e-3)
    return c, full, f"pice bench {found[-1]}"


def _comm(r: dict) -> float:
    return sum(r.get(k, 0.0) for k in ("halo", "collectives", "rank_loops", "rebuild"))


def strong_table(scene: Scene, counts, c: Costs, jitter: float) -> list[str]:
    rows = strong(scene, counts, c)
    noisy = strong(scene, counts, replace(c, sigma=jitter))
    out = [f"| P | grid | owned | ghosts/rank (max) | slabs: ghosts | neighbours | halo kB/step | compute ms "
           f"| comm ms | platform ms | step ms | speed-up | efficiency | with jitter {jitter:g} |",
           "|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r, q in zip(rows, noisy):
        out.append(f"| {r['p']} | {r['px']}x{r['py']} | {r['owned']:,.0f} | {r['ghosts_max']:,.0f} | "
                   f"{slab_ghosts(scene, r['p']):,.0f} | {r['neighbours']} | {r['ghost_bytes'] / 1e3:.1f} | "
                   f"{1e3 * (r['compute'] + r['ghosts']):.2f} | {1e3 * _comm(r):.3f} | {1e3 * r['platform']:.2f} | "
                   f"{1e3 * r['total']:.2f} | {r['speedup']:.1f} | {r['efficiency']:.3f} | {q['efficiency']:.3f} |")
    return out


def weak_table(counts, c: Costs, jitter: float, per_rank: float) -> list[str]:
    rows, noisy = weak(counts, c, per_rank), weak(counts, replace(c, sigma=jitter), per_rank)
    out = [f"| P | sheet km | grid | elements | ghosts/rank (max) | halo ms | collectives ms | rank loops ms "
           f"| rebuild ms | step ms | efficiency | with jitter {jitter:g} | set-up GB/rank |",
           "|---:|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r, q in zip(rows, noisy):
        sc = weak_scene(r["p"], per_rank)
        out.append(f"| {r['p']} | {sc.length / 1e3:.2f} x {sc.width / 1e3:.2f} | {r['px']}x{r['py']} | "
                   f"{sc.elements:,.0f} | {r['ghosts_max']:,.0f} | {1e3 * r['halo']:.3f} | "
                   f"{1e3 * r['collectives']:.3f} | {1e3 * r['rank_loops']:.3f} | {1e3 * r['rebuild']:.3f} | "
                   f"{1e3 * r['total']:.2f} | {r['efficiency']:.3f} | {q['efficiency']:.3f} | "
                   f"{r['setup_bytes'] / 1e9:.2f} |")
    return out


def check_lines(c: Costs, full: Scene) -> list[str]:
    """The model beside the 1- and 2-rank measurements (MEASURED)."""
    m = MEASURED
    s1, s2 = step_terms(SHEET, 1, c), step_terms(SHEET, 2, c)
    eff = s1["total"] / (2 * s2["total"])
    share = _comm(s2) / s2["total"]
    f2 = step_terms(full, 2, c)
    lo, hi = m["sheet_efficiency_2"]
    return [
        f"- sheet, 1 rank: {1e3 * s1['total']:.1f} ms/step, {SHEET.elements / s1['total']:.3g} particle-steps/s "
        f"(measured {m['sheet_rate_1'][0]:.2g}-{m['sheet_rate_1'][1]:.2g}: the rate is the model's input)",
        f"- sheet, 2 ranks: ghosts/rank {s2['ghosts_max']:.0f} (counted {m['sheet_ghosts_2'][0]} on average, "
        f"{m['sheet_ghosts_2'][1]} at the end), ghost update "
        f"{s2['ghost_bytes'] / 1e3:.1f} kB/step (counted {m['sheet_bytes_2'] / 1e3:.1f}), efficiency {eff:.3f} "
        f"(measured {lo:.2f}-{hi:.2f}), communication share {share:.2%} (measured {m['sheet_comm_share_2'][0]:.0%}-"
        f"{m['sheet_comm_share_2'][1]:.0%}); jitter that gives the measured efficiency: sigma "
        f"{fit_sigma(SHEET, 2, hi, c):.2f}-{fit_sigma(SHEET, 2, lo, c):.2f}",
        f"- full scene, 2 ranks: {1e3 * f2['total']:.1f} ms/step (measured {m['full_ms_2']} ms)"]


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bench", help="a pice bench JSON of one rank (default: the newest runs/bench_*_1ranks.json)")
    ap.add_argument("--sigma", type=float, default=0.02, help="the jitter of the last efficiency column [-]")
    ap.add_argument("--per-rank", type=float, default=92_000.0, help="elements per rank in the weak series")
    args = ap.parse_args(argv)
    c, full, source = costs_from_bench(args.bench)
    strong_counts, weak_counts = [1, 2, 4, 8, 16, 32, 64], [1 << k for k in range(11)]
    print(f"unit costs: {c}\nrate and platform from {source}\n")
    for scene in (SHEET, full):
        print(f"strong scaling, {scene.name} ({scene.elements:,.0f} elements, "
              f"platform {1e3 * scene.platform:.2f} ms/step)")
        print("\n".join(strong_table(scene, strong_counts, c, args.sigma)) + "\n")
    print(f"weak scaling, {args.per_rank:,.0f} elements per rank")
    print("\n".join(weak_table(weak_counts, c, args.sigma, args.per_rank)) + "\n")
    print("check against the measurements:\n" + "\n".join(check_lines(c, full)))


if __name__ == "__main__":
    main()
