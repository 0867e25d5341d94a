"""What a study measures in each run file, and its change against the reference variant.

Metrics, from the run file's /series (read through io/run_reader.py), for body 0 (for the sum over
the walls when the job has no bodies):

* ``peak_load_x`` [N]: the largest ice load Fx, ``peak_load_z`` [N]: the largest |Fz|, over the
  extremes between series rows (``ice_force_max``, ``ice_force_min``) and the rows (``ice_force``);
* ``mean_offset``, ``max_offset`` [m]: horizontal distance of the body's centre from its position
  in the first row, over the rows with t >= ``settle``;
* ``max_fairlead_tension`` [N]: over every line and row, of ``fairlead_tension_max`` (the peaks
  between rows) where recorded, else of ``fairlead_tension``;
* ``max_pitch``, ``max_roll`` [deg]: the largest |pitch| and |roll| of the body over the rows;
* ``max_mooring_load``, ``mean_mooring_load`` [N]: the largest and the mean horizontal pull of all
  the body's lines (|F_h| of ``mooring_force``, seed 003's "mooring load") over the rows with
  t >= ``settle``;
* the design criteria of Cai (2018, seed 004, section 6.1; study/hull_metrics.py), from the body's
  pose in each row, its hull (the run's first snapshot) and the water of the job the run file keeps:
  ``max_heel`` [deg] (criterion (1), no overturning: max_heel_deg < 90), ``draft``, ``min_draft``,
  ``max_draft`` [m] (criterion (3)), ``min_rim_freeboard`` [m] (criterion (4): the upward slope
  never under water, min_rim_freeboard_m > 0) and ``max_offset_of_depth`` [%] (criteria (5), (7):
  max_offset_of_depth_pct <= 15 or 25);
* ``mass`` [kg]: body 0's mass as the run resolved it (the file's ``body_mass``; the buoy sweep's
  objective, seed 004 section 6.2.4).
* for a ship run through a [keel] (seed 002; postproc/resistance.py): ``keel_peak_resistance`` [N],
  R^p, the peak of the 6 m running average of R = -f_x against the penetration; ``keel_peak_at``
  [m], the penetration at which it peaks; ``keel_work`` [J], the work of R over the record. A study
  of ``keel.contact.friction`` then gives Table 2's rise of R^p with mu_i as the change column.
  A keel run has only these three: its ship moves as prescribed, so the offsets, attitudes, drafts
  and mass are the job's input, and its ice load is R, which they describe.

Change against the reference: 100 (v - v_ref) / |v_ref| [%]. A metric a run does not have (no
body: offsets and tensions) is NaN.
"""

from __future__ import annotations

import math

import numpy as np

from ..io.run_reader import open_run
from .hull_metrics import HULL_METRICS, hull_metrics

#: (name, unit, label) of every metric, in the order of the table, the CSV and the figure
METRICS = (("peak_load_x", "N", "peak ice load Fx"), ("peak_load_z", "N", "peak ice load |Fz|"),
           ("mean_offset", "m", "mean offset"), ("max_offset", "m", "max offset"),
           ("max_fairlead_tension", "N", "max fairlead tension"), ("max_pitch", "deg", "max |pitch|"),
           ("max_roll", "deg", "max |roll|"), ("max_mooring_load", "N", "max mooring load"),
           ("mean_mooring_load", "N", "mean mooring load"), ("mass", "kg", "mass"),
           ("keel_peak_resistance", "N", "keel R^p"), ("keel_peak_at", "m", "R^p at penetration"),
           ("keel_work", "J", "work of R"), *HULL_METRICS)


def run_metrics(path, *, settle: float = 0.0) -> dict[str, float]:
    """The metrics of one run file (module docstring): SI units, NaN where the run has no such series.

    ``settle`` [s]: the offsets are taken over the rows with t >= settle."""
    nan = float("nan")
    out = dict.fromkeys((m[0] for m in METRICS), nan)
    with open_run(path) as run:
        get = run.series
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
        mooring = get("mooring_force")
        if mooring is not None and mooring.ndim == 3 and mooring.shape[1] > 0 and np.any(mooring):
            load = np.hypot(mooring[:, 0, 0], mooring[:, 0, 1])[time >= settle]
            if load.size:
                out["max_mooring_load"], out["mean_mooring_load"] = float(load.max()), float(load.mean())
        rotation = get("body_rotation")
        if rotation is not None and rotation.shape[1] > 0 and len(rotation):
            out["max_roll"] = float(math.degrees(np.abs(rotation[:, 0, 0]).max()))
            out["max_pitch"] = float(math.degrees(np.abs(rotation[:, 0, 1]).max()))
        masses = run.attrs.get("body_mass")
        if masses is not None and len(masses):
            out["mass"] = float(masses[0])
        out.update(hull_metrics(run, settle=settle, max_offset=out["max_offset"]))
        keel = _keel_metrics(run)
        if keel:  # the ship's motion is prescribed: only R's metrics mean something (docstring)
            out = dict.fromkeys(out, nan)
            out.update(keel)
    return out


def _keel_metrics(run) -> dict[str, float]:
    """R^p [N], where it peaks [m] and the work of R [J] of a ship run through a [keel]; {} otherwise."""
    from ..postproc.resistance import keel_record, peak_resistance, resistance_work

    record = keel_record(run)
    if record is None:
        return {}
    delta, r = record
    peak, where = peak_resistance(delta, r)
    return {"keel_peak_resistance": peak, "keel_peak_at": where, "keel_work": resistance_work(delta, r)}


def change_percent(value: float, reference: float) -> float:
    """100 (value - reference) / |reference| [%]; 0 when both are 0, NaN when undefined."""
    if math.isnan(value) or math.isnan(reference):
        return float("nan")
    if reference == 0.0:
        return 0.0 if value == 0.0 else float("nan")
    return 100.0 * (value - reference) / abs(reference)


def compare(rows: list[dict], reference: int | None = None) -> int:
    """Add each row's ``change_pct`` against the reference row: variant number ``reference``, by
    default the most particle-steps (the first of equals); return the reference's variant number."""
    pos = ([r["variant"] for r in rows].index(reference) if reference is not None
           else max(range(len(rows)), key=lambda k: rows[k]["particle_steps"]))
    for row in rows:
        nan = float("nan")  # a metric a row lacks (a study written before it existed) compares as NaN
        row["change_pct"] = {name: change_percent(row["metrics"].get(name, nan), rows[pos]["metrics"].get(name, nan))
                             for name, _, _ in METRICS}
    return rows[pos]["variant"]
