"""The mooring load of a run and its analysis as seed 003 reports it: the time series of the total
horizontal force of the lines, its power spectrum (Fig. 12) and the maximum load of each ice
interaction event (Fig. 10). Numbers only; postproc/plots.py draws them (``mooring_load.png``).

* The mooring load is |F_h| of the lines' total pull on a body (series ``mooring_force``), the ice
  load |F_h| of the ice's (``ice_force``), both [N]. With a baseline run (the scene without ice),
  the mooring load is the ice-induced one: the difference of the two pulls (``ice_induced``).
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


def ice_induced(run, baseline, name: str = "mooring_force", body: int = 0):
    """(t [s], |F_h - F_h,baseline| [N]): the horizontal force vector of series ``name`` less that of a
    ``baseline`` run of the same scene without the ice (its current and waves alone), interpolated to
    the run's times. Seed 003 shows its mooring loads so ("the direct current and wave loads have been
    excluded"); the difference is the ice's share only as far as the loads superpose (the mooring
    stiffens with offset, and the hull meets the waves where the ice has pushed it). None when either
    run lacks the series."""
    t, f = run.series("time"), run.series(name)
    tb, fb = baseline.series("time"), baseline.series(name)
    if t is None or f is None or tb is None or fb is None or f.shape[1] <= body or fb.shape[1] <= body:
        return None
    dx = f[:, body, 0] - np.interp(t, tb, fb[:, body, 0])
    dy = f[:, body, 1] - np.interp(t, tb, fb[:, body, 1])
    return t, np.hypot(dx, dy)


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


def write_events(events: list[dict], path) -> None:
    keys = list(events[0])
    lines = [",".join(f"{k}{' [s]' if k in ('start', 'end') else ' [N]'}" for k in keys)]
    lines += [",".join(f"{e[k]:.6g}" for k in keys) for e in events]
    path.write_text("\n".join(lines) + "\n")
