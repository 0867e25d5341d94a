"""The criteria of seed 004 section 6.1 as study metrics (pice/study/hull_metrics.py), computed on a
hand-made run file of the pre-designed buoy whose answers follow from its geometry by hand."""

from __future__ import annotations

import math
import pathlib

import h5py
import numpy as np
import pytest
from scenes import job_from_text

from pice.study.metrics import run_metrics


def test_buoy_criteria_metrics_of_a_hand_made_run(tmp_path):
    """Cai's criteria (study/hull_metrics.py) on the pre-designed buoy (jobs/cai_2018_buoy.toml: the widest
    ring r = 4.5 m at h = 2.5 - 1.83426 m above the centre, the keel ring r = 2.5 m at -1.83426 m) in
    three rows: at rest at z0; at t = 1 s 3 m and 4 m off and pitched 10 deg; at t = 2 s rolled 100 deg."""
    from pice.platform.build import hull_mesh

    text = (pathlib.Path(__file__).resolve().parents[2] / "jobs" / "cai_2018_buoy.toml").read_text()
    vertices = hull_mesh(job_from_text(text), 0)[0]
    z0, zg = -0.44366, 1.834261
    position = np.array([[[0.0, 0.0, z0]], [[3.0, 4.0, z0]], [[3.0, 4.0, z0]]])
    rotation = np.zeros((3, 1, 3))
    rotation[1, 0, 1], rotation[2, 0, 0] = math.radians(10.0), math.radians(100.0)
    with h5py.File(tmp_path / "buoy.h5", "w") as f:
        f.attrs["job_text"] = text
        f["series/time"], f["series/body_position"], f["series/body_rotation"] = np.arange(3.0), position, rotation
        f["snapshots/00000/hull0_vertices"] = vertices
    m = run_metrics(tmp_path / "buoy.h5", settle=0.5)
    assert m["max_heel"] == pytest.approx(100.0, abs=1e-9)
    assert m["draft"] == pytest.approx(zg - z0, abs=1e-5)                      # 2.278 m: the keel at rest
    # pitched 10 deg, the keel ring's vertex at x = +2.5 m is lowest: 2.5 sin 10 + 1.834 cos 10 - z0 = 2.684 m;
    # rolled 100 deg, the widest ring's vertex at y = -4.5 m: 4.5 sin 100 - 0.666 cos 100 - z0 = 4.991 m
    pitched = 2.5 * math.sin(math.radians(10.0)) + zg * math.cos(math.radians(10.0)) - z0
    rolled = 4.5 * math.sin(math.radians(100.0)) - (2.5 - zg) * math.cos(math.radians(100.0)) - z0
    assert m["min_draft"] == pytest.approx(pitched, abs=1e-5) and m["max_draft"] == pytest.approx(rolled, abs=1e-5)
    rim = [z0 + (2.5 - zg) * math.cos(a) - 4.5 * abs(math.sin(a)) for a in (0.0, math.radians(10.0),
                                                                             math.radians(100.0))]
    assert rim[0] == pytest.approx(0.2221, abs=1e-4)  # at rest the widest section is 0.22 m above the water
    assert m["min_rim_freeboard"] == pytest.approx(min(rim), abs=1e-6)  # zg to 6 decimals
    assert m["max_offset"] == 5.0 and m["max_offset_of_depth"] == pytest.approx(100.0 * 5.0 / 30.0)
    del_text = tmp_path / "bare.h5"  # no job text: no water, no criteria
    with h5py.File(del_text, "w") as f:
        f["series/time"], f["series/body_position"], f["series/body_rotation"] = np.arange(3.0), position, rotation
    bare = run_metrics(del_text)
    assert all(math.isnan(bare[k]) for k in ("max_heel", "draft", "min_rim_freeboard", "max_offset_of_depth"))
