"""The grids docs/buoy_design.md sets beside Cai (2018) Tables 6-4 to 6-9, read from a buoy sweep's folder.

    python benchmarks/buoy_sweep_tables.py [jobs/cai_2018_buoy_sweep.toml] [--out RUNS_DIR] [--extreme-also DIR ...]

Rows: the hull angle alpha 30-70 deg; columns: D_max 7-10.5 m (Table 6-1). Each cell: our value and,
in brackets, the thesis's (seed 004, Tables 6-4 to 6-9, typed in below; "-": not in its table, "*":
overturned). A finished phase is read from its study.json; a phase still running from its finished
designs' run files (pice.study.metrics.run_metrics, the metrics the study's table uses), judged by
the sweep file's criteria for that phase. Markdown on stdout.

--extreme-also: folders of other studies with an "extreme" phase (a sweep file of the extreme phase
alone, run on designs the sweep did not keep, such as the thesis's survivors of its normal phase),
whose designs join the extreme grids.
"""

import argparse
import json
import math
import pathlib
import sys

from pice.study.criteria import judge, parse_criterion
from pice.study.sweep import load_sweep

D = [7.0, 7.5, 8.0, 8.5, 9.0, 9.5, 10.0, 10.5]
A = [30.0, 35.0, 40.0, 45.0, 50.0, 55.0, 60.0, 65.0, 70.0]
_ = None
OVR = "*"
# seed 004, Tables 6-4 .. 6-8 (rows alpha 30..70, columns D_max 7..10.5); None: "-"
T64 = [[_]*8, [_]*7 + [1.53], [_]*4 + [1.57, 2.18, 2.71, 3.16], [_, _, 1.85, 2.63, 3.28, 3.81, 4.25, 4.61],
       [1.74, 2.78, 3.62, 4.30, 4.84, 5.27, 5.62, 5.89], [3.61, 4.53, 5.25, 5.81, 6.24, 6.56, 6.81, 6.98],
       [5.36, 6.14, 6.72, 7.15, 7.47, 7.68, 7.83, 7.92], [6.96, 7.59, 8.03, 8.34, 8.54, 8.66, 8.71, 8.72],
       [8.38, 8.86, 9.16, 9.35, 9.45, 9.47, 9.45, 9.39]]
T65 = [[_]*8, [_]*7 + [5.38], [_]*4 + [7.29, 6.03, 5.42, 4.94], [_, _, 8.69, 7.49, 6.79, 5.90, 4.71, 3.92],
       [8.89, 8.22, 7.34, 7.98, 6.23, 5.74, 5.13, 16.91], [8.58, 7.62, 6.32, 6.63, 5.24, 4.98, 8.38, 5.30],
       [7.34, 6.98, 6.07, 6.97, 5.20, 5.15, 5.95, 9.96], [6.82, 6.02, 7.45, 5.57, 4.68, 7.21, OVR, OVR],
       [7.28, 7.24, OVR, 6.63, 7.67, 10.09, OVR, OVR]]
T66 = [[_]*8, [_]*8, [_]*8, [_]*7 + [4.53], [_]*6 + [4.82, _], [_]*4 + [4.70, 4.83, _, 4.29],
       [_, _, 4.28, 4.59, 4.48, 4.17, 4.35, _], [4.20, 3.85, 4.58, 4.62, 4.00, 3.42, _, _],
       [4.46, 4.36, _, 4.71, 4.23, 3.53, _, _]]
T67 = [[_]*8]*5 + [[_]*7 + [9.20], [_, _, 11.77, _, 11.04, 7.97, 11.66, _], [17.04, 11.67, _, _, OVR, OVR, _, _],
                   [18.16, 20.67, _, _, 20.17, OVR, _, _]]
T68 = [[_]*8]*5 + [[_]*7 + [5.31], [_, _, 6.59, _, 6.59, 9.74, 6.01, _], [_, 6.42] + [_]*6, [_]*8]
T69 = [[_]*8]*5 + [[_]*7 + [105.69], [_, _, 66.34, _, 82.00, _, 99.19, _], [_, 61.27] + [_]*6, [_]*8]


# the thesis's number (section 6.1) of each criterion's metric, to name what a design failed
NUMBER = {"max_heel_deg": "1", "draft_m": "3", "min_rim_freeboard_m": "4", "max_offset_of_depth_pct": "5",
          "max_pitch_deg": "6"}


def load(out, phase, criteria=()):
    """(the phase's study dict, {(alpha, D_max): variant row}); ``criteria`` judge a running phase."""
    p = pathlib.Path(out) / phase / "study.json"
    if not p.parent.is_dir():
        return {"busy": "(not run)"}, {}
    if not p.exists():  # the phase is still running: its finished designs, metrics from their run files
        from pice.study.metrics import run_metrics
        by = {}
        for rec in sorted((pathlib.Path(out) / phase).glob("*.outcome.json")):
            v = json.loads(rec.read_text())
            if not v.get("error"):
                v["metrics"] = run_metrics(v["run"])
                v["passed"], v["failed"] = judge(criteria, v["metrics"])
            vals = v["values"]
            by[(vals["bodies[0].hull.alpha"], vals["bodies[0].hull.d_max"])] = v
        return {"busy": "(the phase is still running)"}, by
    s = json.loads(p.read_text(encoding="utf-8"))
    by = {}
    for v in s["variants"]:
        vals = v["values"]
        by[(vals["bodies[0].hull.alpha"], vals["bodies[0].hull.d_max"])] = v
    return s, by


def cell(v, metric, fmt, ours_ok, thesis):
    t = "-" if thesis is None else (thesis if isinstance(thesis, str) else f"{thesis:.2f}")
    if v is None:
        return f"- ({t})"
    if v.get("error"):
        return f"failed ({t})"
    m = v["metrics"]
    x = m.get(metric)
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return f"? ({t})"
    s = fmt.format(x / 1000.0 if metric == "mass" else x)
    if m.get("max_heel", 0.0) >= 90.0:
        s = "overturned"
    return (f"**{s}**" if ours_ok(v) else s) + f" ({t})"


def grid(title, by, metric, fmt, ok, thesis):
    lines = [f"#### {title}", "", "| alpha \\ D_max [m] | " + " | ".join(f"{d:g}" for d in D) + " |",
             "|---|" + "---|" * len(D)]
    for i, a in enumerate(A):
        row = [cell(by.get((a, d)), metric, fmt, ok, thesis[i][j]) for j, d in enumerate(D)]
        lines.append(f"| {a:g} | " + " | ".join(row) + " |")
    return lines + [""]


def thesis_normal(i, j):
    """The thesis's phase-2 verdict of design (alpha row i, D_max column j): criteria (1), (4), (5)."""
    pitch, crit, off = T65[i][j], T64[i][j], T66[i][j]
    if pitch is None:
        return "3"
    if pitch == OVR:
        return "1"
    if crit is None or pitch > crit:
        return "4"
    if off is None or off > 4.5:
        return "5"
    return "ok"


def ours(v):
    """Our verdict: **ok**, or the thesis's numbers of the criteria failed (None: not run)."""
    if v is None:
        return None
    if v.get("error"):
        return "error"
    return "**ok**" if v["passed"] else ",".join(NUMBER.get(f.split()[0], f) for f in v["failed"])


def verdict_grid(by, draft):
    lines = ["#### Normal ice: the verdict, ours / the thesis's (Tables 6-4 to 6-6): ok, or the criteria failed", "",
             "| alpha \\ D_max [m] | " + " | ".join(f"{d:g}" for d in D) + " |", "|---|" + "---|" * len(D)]
    for i, a in enumerate(A):
        row = []
        for j, d in enumerate(D):
            o, t = ours(by.get((a, d))), thesis_normal(i, j)
            dv = draft.get((a, d))
            if o is None and dv is not None and not dv.get("passed"):
                o = "sinks" if dv.get("error") else "3"
            row.append(f"{o or 'not run'} / {'**ok**' if t == 'ok' else (t or '-')}" if (o or t) else "")
        lines.append(f"| {a:g} | " + " | ".join(row) + " |")
    return lines + [""]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("sweep", nargs="?", default="jobs/cai_2018_buoy_sweep.toml")
    parser.add_argument("--out", help="the sweep's folder (default: the sweep file's out)")
    parser.add_argument("--extreme-also", nargs="*", default=[], metavar="DIR",
                        help="folders of extreme-phase studies whose designs join the extreme grids")
    args = parser.parse_args(argv)
    sweep = load_sweep(args.sweep)
    out = pathlib.Path(args.out or pathlib.Path(args.sweep).parent / sweep.out)
    criteria = {ph.name: [parse_criterion(t) for t in ph.criteria] for ph in sweep.phases}
    lines = []
    sn, normal = load(out, "normal", criteria.get("normal", ()))
    se, extreme = load(out, "extreme", criteria.get("extreme", ()))
    busy = [f"{out}: {se.get('busy')}"]
    for other in args.extreme_also:
        if not (pathlib.Path(other) / "extreme").is_dir():
            parser.error(f"--extreme-also {other}: no extreme/ folder in it; give the --out of a study whose "
                         "sweep file has a phase named extreme")
        so, more = load(other, "extreme", criteria.get("extreme", ()))
        extreme.update(more)
        busy.append(f"{other}: {so.get('busy')}")
    passed = lambda v: bool(v.get("passed"))  # noqa: E731
    rim_ok = lambda v: v["metrics"]["min_rim_freeboard"] > 0  # noqa: E731
    if normal:
        lines += grid("Normal ice: lowest rim freeboard [m] (thesis: critical pitch, Table 6-4)", normal,
                      "min_rim_freeboard", "{:.2f}", rim_ok, T64)
        lines += grid("Normal ice: maximum pitch [deg] (Table 6-5)", normal, "max_pitch", "{:.2f}", rim_ok, T65)
        lines += grid("Normal ice: maximum horizontal offset [m] (Table 6-6; limit 4.5 m)", normal, "max_offset",
                      "{:.2f}", passed, T66)
        lines += verdict_grid(normal, load(out, "draft")[1])
        lines.append(f"normal: {sum(map(passed, normal.values()))} of {len(normal)} passed; busy {sn.get('busy')}")
    if extreme:
        lines += grid("Extreme ice: maximum pitch [deg] (Table 6-7; limit 15 deg)", extreme, "max_pitch", "{:.2f}",
                      lambda v: v["metrics"]["max_pitch"] <= 15, T67)
        lines += grid("Extreme ice: maximum horizontal offset [m] (Table 6-8; limit 7.5 m)", extreme, "max_offset",
                      "{:.2f}", passed, T68)
        lines += grid("Mass of the designs kept [t] (Table 6-9)", {k: v for k, v in extreme.items() if passed(v)},
                      "mass", "{:.2f}", passed, T69)
        lines.append(f"extreme: {sum(map(passed, extreme.values()))} of {len(extreme)} passed; busy " + "; ".join(busy))
    print("\n".join(lines) if lines else f"{out}: no phase past the draft has a finished design yet")
    return 0


if __name__ == "__main__":
    sys.exit(main())
