"""The 92k benchmark sheet on N ranks with the cuts balanced by elements and by measured busy time
([parallel] balance_by, parallel/domain.py): step time, each rank's busy and waiting time, and
the elements each rank owns, measured in one launch (the two settings alternate, ``--rounds``).

    mpiexec -n 2 python mpi/balance_by_time.py [--steps 500] [--every 100] [--rounds 2] [--threshold 1.05]

Each setting starts from the same sheet (pice/bench/sheet.py), takes ``--settle`` steps in which
the cuts may move every ``--every`` steps (the first check only starts the busy clock), then a
window of ``--steps`` steps with the cuts fixed. Run it on an otherwise idle machine.
"""

from __future__ import annotations

import argparse
from time import perf_counter

from pice.bench.sheet import reference_sheet
from pice.parallel.comm import world


def window(by: str, args, comm) -> dict:
    sim, _ = reference_sheet(length=args.length, width=args.width, comm=comm)
    d = sim.domain
    d.parallel = d.parallel.model_copy(update={"balance_by": by, "balance_every": args.every,
                                               "imbalance_threshold": args.threshold})
    sim.advance(args.settle)
    d.parallel = d.parallel.model_copy(update={"balance_every": 0})  # the cuts stay for the window
    comm.barrier()
    t0, w0 = perf_counter(), comm.blocked
    sim.advance(args.steps)
    mine = perf_counter() - t0
    waited = comm.blocked - w0
    return dict(by=by, step_ms=1e3 * comm.max(mine) / args.steps, busy_ms=comm.gather(1e3 * (mine - waited) / args.steps),
                wait_ms=comm.gather(1e3 * waited / args.steps), elements=comm.gather(sim.p.nlocal))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=500, help="steps in each measured window")
    ap.add_argument("--settle", type=int, default=600, help="steps before the window, the cuts free to move")
    ap.add_argument("--every", type=int, default=100, help="balance_every during --settle")
    ap.add_argument("--rounds", type=int, default=2, help="windows of each setting, alternating")
    ap.add_argument("--threshold", type=float, default=1.05, help="[parallel] imbalance_threshold during --settle")
    ap.add_argument("--length", type=float, default=400.0)
    ap.add_argument("--width", type=float, default=200.0)
    args = ap.parse_args()
    comm = world()
    for r in range(args.rounds):
        for by in ("elements", "time"):
            res = window(by, args, comm)
            if comm.rank == 0:
                print(f"round {r} balance_by {by:8s} step {res['step_ms']:.3f} ms | busy "
                      + " ".join(f"{b:.3f}" for b in res["busy_ms"]) + " ms | waiting "
                      + " ".join(f"{w:.3f}" for w in res["wait_ms"]) + " ms | elements "
                      + " ".join(str(n) for n in res["elements"]), flush=True)


if __name__ == "__main__":
    main()
