"""What one step sends: ghosts per rank, messages and bytes per step, counted in the code.

    .venv/bin/mpiexec -n 2 .venv/bin/python mpi/comm_volume.py                 # the 92k sheet, 200 steps
    .venv/bin/mpiexec -n 2 .venv/bin/python mpi/comm_volume.py --job jobs/zhu_ji_2022_semisub_small.toml --steps 50
    .venv/bin/mpiexec -n 2 .venv/bin/python mpi/comm_volume.py --length 40 --width 20 --steps 20   # a quick check

The simulation runs on pice.parallel.counting.CountingComm, which records every collective and
exchange the step really issues, by kind and by the pice function that issued it (docs/performance.md,
"Scaling"). The sheet is pice/bench/sheet.py's (the benchmark sheet of `pice bench`); ``--job`` takes
a job file instead (e.g. the coarse reference scene, for the platform's collectives). Counting begins
after ``--warmup`` steps; after the window ``--rebuilds`` halo rebuilds are forced and timed. Printed
on rank 0 and written as JSON (``--json``, default runs/comm_volume_<R>ranks.json). The counts do not
depend on the machine; the seconds do (the time inside each call, waiting for the slowest rank
included): on a loaded machine they are not comparable.
"""

from __future__ import annotations

import argparse
import json
import os
import pathlib
import sys
import time

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))


def build(comm, args):
    """(Simulation, description) of the counted scene on ``comm``."""
    if args.job:
        from pice.job import load_job
        from pice.simulation import Simulation

        path = pathlib.Path(args.job)
        return Simulation(load_job(path), base_dir=path.parent, comm=comm), str(path)
    from pice.bench.sheet import reference_sheet

    sim, _ = reference_sheet(length=args.length, width=args.width, broken=args.broken, comm=comm)
    return sim, f"benchmark sheet {args.length:g} m x {args.width:g} m, {args.broken} bonds broken"


def per_rank(sim) -> dict:
    """This rank's owned elements, ghosts, neighbours it sends ghosts to and the ghost width [m]."""
    halo = sim.domain.halo
    return {"owned": int(sim.p.nlocal), "ghosts": int(sim.p.n - sim.p.nlocal),
            "ghosts_sent": int(sum(len(i) for i in halo.send_idx)),
            "neighbours": int(sum(1 for i in halo.send_idx if len(i))), "ghost_width_m": halo.ghost_width,
            "box": [float(v) for v in sim.domain.decomp.box(sim.comm.rank)]}


def summarise(tables: list[list[dict]], ranks: list[dict], steps: int, wall: float, scene: str) -> dict:
    """Rank 0: the rows averaged over ranks and per step, the rebuilds, the step's totals."""
    keys = sorted({(r["kind"], r["caller"]) for t in tables for r in t})
    rows = []
    for kind, caller in keys:
        mine = [next((r for r in t if (r["kind"], r["caller"]) == (kind, caller)), None) for t in tables]
        calls = [r["calls"] if r else 0 for r in mine]
        tot = {f: sum(r[f] if r else 0 for r in mine) / len(tables) for f in ("messages", "bytes", "seconds")}
        rows.append({"kind": kind, "caller": caller, "calls_per_step": max(calls) / steps,
                     "messages_per_step": tot["messages"] / steps, "bytes_per_step": tot["bytes"] / steps,
                     "us_per_call": 1e6 * tot["seconds"] / max(max(calls), 1)})
    rebuild_calls = next((r["calls_per_step"] for r in rows if r["caller"] == "Halo.rebuild"
                          and r["kind"] == "alltoall"), 0.0)
    rebuilds = rebuild_calls * steps / 2.0  # two alltoalls a rebuild: the migration and the ghosts
    update = [r for r in rows if r["caller"] != "Halo.rebuild"]
    return {"scene": scene, "ranks": len(tables), "steps": steps, "wall_s": wall,
            "ms_per_step": 1e3 * wall / steps, "per_rank": ranks, "rebuilds": rebuilds,
            "rows": rows,
            "per_step_without_rebuilds": {
                "calls": sum(r["calls_per_step"] for r in update),
                "messages": sum(r["messages_per_step"] for r in update),
                "bytes": sum(r["bytes_per_step"] for r in update)},
            "per_rebuild": {"bytes": sum(r["bytes_per_step"] for r in rows if r["caller"] == "Halo.rebuild")
                            * steps / max(rebuilds, 1)}}


def report(s: dict) -> list[str]:
    lines = [f"{s['scene']}: {s['ranks']} rank(s), {s['steps']} steps counted, {s['ms_per_step']:.2f} ms/step "
             f"(wall, with counting), {s['rebuilds']:g} halo rebuild(s) in the window"]
    for k, r in enumerate(s["per_rank"]):
        lines.append(f"  rank {k}: {r['owned']:,} owned, {r['ghosts']:,} ghosts received, {r['ghosts_sent']:,} "
                     f"sent to {r['neighbours']} neighbour(s); ghost width {r['ghost_width_m']:.4g} m")
    lines.append(f"  {'kind':<10} {'issued by':<32} {'calls/step':>10} {'msgs/step':>10} {'bytes/step':>11} "
                 f"{'us/call':>9}")
    for r in s["rows"]:
        lines.append(f"  {r['kind']:<10} {r['caller']:<32} {r['calls_per_step']:10.4f} "
                     f"{r['messages_per_step']:10.4f} {r['bytes_per_step']:11.1f} {r['us_per_call']:9.1f}")
    t = s["per_step_without_rebuilds"]
    lines.append(f"  per step without rebuilds (mean per rank): {t['calls']:.2f} calls, {t['messages']:.2f} "
                 f"point-to-point messages, {t['bytes'] / 1e3:.2f} kB; "
                 f"per rebuild {s['per_rebuild']['bytes'] / 1e3:.1f} kB")
    lines.append("  bytes: payload this rank sends (8 B a double, pickles as mpi4py sends them); "
                 "us/call: wall time inside the call, waiting included (this machine, loaded or not)")
    return lines


def forced_rebuilds(sim, comm, count: int) -> list[float]:
    """Seconds [s] of ``count`` halo rebuilds forced after the window (Domain.rebuild: the migration
    and the ghosts, what a rebuild does every skin/2 of motion), each from a barrier, the slowest rank's."""
    out = []
    for _ in range(count if comm.size > 1 else 0):
        comm.inner.barrier()
        t0 = time.perf_counter()
        sim.domain.rebuild(sim.p)
        out.append(comm.inner.max(time.perf_counter() - t0))
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=200)
    ap.add_argument("--warmup", type=int, default=20)
    ap.add_argument("--length", type=float, default=400.0, help="[m] of the sheet along the current")
    ap.add_argument("--width", type=float, default=200.0, help="[m] of the sheet across it")
    ap.add_argument("--broken", type=int, default=300, help="bonds broken at random before counting")
    ap.add_argument("--job", help="count this job file's scene instead of the sheet")
    ap.add_argument("--rebuilds", type=int, default=3, help="halo rebuilds timed after the window")
    ap.add_argument("--json", help="where to write the figures (default runs/comm_volume_<R>ranks.json)")
    args = ap.parse_args()

    from pice.parallel.comm import world
    from pice.parallel.counting import CountingComm

    comm = CountingComm(world())
    sim, scene = build(comm, args)
    sim.advance(args.warmup)
    comm.inner.barrier()
    comm.reset()
    t0 = time.perf_counter()
    sim.advance(args.steps)
    wall = comm.inner.max(time.perf_counter() - t0)
    tables = comm.inner.gather(comm.table())
    rebuild_s = forced_rebuilds(sim, comm, args.rebuilds)
    ranks = comm.inner.gather(per_rank(sim))
    if comm.rank != 0:
        return
    s = summarise(tables, ranks, args.steps, wall, scene)
    s["forced_rebuild_ms"] = [1e3 * t for t in rebuild_s]
    if rebuild_s:
        s["forced_rebuild_us_per_owned"] = 1e6 * min(rebuild_s) / max(r["owned"] for r in ranks)
    s["load_average"] = list(os.getloadavg())
    print("\n".join(report(s)), flush=True)
    if rebuild_s:
        print(f"  forced rebuilds (migration and ghosts, slowest rank): "
              f"{', '.join(f'{t:.1f}' for t in s['forced_rebuild_ms'])} ms, the fastest "
              f"{s['forced_rebuild_us_per_owned']:.2f} us per owned element of the largest rank")
    path = pathlib.Path(args.json or f"runs/comm_volume_{s['ranks']}ranks.json")
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(s, indent=2) + "\n")
    print(f"written {path}")


if __name__ == "__main__":
    main()
