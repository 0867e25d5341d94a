"""Time-history figures of a run file (PNG, matplotlib's Agg backend, so no display is needed).

``plot_run("runs/x.h5", "runs/x_plots")`` writes one PNG per figure whose series the run holds:

* ``ice_loads.png``: force of the ice on each wall (Fx, Fy, Fz and |F|, kN) against time, and their
  sum when there are several walls;
* ``platform.png``: per body, the ice load (with its range between series rows), the offset and
  rotation from t = 0, and every fairlead tension (MN);
* ``mooring_load.png`` (with ``events.csv``): the lines' total horizontal pull against time, its power
  spectrum and the peak load of each ice interaction event, as seed 003's Figs. 10-12
  (postproc/mooring.py);
* ``keel_resistance.png``: a ship run through a [keel]: R = -f_x against the penetration, its 6 m
  running average and peak R^p, as seed 002's Fig. 5, and the water's drag on the rubble, the part of
  R that moves it through the water, and the part on each piece of a ship's hull (its bow and
  midbody: postproc/resistance.py);
* ``energies.png``: the change of each energy since t = 0 (kJ);
* ``broken_bonds.png``: cumulative broken bonds against time, by failure mode (from the event log).

A figure whose series are absent is skipped. Every figure is ``FIGSIZE`` at ``DPI``
(1000 x 700 pixels).
"""

from __future__ import annotations

import os
import pathlib

import numpy as np

from ..io.errors import OutputError
from ..io.run_reader import open_run
from ..kernels.bonds import FAILURE_MODES

FIGSIZE = (10.0, 7.0)  # inches
DPI = 100
MAX_WALL_PANELS = 6    # more walls than this: only their sum is drawn


def _figure(nrows: int = 1):
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(nrows, 1, figsize=FIGSIZE, dpi=DPI, sharex=True, squeeze=False)
    return fig, axes[:, 0]


def _save(fig, path: pathlib.Path) -> pathlib.Path:
    import matplotlib.pyplot as plt

    fig.savefig(path, dpi=DPI)  # no bbox_inches="tight": the pixel size stays FIGSIZE x DPI
    plt.close(fig)
    return path


def _title(run) -> str:
    src = run.attrs.get("job_source", "")
    return f"{pathlib.Path(str(src)).stem or run.path.stem}  ({run.path.name})"


def ice_loads(run, out: pathlib.Path, **_):
    t, f = run.series("time"), run.series("wall_force")
    if t is None or f is None or f.shape[1] == 0:
        return None
    f = f / 1e3  # (rows, walls, 3) kN
    names = run.wall_names() or [f"wall{k}" for k in range(f.shape[1])]
    panels = [(f"ice load on {names[k]}", f[:, k]) for k in range(f.shape[1])] if f.shape[1] <= MAX_WALL_PANELS else []
    if f.shape[1] > 1:
        panels.append((f"ice load on all {f.shape[1]} walls (sum)", f.sum(axis=1)))
    fig, axes = _figure(len(panels))
    for ax, (label, fk) in zip(axes, panels):
        for c, comp in enumerate("xyz"):
            ax.plot(t, fk[:, c], lw=1.2, label=f"F{comp}")
        ax.plot(t, np.linalg.norm(fk, axis=1), "k--", lw=0.8, label="|F|")
        ax.set_ylabel("force [kN]")
        ax.set_title(label, fontsize=10)
        ax.grid(alpha=0.3)
        ax.legend(loc="upper left", fontsize=8, ncol=4)
    axes[-1].set_xlabel("t [s]")
    fig.suptitle(f"Ice loads: {_title(run)}", fontsize=11)
    fig.tight_layout()
    return _save(fig, out / "ice_loads.png")


def energies(run, out: pathlib.Path, **_):
    names = [k for k in run.series_names() if k.endswith("_energy")]
    t = run.series("time")
    if not names or t is None:
        return None
    fig, (ax,) = _figure(1)
    for name in names:
        e = run.series(name)
        style = dict(color="k", lw=2.0) if name == "total_energy" else dict(lw=1.2)
        ax.plot(t, (e - e[0]) / 1e3, label=name.replace("_energy", ""), **style)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("E(t) - E(0) [kJ]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, ncol=2)
    ax.set_title(f"Energies: {_title(run)}", fontsize=11)
    fig.tight_layout()
    return _save(fig, out / "energies.png")


def broken_bonds(run, out: pathlib.Path, **_):
    t, broken = run.series("time"), run.series("broken_bonds")
    if t is None or broken is None:
        return None
    fig, (ax,) = _figure(1)
    ev = run.broken_bonds()
    t_end = float(t[-1]) if len(t) else 0.0
    if len(ev):
        ev = ev[np.argsort(ev[:, 1], kind="stable")]
        modes = [(label, ev[:, 4] == mode) for mode, label in FAILURE_MODES.items()]
        for label, mask in [("all", np.ones(len(ev), bool)), *modes]:
            te = ev[mask, 1]
            if label != "all" and not len(te):
                continue
            ax.step(np.concatenate([[0.0], te, [t_end]]), np.concatenate([[0], np.arange(1, len(te) + 1), [len(te)]]),
                    where="post", lw=2.0 if label == "all" else 1.2, label=label)
    ax.plot(t, broken, "k.", ms=4, label="series rows")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("broken bonds (cumulative)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper left")
    ax.set_title(f"Broken bonds: {_title(run)}", fontsize=11)
    fig.tight_layout()
    return _save(fig, out / "broken_bonds.png")


def platform(run, out: pathlib.Path, **_):
    """Per body: ice load (with the peaks between rows), offset from the start, rotation, and the
    fairlead tensions (MN)."""
    t, x = run.series("time"), run.series("body_position")
    if t is None or x is None:
        return None
    tension = run.series("fairlead_tension")
    has_lines = tension is not None and tension.shape[1] > 0
    fig, axes = _figure(4 if has_lines else 3)
    f = run.series("ice_force") / 1e6
    f_max, f_min = run.series("ice_force_max"), run.series("ice_force_min")
    for k in range(f.shape[1]):
        for c, comp in enumerate("xyz"):
            line, = axes[0].plot(t, f[:, k, c], lw=1.2, label=f"body {k}: F{comp}")
            if f_max is not None:
                axes[0].fill_between(t, f_min[:, k, c] / 1e6, f_max[:, k, c] / 1e6,
                                     color=line.get_color(), alpha=0.2, lw=0)
    axes[0].set_ylabel("ice load [MN]")
    axes[0].set_title("ice load on the hull (shaded: range between series rows)", fontsize=10)
    for k in range(x.shape[1]):
        for c, comp in enumerate(("surge", "sway", "heave")):
            axes[1].plot(t, x[:, k, c] - x[0, k, c], lw=1.2, label=f"body {k}: {comp}")
    axes[1].set_ylabel("offset from t = 0 [m]")
    r = np.degrees(run.series("body_rotation"))
    for k in range(r.shape[1]):
        for c, comp in enumerate(("roll", "pitch", "yaw")):
            axes[2].plot(t, r[:, k, c], lw=1.2, label=f"body {k}: {comp}")
    axes[2].set_ylabel("rotation [deg]")
    if has_lines:
        ft = tension / 1e6
        for j in range(ft.shape[1]):
            axes[3].plot(t, ft[:, j], lw=0.8, label=f"line {j}" if ft.shape[1] <= 12 else None)
        axes[3].set_ylabel("fairlead tension [MN]")
    for ax in axes:
        ax.grid(alpha=0.3)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(loc="upper left", fontsize=7, ncol=6)
    axes[-1].set_xlabel("t [s]")
    fig.suptitle(f"Moored platform: {_title(run)}", fontsize=11)
    fig.tight_layout()
    return _save(fig, out / "platform.png")


def mooring_load(run, out: pathlib.Path, skip: float = 0.0, baseline=None, **_):
    """mooring_load.png: the mooring and ice loads against time, the mooring load's spectrum, and the
    peak loads of each ice interaction event (postproc/mooring.py); events.csv beside it. With a
    ``baseline`` run (open, the scene without ice), the mooring load less the baseline's: the
    ice-induced load. None without mooring lines."""
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    from .mooring import EVENT_THRESHOLD, horizontal, ice_induced, interaction_events, load_spectrum, write_events

    moor, ice = horizontal(run, "mooring_force"), horizontal(run, "ice_force")
    if moor is None or not np.any(moor[1]):
        return None
    label = "mooring load |F_h|"
    if baseline is not None:
        moor = ice_induced(run, baseline) or moor
        label = f"ice-induced mooring load |F_h - F_h of {baseline.path.parent.name}/{baseline.path.name}|"
    t, m = moor
    fig, axes = plt.subplots(3, 1, figsize=FIGSIZE, dpi=DPI)  # the spectrum has its own x axis
    axes[0].plot(t, m / 1e6, lw=1.0, label=label)
    if ice is not None:
        axes[0].plot(t, ice[1] / 1e6, lw=0.6, alpha=0.7, label="ice load |F_h|")
    axes[0].axvline(skip, color="k", lw=0.6, ls=":")
    axes[0].set_ylabel("load [MN]")
    axes[0].set_xlabel("t [s]")
    spectrum = load_spectrum(t, m, skip)
    if spectrum is not None:
        f, psd = spectrum
        axes[1].loglog(f[1:], psd[1:] / 1e12, lw=1.0)
        axes[1].set_xlabel("frequency [Hz]")
    axes[1].set_ylabel("PSD [MN^2 s]")
    axes[1].set_title(f"power spectrum of the mooring load after t = {skip:g} s (Welch)", fontsize=10)
    events = interaction_events(t, ice[1], m, skip=skip) if ice is not None else []
    if events:
        mid = [0.5 * (e["start"] + e["end"]) for e in events]
        axes[2].plot(mid, [e["mooring_max"] / 1e6 for e in events], "o", label="mooring load")
        axes[2].plot(mid, [e["ice_max"] / 1e6 for e in events], "x", label="ice load")
        write_events(events, out / "events.csv")
    axes[2].set_ylabel("peak per event [MN]")
    axes[2].set_xlabel("t [s] (middle of the event)")
    axes[2].set_title(f"{len(events)} ice interaction events (ice load above {EVENT_THRESHOLD:.0%} of its peak)",
                      fontsize=10)
    for ax in axes:
        ax.grid(alpha=0.3)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(loc="upper left", fontsize=8)
    fig.suptitle(f"Mooring load: {_title(run)}", fontsize=11)
    fig.tight_layout()
    return _save(fig, out / "mooring_load.png")


def keel_resistance(run, out: pathlib.Path, **_):
    """keel_resistance.png: a ship run through a [keel]: R = -f_x against the penetration, its running
    average over 6 m and the peak R^p (seed 002, Fig. 5; postproc/resistance.py). None otherwise."""
    from .resistance import (WINDOW, keel_record, malmberg_for_job, peak_resistance, piece_resistance_record,
                             running_average, water_drag_record)

    record = keel_record(run)
    if record is None:
        return None
    delta, r = record
    fig, axes = _figure(1)
    ax = axes[0]
    ax.plot(delta, r / 1e3, lw=0.6, alpha=0.6, label="R = -f_x")
    ax.plot(delta, running_average(delta, r) / 1e3, lw=1.6, label=f"{WINDOW:g} m running average")
    peak, where = peak_resistance(delta, r)
    if np.isfinite(peak):
        ax.plot([where], [peak / 1e3], "o", label=f"R^p = {peak / 1e3:,.0f} kN at {where:.1f} m")
    drag = water_drag_record(run)
    if drag is not None:  # the part of R that moves the rubble through the water (postproc/resistance.py)
        ax.plot(drag[0], running_average(*drag) / 1e3, "--", lw=1.2,
                label=f"the water's drag on the rubble along -x, {WINDOW:g} m average")
    pieces = piece_resistance_record(run)
    if pieces is not None:  # where on the hull R acts: a ship's bow and midbody (Malmberg's two terms)
        d, rp, names = pieces
        for k, name in enumerate(names):
            ok = np.isfinite(rp[:, k])
            if ok.any() and np.any(rp[ok, k] != 0.0):
                ax.plot(d[ok], running_average(d[ok], rp[ok, k]) / 1e3, ":", lw=1.2,
                        label=f"on the {name}, {WINDOW:g} m average")
    malmberg = malmberg_for_job(run.job)
    if malmberg is not None:  # the analytic reference (seed 002, Eqs. 1-2), for a keel wider than the bow
        half = " / 2 (half hull)" if run.job.bodies[0].hull.half else ""
        ax.axhline(malmberg.total / 1e3, color="0.4", ls="-.", lw=1.0,
                   label=f"Malmberg's R_A{half} = {malmberg.total / 1e3:,.0f} kN (phi 40 deg, p 0.3)")
    ax.set_xlabel("penetration delta [m]")
    ax.set_ylabel("keel resistance [kN]")
    ax.grid(alpha=0.3)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.1), ncol=2, fontsize=8)  # below: clear of the peak
    fig.suptitle(f"Keel resistance: {_title(run)}", fontsize=11)
    fig.tight_layout()
    return _save(fig, out / "keel_resistance.png")


# each figure: builder(run, out_dir, skip=...) -> path or None when the run lacks its series
FIGURES = (ice_loads, platform, mooring_load, keel_resistance, energies, broken_bonds)


def default_out_dir(run_path) -> pathlib.Path:
    p = pathlib.Path(run_path)
    return p.with_name(p.stem + "_plots")


def plot_run(run_path: str | os.PathLike, out_dir: str | os.PathLike | None = None, *,
             skip: float = 0.0, baseline: str | os.PathLike | None = None) -> list[pathlib.Path]:
    """Write the PNG figures of a run into ``out_dir`` (default ``<run>_plots/``); return their paths.
    ``skip`` [s]: the start left out of the mooring load's spectrum and events (postproc/mooring.py);
    ``baseline``: a run of the scene without ice, whose mooring load is subtracted."""
    import contextlib

    out = pathlib.Path(out_dir) if out_dir is not None else default_out_dir(run_path)
    written = []
    with open_run(run_path) as run, (open_run(baseline) if baseline else contextlib.nullcontext()) as base:
        try:
            out.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise OutputError(f"{out}: cannot create the output folder ({exc.strerror or exc})") from None
        for figure in FIGURES:
            try:
                path = figure(run, out, skip=skip, baseline=base)
            except OSError as exc:
                raise OutputError(f"{out}: cannot write {figure.__name__} ({exc.strerror or exc})") from None
            if path is not None:
                written.append(path)
    return written
