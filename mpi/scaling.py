"""Parallel scaling of the level-ice sheet of Zhu & Ji (2022, Table 4): strong (the 92,000-element
sheet on more ranks) and weak (a sheet that grows with the ranks, 92,000 elements per rank).

Strong, on N ranks:  .venv/bin/mpiexec -n N .venv/bin/python mpi/scaling.py [--steps 500]
Or all at once:      .venv/bin/python mpi/scaling.py --sweep 1,2,4,8   (launches each N itself)
Weak, in one job:    .venv/bin/mpiexec -n N .venv/bin/python mpi/scaling.py --weak [--per-rank 92000]
On a cluster:        sbatch --nodes=8 --ntasks-per-node=128 mpi/slurm.sbatch mpi/scaling.py --weak

Prints particle-steps per second (total and per rank; the fastest of --repeat timed blocks), the
share of wall time spent in the halo exchange and collectives (including waiting for the slowest
rank), and the parallel efficiency against the 1-rank run. On this 2-core machine, 4 and 8 ranks
are oversubscribed: their throughput is meaningless, but their communication share is a planning
figure for a cluster.

``--weak`` runs the whole series inside the one job it is launched as: for each count k of
``--counts`` (default 1, 2, 4, ... up to the job's size, and the size itself) the first k ranks step
a sheet of k x ``--per-rank`` elements cut into k square subdomains (pice/bench/scaling_model.py
weak_sheet: 9.0 km x 9.0 km on 1,024 ranks; --per-rank 112800 makes it 10 km x 10 km) while the
other ranks sleep; the weak efficiency is the per-rank rate on k ranks over that on one. Every rank
builds the whole sheet at set-up (pice/memory.py), so the largest sheets are refused when the ranks
of a node lack the memory: the series stops there and says so (docs/performance.md, "Scaling").
"""

from __future__ import annotations

import argparse
import os
import pathlib
import re
import subprocess
import sys
import time

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))

PER_RANK = 92_000  # elements per rank in the weak series: the reference sheet's


def sheet_job(length: float, width: float):
    """The drifting sheet of ``length`` x ``width`` [m] (1 m elements, 1 m/s), no load balancing."""
    from pice.scenes.reference import zhu_ji_sheet_job

    return zhu_ji_sheet_job(length=length, width=width, source="scaling", parallel={"balance_every": 0})


def timed(comm, length: float, width: float, steps: int, warmup: int, repeat: int) -> dict | None:
    """Step the sheet on ``comm`` (collective): the fastest of ``repeat`` blocks of ``steps`` steps.
    Returns on rank 0 {"ranks", "elements", "ghosts" (sum), "ghosts_max" (per rank), "wall" [s],
    "rate" [particle-steps/s], "per_rank", "comm_share" (halo + waiting over wall)}; None elsewhere."""
    from pice.simulation import Simulation

    sim = Simulation(sheet_job(length, width), comm=comm)
    sim.advance(warmup)
    timers = sim.enable_timers()  # pice/timers.py: the halo exchange and the waiting in collectives
    best = None
    for _ in range(repeat):  # the fastest of `repeat` blocks: the machine is shared and noisy
        comm.barrier()
        timers.start()
        t0 = time.perf_counter()
        sim.advance(steps)
        comm.barrier()
        elapsed = comm.max(time.perf_counter() - t0)
        exchange = comm.max(timers.seconds["halo"] + timers.seconds["waiting"])
        if best is None or elapsed < best[0]:
            best = (elapsed, exchange)
    elapsed, exchange = best
    n = comm.sum(sim.p.nlocal)
    ghosts = sim.p.n - sim.p.nlocal
    total, most = comm.sum(ghosts), comm.max(ghosts)
    if comm.rank != 0:
        return None
    rate = n * steps / elapsed
    return {"ranks": comm.size, "elements": n, "ghosts": total, "ghosts_max": most, "steps": steps,
            "wall": elapsed, "rate": rate, "per_rank": rate / comm.size, "comm_share": exchange / elapsed}


def line(r: dict) -> str:
    return (f"ranks={r['ranks']} elements={r['elements']} ghosts={r['ghosts']} steps={r['steps']} "
            f"wall={r['wall']:.2f}s rate={r['rate']:.4e} per_rank={r['per_rank']:.4e} "
            f"comm_share={r['comm_share']:.3f}")


def measure(steps: int, warmup: int, length: float, width: float, repeat: int) -> None:
    """Strong scaling: one point, on the ranks this process was launched with."""
    from pice.parallel.comm import world

    result = timed(world(), length, width, steps, warmup, repeat)
    if result is not None:
        print(line(result))


def sweep(counts: list[int], steps: int, length: float, width: float, repeat: int) -> None:
    """Strong scaling: launch each rank count of ``counts`` with the venv's mpiexec."""
    from pice.parallel.comm import without_launcher

    env = without_launcher()
    bindir = pathlib.Path(sys.executable).parent
    rates = {}
    for n in counts:
        cmd = [str(bindir / "mpiexec"), "-n", str(n), sys.executable, __file__, "--steps", str(steps),
               "--length", str(length), "--width", str(width), "--repeat", str(repeat)]
        out = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True).stdout
        found = [ln for ln in out.splitlines() if ln.startswith("ranks=")][-1]
        print(found + ("  (oversubscribed)" if n > (os.cpu_count() or 1) else ""), flush=True)
        rates[n] = float(re.search(r"rate=(\S+)", found).group(1))
    if 1 in rates:
        for n in counts:
            if n > 1 and n <= (os.cpu_count() or 1):
                print(f"parallel efficiency on {n} ranks: {rates[n] / (n * rates[1]):.1%}")


# -- weak scaling ---------------------------------------------------------------------------------
def default_counts(size: int) -> list[int]:
    counts = [1 << i for i in range(size.bit_length()) if (1 << i) <= size]
    return counts + ([size] if counts[-1] != size else [])


def weak(per_rank: int, counts: list[int] | None, steps: int, warmup: int, repeat: int) -> None:
    """The weak series inside this job: each count k on the first k ranks, the others asleep."""
    from pice.bench.scaling_model import square_grid, weak_sheet
    from pice.errors import PiceError
    from pice.parallel.comm import MPIComm, SerialComm, launched_by_mpi

    world = None
    if launched_by_mpi():
        from mpi4py import MPI

        world = MPI.COMM_WORLD
    rank, size = (world.Get_rank(), world.Get_size()) if world is not None else (0, 1)
    counts = counts or default_counts(size)
    if max(counts) > size:
        raise SystemExit(f"--counts {max(counts)} is more than the {size} rank(s) this job has")
    if rank == 0:
        print(f"weak scaling: {per_rank:,} elements per rank, counts {counts}, {steps} steps x "
              f"{repeat} blocks after {warmup}", flush=True)
    base = None
    for k in counts:
        length, width = weak_sheet(k, per_rank)
        result, refused = None, None
        sub = world.Split(0 if rank < k else MPI.UNDEFINED, rank) if world is not None else None
        if rank < k:
            comm = SerialComm() if k == 1 else MPIComm(sub)
            try:
                result = timed(comm, length, width, steps, warmup, repeat)
            except PiceError as exc:  # raised on every rank of the point (on_root): memory refused
                refused = str(exc)
            if sub is not None:
                sub.Free()
        if world is not None:
            _sleep_until_all(world)
            refused = world.bcast(refused, root=0)
        if rank == 0:
            if refused:
                print(f"ranks={k}: refused: {refused}", flush=True)
            else:
                base = base or result["per_rank"]
                px, py = square_grid(k)
                print(f"{line(result)} sheet={length:.0f}x{width:.0f}m grid={px}x{py} "
                      f"ghosts_max={result['ghosts_max']} weak_efficiency={result['per_rank'] / base:.3f}",
                      flush=True)
        if refused:
            return


def _sleep_until_all(world, poll: float = 0.05) -> None:
    """A barrier the idle ranks wait at asleep (not spinning on a core the others may share)."""
    req = world.Ibarrier()
    while not req.Test():
        time.sleep(poll)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=500)
    ap.add_argument("--warmup", type=int, default=20)
    ap.add_argument("--length", type=float, default=400.0, help="[m] strong scaling's sheet along the current")
    ap.add_argument("--width", type=float, default=200.0, help="[m] strong scaling's sheet across it")
    ap.add_argument("--repeat", type=int, default=3, help="timed blocks of --steps; the fastest counts")
    ap.add_argument("--sweep", help="strong scaling: comma-separated rank counts to launch, e.g. 1,2,4,8")
    ap.add_argument("--weak", action="store_true", help="the weak series inside this job (see above)")
    ap.add_argument("--per-rank", type=int, default=PER_RANK, help="weak: elements per rank (fewer to test)")
    ap.add_argument("--counts", help="weak: comma-separated rank counts (default 1, 2, 4, ... and the size)")
    args = ap.parse_args()
    if args.weak:
        counts = [int(c) for c in args.counts.split(",")] if args.counts else None
        weak(args.per_rank, counts, args.steps, args.warmup, args.repeat)
    elif args.sweep:
        sweep([int(c) for c in args.sweep.split(",")], args.steps, args.length, args.width, args.repeat)
    else:
        measure(args.steps, args.warmup, args.length, args.width, args.repeat)


if __name__ == "__main__":
    main()
