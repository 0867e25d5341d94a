"""The MPI latency and bandwidth of this machine, and what pice's own calls cost (a few seconds).

    .venv/bin/mpiexec -n 2 .venv/bin/python mpi/pingpong.py [--budget 0.3] [--ghosts 314] [--json PATH]

* ping-pong between ranks 0 and 1 (mpi4py Send/Recv of numpy buffers, 8 B to 4 MiB): half the
  round trip [us] per size, as the median and the fastest of timed batches; the latency is the
  fastest half round trip of 8 B, the bandwidth [GB/s] the best of size over fastest half round trip
  (and the 4 MiB figure, beyond the caches);
* pice's calls through pice.parallel.comm.MPIComm, on every rank, as the step makes them: the
  rebuild check's allreduce of a Python float (pickled), the health check's Allreduce of two
  doubles, the loads' Reduce and the poses' Bcast of the full scene (6 and 13 doubles: one body), and the
  ghost update (Alltoall of the counts, then Alltoallv of ``--ghosts`` records of 9 doubles to each
  neighbour rank: 0 and 1 exchange with each other, further ranks with rank +-1).

The figures are those of a quiet machine only when nothing else runs: on a loaded one (other jobs on
the cores) a rank can be descheduled in the middle of a round trip, and the medians grow by orders of
magnitude while the fastest batches stay near the quiet figure. Rank 0 prints, and writes the JSON
(default runs/pingpong_<R>ranks.json) with the load average beside the figures.
"""

from __future__ import annotations

import argparse
import json
import os
import pathlib
import statistics
import sys
import time

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))

SIZES = [8, 64, 512, 4096, 32768, 262144, 1 << 20, 1 << 22]  # [B]


def timed(fn, budget: float, comm, batch: int) -> list[float]:
    """Seconds per call of ``fn`` over batches of ``batch`` calls, for about ``budget`` seconds
    (rank 0 decides when to stop, so every rank makes the same calls)."""
    for _ in range(3):
        fn()
    out, start = [], time.perf_counter()
    while True:
        comm.Barrier()
        t0 = time.perf_counter()
        for _ in range(batch):
            fn()
        out.append((time.perf_counter() - t0) / batch)
        done = comm.bcast(time.perf_counter() - start > budget if comm.Get_rank() == 0 else None, root=0)
        if done:
            return out


def pingpong(comm, nbytes: int, budget: float) -> list[float]:
    """Half round trips [s] between ranks 0 and 1 of ``nbytes`` bytes (other ranks idle)."""
    rank = comm.Get_rank()
    buf = np.zeros(max(nbytes // 8, 1))

    def once():
        if rank == 0:
            comm.Send(buf, dest=1, tag=7)
            comm.Recv(buf, source=1, tag=7)
        elif rank == 1:
            comm.Recv(buf, source=0, tag=7)
            comm.Send(buf, dest=0, tag=7)

    batch = 200 if nbytes <= 4096 else (20 if nbytes <= 262144 else 4)
    return [t / 2.0 for t in timed(once, budget, comm, batch)]


def pice_calls(pcomm, comm, budget: float, ghosts: int) -> dict[str, list[float]]:
    """Seconds per call of the collectives and the exchange the step makes (pice.parallel.comm)."""
    rank, size = pcomm.rank, pcomm.size
    counts = np.zeros(size, np.int64)
    for r in (rank - 1, rank + 1) if size > 2 else (1 - rank,):
        if 0 <= r < size:
            counts[r] = 9 * ghosts
    send = np.random.default_rng(rank).random(int(counts.sum()))
    sends = [(r, send[:n]) for r, n in enumerate(counts) if n]  # the same records to each neighbour
    recvs = [(r, n) for r, n in enumerate(counts) if n]
    flags, loads, poses = np.zeros(3), np.zeros((1, 6)), np.zeros((1, 13))  # the full scene: one body
    calls = {"allreduce of a float (pickled: as Halo.needs_rebuild was, every step)": lambda: pcomm.max(1.0),
             "Allreduce of 3 doubles (Halo.needs_rebuild on a check, Simulation.check_health)":
                 lambda: pcomm.max(flags),
             "Reduce of 6 doubles (the loads of one body, full scene)": lambda: pcomm.reduce_sum(loads),
             "Bcast of 13 doubles (the pose of one body, full scene)": lambda: pcomm.bcast_array(poses),
             f"ghost update, {ghosts} records of 72 B per neighbour, Alltoall + Alltoallv (before issue 12)":
                 lambda: pcomm.exchange_doubles(send, counts),
             f"ghost update, {ghosts} records of 72 B per neighbour, Isend/Irecv + Waitall (Halo.update)":
                 lambda: pcomm.finish_neighbour_exchange(pcomm.start_neighbour_exchange(sends, recvs))}
    return {name: timed(fn, budget, comm, 50) for name, fn in calls.items()}


def us(values: list[float]) -> dict:
    return {"median_us": 1e6 * statistics.median(values), "min_us": 1e6 * min(values)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--budget", type=float, default=0.3, help="[s] of timing per figure")
    ap.add_argument("--ghosts", type=int, default=314, help="ghost records per neighbour in the ghost update "
                    "(the 92k sheet on 2 ranks: 303-345, mpi/comm_volume.py)")
    ap.add_argument("--json", help="where to write the figures (default runs/pingpong_<R>ranks.json)")
    args = ap.parse_args()

    from mpi4py import MPI

    from pice.parallel.comm import MPIComm

    comm = MPI.COMM_WORLD
    if comm.Get_size() < 2:
        sys.exit("pingpong.py needs at least 2 ranks: mpiexec -n 2 .venv/bin/python mpi/pingpong.py")
    load = list(os.getloadavg())
    sizes = {n: us(pingpong(comm, n, args.budget)) for n in SIZES}
    calls = {k: us(v) for k, v in pice_calls(MPIComm(), comm, args.budget, args.ghosts).items()}
    if comm.Get_rank() != 0:
        return
    big = SIZES[-1]
    result = {"ranks": comm.Get_size(), "mpi_library": MPI.Get_library_version().splitlines()[0].strip(),
              "load_average_before": load, "load_average_after": list(os.getloadavg()),
              "latency_us": sizes[8]["min_us"], "latency_median_us": sizes[8]["median_us"],
              "bandwidth_GBps": max(n / (sizes[n]["min_us"] * 1e-6) for n in SIZES) / 1e9,
              "bandwidth_4MiB_GBps": big / (sizes[big]["min_us"] * 1e-6) / 1e9,
              "bandwidth_4MiB_median_GBps": big / (sizes[big]["median_us"] * 1e-6) / 1e9,
              "pingpong": {str(n): v for n, v in sizes.items()}, "pice_calls": calls}
    print(f"MPI: {result['mpi_library']}; {result['ranks']} ranks; load average {load[0]:.2f} before"
          + ("  (loaded machine: medians are not a quiet machine's)" if load[0] > 0.5 else ""))
    print(f"  latency {result['latency_us']:.2f} us (fastest half round trip of 8 B; median "
          f"{result['latency_median_us']:.2f} us); bandwidth {result['bandwidth_GBps']:.2f} GB/s at best, "
          f"{result['bandwidth_4MiB_GBps']:.2f} GB/s for {big >> 20} MiB (median "
          f"{result['bandwidth_4MiB_median_GBps']:.2f} GB/s)")
    print(f"  {'bytes':>9} {'half round trip: median us':>28} {'fastest us':>11}")
    for n in SIZES:
        print(f"  {n:9d} {sizes[n]['median_us']:28.2f} {sizes[n]['min_us']:11.2f}")
    print(f"  {'pice call, per call':<66} {'median us':>10} {'fastest us':>11}")
    for name, v in calls.items():
        print(f"  {name:<66} {v['median_us']:10.2f} {v['min_us']:11.2f}")
    path = pathlib.Path(args.json or f"runs/pingpong_{result['ranks']}ranks.json")
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(result, indent=2) + "\n")
    print(f"written {path}")


if __name__ == "__main__":
    main()
