"""A sweep file (`pice study SWEEP.toml`, study/sweep.py): designs through phases, each phase running
only the designs that passed every phase before it, and the selected design (issue 16: the phases of
Cai 2018 chapter 6, whose objective is the weight).

Reference: the rules of the sweep themselves. Three barge designs of known mass (1, 2 and 3 kt; the
moored barge of tests/scenes.py, 0.01 s each): a first phase keeps mass < 2.5 kt, so the second
phase runs designs 0 and 1 only, and the least mass of those passing both is design 0. A second call
runs nothing (every design's outcome is recorded). Bad sweep files are one line, exit status 2,
nothing run.
"""

from __future__ import annotations

import csv
import json

import pytest
from scenes import BARGE_SWEEP as SWEEP
from scenes import barge_job

from pice.cli import main


def _files(tmp_path, sweep=SWEEP):
    (tmp_path / "barge.toml").write_text(barge_job(duration=0.01, mooring="dem"))
    path = tmp_path / "sweep.toml"
    path.write_text(sweep)
    return path


def test_phases_run_the_designs_that_passed_and_the_lightest_is_selected(tmp_path, capsys, monkeypatch):
    path = _files(tmp_path)
    out = tmp_path / "out"
    assert main(["study", str(path), "--out", str(out)]) == 0
    captured = capsys.readouterr()
    printed = captured.out
    # each variant's progress line names the designs' key, not the values every design shares
    lines = [x for x in captured.err.splitlines() if x.startswith("pice study: variant")]
    assert lines and all("bodies[0].mass = " in x and "run.snapshots" not in x for x in lines), lines
    assert "selected (least mass_kg): bodies[0].mass = 1e+06: 1e+06" in printed
    assert "2 of 3 design(s) passed every phase" in printed
    # the second phase ran designs 0 and 1 only, each as a variant numbered in the full product
    assert sorted(p.name for p in (out / "upright").glob("*.h5")) == ["barge_0.h5", "barge_1.h5"]
    assert len(list((out / "light").glob("barge_?.h5"))) == 3
    with open(out / "sweep.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert [r["light"] for r in rows] == ["pass", "pass", "fail: mass_kg < 2.5e+06"]
    assert [r["upright"] for r in rows] == ["pass", "pass", "not run"]
    assert [r["passed"] for r in rows] == ["True", "True", "False"]
    summary = json.loads((out / "sweep.json").read_text())
    assert summary["selected"]["bodies[0].mass"] == 1.0e6 and summary["selected"]["mass_kg"] == 1.0e6

    import pice.runner

    def no_run(*args, **kwargs):
        raise AssertionError("a finished design was run again")

    monkeypatch.setattr(pice.runner, "run_job", no_run)  # a second call: every outcome is on disk
    assert main(["study", str(path), "--out", str(out)]) == 0
    assert "selected (least mass_kg): bodies[0].mass = 1e+06" in capsys.readouterr().out


@pytest.mark.parametrize("edit, args, why", [
    (("minimize = \"mass_kg\"", "minimize = \"weight\""), [], "no metric 'weight'"),
    (("name = \"light\"", "name = \"upright\""), [], "phase names must differ"),
    (("criteria = [\"mass_kg < 2.5e6\"]", "criteria = [\"mass < 2.5e6\"]"), [], "no metric 'mass'"),
    (("\"run.snapshots\" = 2", "\"run.snapshot\" = 2"), [], "unknown key 'snapshot'"),
    (("set = {\"run.duration\" = 0.02}", "set = {\"run.snapshots\" = 3}"), [], "run.snapshots is given twice"),
    (("", ""), ["--vary", "run.dt=1e-4"], "a sweep file sets its own designs"),
    (("minimize = \"mass_kg\"", "minimize = \"mass_kg\"\ngrop_size = 1"), [], "study.grop_size = 1: unknown key"),
])
def test_bad_sweep_is_one_line_exit_2_and_nothing_runs(tmp_path, capsys, edit, args, why):
    path = _files(tmp_path, SWEEP.replace(*edit))
    out = tmp_path / "never"
    assert main(["study", str(path), "--out", str(out), *args]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and why in err[0], err
    assert not out.exists()
