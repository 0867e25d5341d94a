"""The mooring load of a run and its analysis as seed 003 reports it: the time series of the total
horizontal force of the lines, its power spectrum (Fig. 12) and the maximum load of each ice
interaction event (Fig. 10).

* The mooring load is |F_h| of the lines' total pull on a body (series ``mooring_force``), the ice
  load |F_h| of the ice's (``ice_force``), both [N].
* The spectrum is Welch's estimate (scipy.signal.welch, Hann windows of ``SEGMENTS``-th of the record,
  half overlapping) of the load less its mean, one-sided [N^2 s], after ``skip`` seconds (seed 003
  leaves out the first 1500 s, where the structure enters the field).
* An ice interaction event is a stretch where the ice load exceeds ``threshold`` of its largest
  value after ``skip``; stretches closer than ``gap`` seconds are one event. Its maximum mooring
  and ice loads are what Fig. 10 plots.
"""

from __future__ import annotations

import numpy as np

SEGMENTS = 8          # Welch segments per record
EVENT_THRESHOLD = 0.1  # of the largest ice load
EVENT_GAP = 10.0       # [s] quieter stretches than this do not split an event


def horizontal(run, name: str, body: int = 0):
    """(t [s], |F_h| [N]) of series ``name`` (rows, bodies, 3) for one body; None when absent."""
    t, f = run.series("time"), run.series(name)
    if t is None or f is None or f.ndim != 3 or f.shape[1] <= body:
        return None
    return t, np.hypot(f[:, body, 0], f[:, body, 1])


def load_spectrum(t: np.ndarray, load: np.ndarray, skip: float = 0.0):
    """(f [Hz], PSD [N^2 s]) of ``load`` after t >= skip (rows evenly spaced: a run's last row, which
    may fall between, is dropped); None when fewer than 16 rows remain."""
    from scipy.signal import welch

    keep = t >= skip
    t, y = t[keep], load[keep]
    if len(t) > 2 and not np.isclose(t[-1] - t[-2], t[1] - t[0], rtol=1e-6):
        t, y = t[:-1], y[:-1]
    if len(t) < 16:
        return None
    fs = 1.0 / np.mean(np.diff(t))
    return welch(y - y.mean(), fs=fs, nperseg=max(16, len(y) // SEGMENTS))


def interaction_events(t: np.ndarray, ice: np.ndarray, mooring: np.ndarray | None = None, *, skip: float = 0.0,
                       threshold: float = EVENT_THRESHOLD, gap: float = EVENT_GAP) -> list[dict]:
    """The ice interaction events after ``skip`` (module docstring): dicts of start, end [s], the peak
    ice load and, with ``mooring``, the peak mooring load [N]."""
    keep = t >= skip
    t, ice = t[keep], ice[keep]
    moor = mooring[keep] if mooring is not None else None
    if not len(t) or ice.max() <= 0.0:
        return []
    above = np.flatnonzero(ice > threshold * ice.max())
    events, start = [], 0
    for k in range(1, len(above) + 1):
        if k == len(above) or t[above[k]] - t[above[k - 1]] > gap:
            lo, hi = above[start], above[k - 1]
            e = dict(start=float(t[lo]), end=float(t[hi]), ice_max=float(ice[lo:hi + 1].max()))
            if moor is not None:
                e["mooring_max"] = float(moor[lo:hi + 1].max())
            events.append(e)
            start = k
    return events


def mooring_figure(run, out, skip: float = 0.0, **_):
    """mooring_load.png: the mooring and ice loads against time, the mooring load's spectrum, and the
    peak loads of each ice interaction event; events.csv beside it. None without mooring lines."""
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    from .plots import DPI, FIGSIZE, _save, _title

    moor, ice = horizontal(run, "mooring_force"), horizontal(run, "ice_force")
    if moor is None or not np.any(moor[1]):
        return None
    t, m = moor
    fig, axes = plt.subplots(3, 1, figsize=FIGSIZE, dpi=DPI)  # the spectrum has its own x axis
    axes[0].plot(t, m / 1e6, lw=1.0, label="mooring load |F_h|")
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
        _write_events(events, out / "events.csv")
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


def _write_events(events: list[dict], path) -> None:
    keys = list(events[0])
    lines = [",".join(f"{k}{' [s]' if k in ('start', 'end') else ' [N]'}" for k in keys)]
    lines += [",".join(f"{e[k]:.6g}" for k in keys) for e in events]
    path.write_text("\n".join(lines) + "\n")
