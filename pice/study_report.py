"""What a study (pice/study.py) reports: the metrics of each run file, their change against the
reference variant, and the printed table, ``study.csv``, ``study.json`` and ``study.png``.

Metrics, from the run file's /series, for body 0 (for the sum over the walls when the job has no
bodies):

* ``peak_load_x`` [N]: the largest ice load Fx, ``peak_load_z`` [N]: the largest |Fz|, over the
  extremes between series rows (``ice_force_max``, ``ice_force_min``) and the rows (``ice_force``);
* ``mean_offset``, ``max_offset`` [m]: horizontal distance of the body's centre from its position
  in the first row, over the rows with t >= ``settle``;
* ``max_fairlead_tension`` [N]: over every line and row, of ``fairlead_tension_max`` (the peaks
  between rows) where recorded, else of ``fairlead_tension``.

Change against the reference: 100 (v - v_ref) / |v_ref| [%]. Values are in SI units in the CSV and
JSON (N, m, s); the table shows forces in kN. A metric a run does not have (no body: offsets and
tensions) is NaN in the CSV and null in the JSON; the table leaves out a metric no variant has.
"""

from __future__ import annotations

import csv
import json
import math
import pathlib

import numpy as np

#: (name, unit, label) of every metric, in the order of the table, the CSV and the figure
METRICS = (("peak_load_x", "N", "peak ice load Fx"), ("peak_load_z", "N", "peak ice load |Fz|"),
           ("mean_offset", "m", "mean offset"), ("max_offset", "m", "max offset"),
           ("max_fairlead_tension", "N", "max fairlead tension"))

_TABLE_SCALE = {"N": (1e3, "kN"), "m": (1.0, "m")}


def show_value(value) -> str:
    """A value for tables and labels: 0.0001, auto, true, [1.0, 0.0]."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return f"{value:g}"
    if isinstance(value, list):
        return "[" + ", ".join(show_value(v) for v in value) + "]"
    return str(value)


def run_metrics(path, *, settle: float = 0.0) -> dict[str, float]:
    """The metrics of one run file (module docstring): SI units, NaN where the run has no such series.

    ``settle`` [s]: the offsets are taken over the rows with t >= settle."""
    import h5py

    nan = float("nan")
    out = dict.fromkeys((m[0] for m in METRICS), nan)
    with h5py.File(path, "r") as f:
        s = f["series"]

        def get(name):
            return s[name][()] if name in s else None

        time = get("time")
        position = get("body_position")
        if position is not None and position.shape[1] > 0:
            force = get("ice_force")
            hi = [a[:, 0] for a in (get("ice_force_max"), force) if a is not None]
            lo = [a[:, 0] for a in (get("ice_force_min"), force) if a is not None]
            tension = get("fairlead_tension_max")
            tension = tension if tension is not None else get("fairlead_tension")
        else:
            walls = get("wall_force")
            hi = lo = [walls.sum(axis=1)] if walls is not None and walls.shape[1] > 0 else []
            tension = None
        if hi and all(a.size for a in hi):
            out["peak_load_x"] = float(max(a[:, 0].max() for a in hi))
            out["peak_load_z"] = float(max(np.abs(a[:, 2]).max() for a in hi + lo))
        if position is not None and position.shape[1] > 0 and len(position):
            xy = position[:, 0, :2]
            offset = np.linalg.norm(xy - xy[0], axis=1)[time >= settle]
            if offset.size:
                out["mean_offset"], out["max_offset"] = float(offset.mean()), float(offset.max())
        if tension is not None and tension.size:
            out["max_fairlead_tension"] = float(tension.max())
    return out


def change_percent(value: float, reference: float) -> float:
    """100 (value - reference) / |reference| [%]; 0 when both are 0, NaN when undefined."""
    if math.isnan(value) or math.isnan(reference):
        return float("nan")
    if reference == 0.0:
        return 0.0 if value == 0.0 else float("nan")
    return 100.0 * (value - reference) / abs(reference)


def compare(rows: list[dict], reference: int | None = None) -> int:
    """Add each row's ``change_pct`` against the reference row (default: the most particle-steps,
    the first of equals); return the reference's index."""
    ref = reference if reference is not None else max(range(len(rows)), key=lambda k: rows[k]["particle_steps"])
    for row in rows:
        row["change_pct"] = {name: change_percent(row["metrics"][name], rows[ref]["metrics"][name])
                             for name, _, _ in METRICS}
    return ref


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
        body.append(cells)
    widths = [max(len(r[i]) for r in [head, *body]) for i in range(len(head))]
    lines = ["  ".join(c.rjust(w) for c, w in zip(r, widths)) for r in [head, *body]]
    rule = "reference" if study["reference_rule"] == "--reference" else "reference, the most particle-steps"
    settle = f"; offsets over t >= {study['settle']:g} s" if study["settle"] else ""
    title = f"pice study of {study['job']}: {len(body)} variant(s), * = {rule}; loads on {study['loads_on']}"
    rows = study["variants"]
    tied = [r["variant"] for r in rows if r["particle_steps"] == rows[ref]["particle_steps"]]
    note = []
    if study["reference_rule"] != "--reference" and len(tied) > 1:
        note = [f"note: variants {', '.join(map(str, tied))} cost the same particle-steps: the first is the "
                "reference; --reference K picks another"]
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
    from postproc.study_plot import plot_study

    out_dir = pathlib.Path(out_dir)
    rows = csv_rows(study)
    with open(out_dir / "study.csv", "w", newline="", encoding="utf-8") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    (out_dir / "study.json").write_text(json.dumps(_json_safe(study), indent=2) + "\n", encoding="utf-8")
    return [out_dir / "study.csv", out_dir / "study.json", plot_study(study, out_dir / "study.png")]
