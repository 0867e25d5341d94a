"""The mooring-load analysis of `pice plot` (pice/postproc/mooring.py), seed 003's Figs. 10-12.

References: Welch's estimate of a sine of amplitude a and frequency f0 in noise peaks at f0 and its
integral is the sine's variance a^2 / 2 (Parseval), within 5 % (the Hann window's leakage stays in
the peak's bins, integrated over); the events of a synthetic load made of known bursts are those
bursts. A short moored Kulluk run in floes writes mooring_load.png and events.csv.
"""

from __future__ import annotations

import numpy as np
import pytest

from pice.postproc.mooring import ice_induced, interaction_events, load_spectrum


def test_spectrum_of_a_sine_peaks_at_its_frequency_and_holds_its_variance():
    rng = np.random.default_rng(0)
    t = np.arange(0.0, 4000.0, 0.5)
    a, f0 = 3.0e5, 1.0 / 64.0  # [N], [Hz]: a surge-period oscillation of the Kulluk
    load = 1.0e6 + a * np.sin(2 * np.pi * f0 * t) + 1.0e3 * rng.standard_normal(len(t))
    f, psd = load_spectrum(t, load, skip=1500.0)
    assert f[np.argmax(psd)] == pytest.approx(f0, rel=0.1)
    variance = np.sum(psd) * (f[1] - f[0])
    assert variance == pytest.approx(0.5 * a * a, rel=0.05)


def test_spectrum_needs_enough_rows():
    t = np.arange(10.0)
    assert load_spectrum(t, np.ones(10)) is None


def test_events_are_the_bursts_above_the_threshold():
    t = np.arange(0.0, 1000.0, 1.0)
    ice = np.zeros_like(t)
    bursts = [(100, 130, 2.0e6), (300, 305, 1.0e6), (311, 320, 0.5e6), (700, 760, 3.0e6)]
    for lo, hi, peak in bursts:
        ice[lo:hi + 1] = peak * np.sin(np.pi * (t[lo:hi + 1] - lo) / (hi - lo)) + 1.0
    mooring = 0.5 * ice
    events = interaction_events(t, ice, mooring, threshold=0.1, gap=10.0)
    # the two bursts 6 s apart (< gap) are one event; the others stand alone
    assert len(events) == 3
    assert [round(e["ice_max"] / 1e6, 1) for e in events] == [2.0, 1.0, 3.0]
    assert all(e["mooring_max"] == pytest.approx(0.5 * e["ice_max"]) for e in events)
    assert events[1]["start"] >= 300 and events[1]["end"] <= 320
    assert interaction_events(t, ice, mooring, skip=500.0, threshold=0.1)[0]["ice_max"] == pytest.approx(3.0e6, rel=1e-3)


class _Run:
    """The series of a run file, as postproc/mooring.py reads them."""

    def __init__(self, **series):
        self._s = series

    def series(self, name):
        return self._s.get(name)


def test_the_ice_induced_load_is_the_pull_less_the_baselines():
    """Superposition: a run's mooring pull made of a baseline's (current and a 25 s wave, sampled at
    other times) and an ice pull along y gives back |ice pull| (to the linear interpolation of the
    baseline's smooth 25 s record between its 0.5 s rows: 1e-3 of its amplitude)."""
    tb = np.arange(0.0, 600.0, 0.5)
    base = np.zeros((len(tb), 1, 3))
    base[:, 0, 0] = 6.7e4 + 1.0e6 * np.sin(2 * np.pi * tb / 25.0)
    t = np.arange(0.3, 590.0, 3.0)
    ice = 2.0e5 * (1.0 + np.cos(2 * np.pi * t / 100.0))
    run = np.zeros((len(t), 1, 3))
    run[:, 0, 0] = 6.7e4 + 1.0e6 * np.sin(2 * np.pi * t / 25.0)
    run[:, 0, 1] = ice
    got_t, got = ice_induced(_Run(time=t, mooring_force=run), _Run(time=tb, mooring_force=base))
    assert np.array_equal(got_t, t)
    np.testing.assert_allclose(got, ice, atol=1e-3 * 1.0e6)
    assert ice_induced(_Run(time=t, mooring_force=run), _Run(time=tb)) is None
