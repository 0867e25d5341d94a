"""What a study (pice/study/) reports: the printed table, ``study.csv``, ``study.json`` and
``study.png`` (study/plot.py), from the study dict of study/runner.py with each variant's metrics
and their change against the reference (study/metrics.py).

Values are in SI units in the CSV and JSON (N, m, s, J); the table shows forces in kN and work in kJ. A metric a run
does not have (no body: offsets and tensions) is NaN in the CSV and null in the JSON; the table
leaves out a metric no variant has.
"""

from __future__ import annotations

import csv
import json
import math
import pathlib

from .metrics import METRICS
from .plot import plot_study
from .variants import show_value

_TABLE_SCALE = {"N": (1e3, "kN"), "m": (1.0, "m"), "deg": (1.0, "deg"), "pct": (1.0, "%"), "kg": (1e3, "t"),
                "J": (1e3, "kJ")}


def study_table(study: dict) -> list[str]:
    """The printed table: one line per variant, the reference marked with ``*``."""
    ref, keys = study["reference"], study["varied"]
    shown = [m for m in METRICS if not all(math.isnan(r["metrics"][m[0]]) for r in study["variants"])]
    head = ["variant", *keys, "wall [s]", "particle-steps"]
    for name, unit, label in shown:
        head.append(f"{label} [{_TABLE_SCALE[unit][1]}] (change)")
    body = []
    for row in study["variants"]:
        cells = [f"{row['variant']}{'*' if row['variant'] == ref else ''}",
                 *(show_value(row["values"][k]) for k in keys), f"{row['wall_time']:.3g}", f"{row['particle_steps']:,}"]
        for name, unit, _ in shown:
            value, change = row["metrics"][name], row["change_pct"][name]
            if math.isnan(value):
                cells.append("n/a")
                continue
            text = f"{value / _TABLE_SCALE[unit][0]:.4g}"
            cells.append(f"{text} (ref)" if row["variant"] == ref else
                         f"{text} ({'n/a' if math.isnan(change) else f'{change:+.2f}%'})")
        if any(r.get("error") for r in study["variants"]):
            cells.append(f"failed: {row['error']}" if row.get("error") else "ok")
        if study.get("criteria"):
            cells.append("pass" if row["passed"] else "fail: " + "; ".join(row["failed"]))
        body.append(cells)
    if any(r.get("error") for r in study["variants"]):
        head.append("run")
    if study.get("criteria"):
        head.append("criteria (" + ", ".join(study["criteria"]) + ")")
    widths = [max(len(r[i]) for r in [head, *body]) for i in range(len(head))]
    lines = ["  ".join(c.rjust(w) for c, w in zip(r, widths)) for r in [head, *body]]
    rule = "reference" if study["reference_rule"] == "--reference" else "reference, the most particle-steps"
    settle = f"; offsets over t >= {study['settle']:g} s" if study["settle"] else ""
    title = f"pice study of {study['job']}: {len(body)} variant(s), * = {rule}; loads on {study['loads_on']}"
    rows = study["variants"]
    ref_steps = next(r["particle_steps"] for r in rows if r["variant"] == ref)
    tied = [r["variant"] for r in rows if r["particle_steps"] == ref_steps]
    note = []
    if study["reference_rule"] != "--reference" and len(tied) > 1:
        note = [f"note: variants {', '.join(map(str, tied))} cost the same particle-steps: the first is the "
                "reference; --reference K picks another"]
    busy = study.get("busy")
    if busy and busy["elapsed"] > 0 and any(r.get("busy_time") for r in rows):
        groups = busy["groups"]
        each = f" (group {', group '.join(f'{g}: {b:.0%}' for g, b in enumerate(groups))})" if len(groups) > 1 else ""
        note.append(f"ranks busy {busy['overall']:.0%} of the {busy['elapsed']:,.0f} s this call ran variants{each}")
    return [title + settle, *lines, *note]


def csv_rows(study: dict) -> list[dict]:
    """One flat dict per variant: the CSV's columns (SI units in the names)."""
    out = []
    for row in study["variants"]:
        flat = {"variant": row["variant"], "reference": int(row["variant"] == study["reference"])}
        flat.update({k: show_value(row["values"][k]) for k in study["varied"]})
        flat.update(wall_time_s=row["wall_time"], steps=row["steps"], elements=row["elements"],
                    particle_steps=row["particle_steps"])
        for name, unit, _ in METRICS:
            flat[f"{name}_{unit}"] = row["metrics"][name]
            flat[f"{name}_change_pct"] = row["change_pct"][name]
        flat["error"] = row.get("error") or ""
        if study.get("criteria"):
            flat["passed"] = int(row["passed"])
            flat["failed"] = "; ".join(row["failed"])
        out.append(flat)
    return out


def _json_safe(value):
    """NaN and inf -> None (JSON has no such numbers)."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {k: _json_safe(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_json_safe(v) for v in value]
    return value


def write_report(study: dict, out_dir) -> list[pathlib.Path]:
    """Write study.csv, study.json and study.png into ``out_dir``; return their paths."""
    out_dir = pathlib.Path(out_dir)
    rows = csv_rows(study)
    with open(out_dir / "study.csv", "w", newline="", encoding="utf-8") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    (out_dir / "study.json").write_text(json.dumps(_json_safe(study), indent=2) + "\n", encoding="utf-8")
    return [out_dir / "study.csv", out_dir / "study.json", plot_study(study, out_dir / "study.png")]
