"""The 2-rank parallel efficiency of the 92k sheet as issue 12 asks it measured: rounds of `pice bench
--scene sheet` on 1 and on R ranks, interleaved, of one or more checkouts side by side, and medians.

    .venv/bin/python benchmarks/efficiency.py                          # this checkout, 3 rounds, 2 ranks
    .venv/bin/python benchmarks/efficiency.py --trees ../before .      # the commit before against now
    .venv/bin/python benchmarks/efficiency.py --rounds 5 --steps 1500 --warmup 300

A round runs, for each tree in turn, 1 rank then R ranks (one launch at a time: two timed runs at once
measure each other). The efficiency of a pair is the R-rank throughput over R times the 1-rank
throughput of the same round, so that a machine whose speed drifts between rounds moves both. Each
tree runs with its own code (PYTHONPATH) in this interpreter's environment. Printed per round and per
tree: the two throughputs [particle-steps/s], the efficiency, the efficiency of the median blocks
(`pice bench`'s "median block": the step's cost over blocks of 10 steps with the rare long pauses of
a shared machine left out, which on R ranks stall every rank) and the R-rank waits for the ghost
update (median / 90th percentile, the rank that waits most); then each tree's median efficiencies.
The issue's figure is the first; the second tells the code's cost from the machine's interruptions.
The JSON of every launch stays in --out.
"""

from __future__ import annotations

import argparse
import json
import pathlib
import statistics
import subprocess
import sys

from pice.parallel.comm import without_launcher


def bench(tree: pathlib.Path, ranks: int, args, json_path: pathlib.Path) -> dict:
    """One `pice bench --scene sheet` launch of ``tree``'s code on ``ranks`` ranks; its JSON."""
    bindir = pathlib.Path(sys.executable).parent
    cmd = [sys.executable, "-c", "import sys; from pice.cli import main; sys.exit(main())", "bench",
           "--scene", "sheet", "--steps", str(args.steps), "--warmup", str(args.warmup),
           "--length", str(args.length), "--width", str(args.width), "--json", str(json_path)]
    if ranks > 1:
        cmd = [str(bindir / "mpiexec"), "-n", str(ranks)] + cmd
    env = without_launcher()
    env["PYTHONPATH"] = str(tree)
    done = subprocess.run(cmd, cwd=tree, env=env, capture_output=True, text=True)
    if done.returncode != 0:
        raise SystemExit(f"efficiency.py: `pice bench` of {tree} on {ranks} rank(s) failed "
                         f"(exit {done.returncode}):\n{done.stdout[-2000:]}{done.stderr[-2000:]}")
    return json.loads(json_path.read_text())


def waits(result: dict) -> str:
    """The ghost-update wait of the rank that waits most: 'median / p90 ms' ('-' if none)."""
    per_rank = [w for w in result["sheet"]["split"].get("ghost_wait_ms") or [] if w]
    if not per_rank:
        return "-"
    w = max(per_rank, key=lambda w: w["p90"])
    return f"{w['median']:.3f} / {w['p90']:.3f} ms"


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--trees", nargs="+", default=["."], help="checkouts to compare (default: this one)")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--ranks", type=int, default=2)
    ap.add_argument("--steps", type=int, default=1500, help="steps in each measured window")
    ap.add_argument("--warmup", type=int, default=300)
    ap.add_argument("--length", type=float, default=400.0, help="the sheet's length [m]")
    ap.add_argument("--width", type=float, default=200.0, help="the sheet's width [m]")
    ap.add_argument("--out", default="runs/efficiency", help="folder for each launch's JSON")
    args = ap.parse_args(argv)
    for name, least in (("rounds", 1), ("ranks", 2), ("steps", 1), ("warmup", 0)):
        if getattr(args, name) < least:
            ap.error(f"--{name} {getattr(args, name)}: give at least {least}")
    trees = [pathlib.Path(t).resolve() for t in args.trees]
    for t in trees:
        if not (t / "pice" / "cli.py").is_file():
            raise SystemExit(f"efficiency.py: {t} is not a pice checkout (no pice/cli.py); give --trees paths "
                             "to checkouts, e.g. a `git worktree add ../before HEAD~1`")
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    eff = {str(t): [] for t in trees}
    robust = {str(t): [] for t in trees}
    print(f"{'round':>5}  {'tree':<40} {'1 rank':>10} {f'{args.ranks} ranks':>10} {'efficiency':>10} "
          f"{'median block':>12}  ghost wait (median / p90)")
    for r in range(1, args.rounds + 1):
        for k, t in enumerate(trees):
            one = bench(t, 1, args, out / f"tree{k}_1r_round{r}.json")
            many = bench(t, args.ranks, args, out / f"tree{k}_{args.ranks}r_round{r}.json")
            a = one["sheet"]["particle_steps_per_second"]
            b = many["sheet"]["particle_steps_per_second"]
            e = b / (args.ranks * a)
            eff[str(t)].append(e)
            ma = one["sheet"].get("median_block_particle_steps_per_second")  # absent before 2026-12-05
            mb = many["sheet"].get("median_block_particle_steps_per_second")
            m = mb / (args.ranks * ma) if ma and mb else float("nan")
            robust[str(t)].append(m)
            commit = (many["code"]["commit"] or "no git")[:10] + ("+" if many["code"].get("dirty") else "")
            print(f"{r:>5}  {str(t)[-29:] + ' ' + commit:<40} {a:>10.3e} {b:>10.3e} {e:>10.3f} {m:>12.3f}  {waits(many)}",
                  flush=True)
    for t, values in eff.items():
        print(f"median efficiency {statistics.median(values):.3f} over {len(values)} round(s) "
              f"(of the median blocks: {statistics.median(robust[t]):.3f}): {t}")
    return {t: statistics.median(v) for t, v in eff.items()}


if __name__ == "__main__":
    main()
