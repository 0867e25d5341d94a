"""pice bench and the step's timers (pice/bench/, pice/timers.py), on tiny scenes and a few steps.

No assertion here is on speed (speed is measured by `pice bench` itself, on a quiet machine), and
none reads the real clock: the timers and the bench read a stand-in clock that advances one tick per
read, so every figure is a count of clock reads. These check the report's keys, that the timed parts
cover the measured window, that the plain step reads no clock, and that the timed step gives the
plain step's numbers bit for bit.
"""

from __future__ import annotations

import itertools
import json

import numpy as np
import pytest
import scenes
from launch import serial_only

import pice.bench.measure
import pice.timers
from pice.bench import run_bench
from pice.bench.report import report_lines
from pice.simulation import Simulation
from pice.timers import PARTS

#: the timed window read outside the step against the parts' sum: the laps follow one another, so
#: with one tick per clock read only the window's own reads fall outside the parts (the read that
#: opens it, the timers' start, the read that closes it, and any read between the last lap and
#: that close: counted 4 for the sheet and 2 for the full scene)
OUTSIDE_TICKS = 4


@pytest.fixture
def tick_clock(monkeypatch):
    """A stand-in for perf_counter in the timers and the bench: 1 ms per read; returns the reads."""
    reads = []
    ticks = itertools.count()

    def clock():
        reads.append(1)
        return 1e-3 * next(ticks)

    monkeypatch.setattr(pice.timers, "perf_counter", clock)
    monkeypatch.setattr(pice.bench.measure, "perf_counter", clock)
    return reads


def _barge(tmp_path, series_every=3):
    path = tmp_path / "barge.toml"
    path.write_text(scenes.barge_job(duration=0.05, series_every=series_every, mooring="dem"))
    return path


def test_bench_writes_the_figures_the_machine_and_a_split_that_adds_up(tmp_path, tick_clock):
    serial_only()
    out = tmp_path / "bench.json"
    result = run_bench(scene="both", steps=6, warmup=2, job=_barge(tmp_path), length=12.0, width=8.0, broken=5,
                       json_path=out)
    data = json.loads(out.read_text())
    assert {"format", "created_utc", "ranks", "machine", "software", "code", "settings", "sheet", "full"} <= set(data)
    assert data["ranks"] == 1
    assert {"cpu_model", "logical_cpus", "physical_cores", "memory_gib", "load_average_before"} <= set(data["machine"])
    assert {"python", "numpy", "numba", "mpi4py", "mpi_library"} <= set(data["software"])
    assert {"commit", "dirty"} <= set(data["code"])
    assert data["settings"]["steps"] == 6
    sheet, full = data["sheet"], data["full"]
    assert sheet["elements"] > 50 and sheet["bonds_broken_before_timing"] == 5
    assert sheet["particle_steps_per_second"] > 0 and sheet["dt"] > 0
    assert full["bodies"] == 1 and full["mooring_lines"] == 4
    assert full["projected_hours"] == pytest.approx(full["wall_s_per_simulated_s"] * 0.05 / 3600)
    assert full["wall_s_per_simulated_s"] == pytest.approx(full["ms_per_step"] / 1e3 / full["dt"])
    for split in (sheet["split"], full["split"]):
        assert set(split["parts"]) == set(PARTS) and split["steps"] == 6
        parts = sum(p["ms_per_step"] for p in split["parts"].values())
        assert parts == pytest.approx(split["ms_per_step"], rel=1e-12)
        assert sum(p["percent"] for p in split["parts"].values()) == pytest.approx(100.0)
        outside_ticks = (split["outside_ms_per_step"] - split["ms_per_step"]) * split["steps"]  # 1 ms a tick
        assert 0 <= round(outside_ticks) <= OUTSIDE_TICKS, outside_ticks
        assert split["parts"]["bonds"]["ms_per_step"] > 0 and split["parts"]["integration"]["ms_per_step"] > 0
        assert split["ghost_wait_ms"] == [None]  # one rank receives no ghost update
    assert full["split"]["parts"]["platform"]["ms_per_step"] > 0 and full["split"]["parts"]["output"]["ms_per_step"] > 0
    assert sheet["split"]["parts"]["output"]["ms_per_step"] == 0.0  # the sheet writes nothing
    # the plain window in blocks of check_every (10) steps: 6 steps are one block of 6, two clock reads
    assert sheet["block_steps"] == 10 and sheet["median_block_ms_per_step"] == pytest.approx(1.0 / 6)
    assert sheet["median_block_particle_steps_per_second"] == pytest.approx(sheet["elements"] * 6e3)
    assert result["json"] == str(out) and not (tmp_path / "bench_scratch.h5").exists()
    text = "\n".join(report_lines(result))
    assert "particle-steps/s" in text and "per simulated second" in text and "platform" in text


def test_bench_starts_the_full_scene_from_a_checkpoint_of_its_run(tmp_path):
    """``pice bench --restart CHECKPOINT``: the window starts where the run's checkpoint left it (a
    later phase of the scene), recorded in the settings; a missing checkpoint is refused first."""
    from pice.errors import JobError
    from pice.io.checkpoint import CheckpointError
    from pice.job import load_job
    from pice.runner import run_job

    serial_only()
    job_path = tmp_path / "barge.toml"
    job_path.write_text(scenes.barge_job(duration=0.004, series_every=10, mooring="dem").replace(
        "snapshots = 3", "snapshots = 2\ncheckpoint_every = 0.002"))
    run_job(load_job(job_path), output=str(tmp_path / "barge.h5"), progress=None)
    ckpt = tmp_path / "barge.ckpt.h5"
    result = run_bench(scene="full", steps=4, warmup=2, job=job_path, json_path=tmp_path / "b.json", restart=ckpt)
    assert result["settings"]["restart"] == str(ckpt)
    assert result["full"]["window_start_time_s"] == pytest.approx(0.004 + 2e-4, rel=1e-9)  # 40 + 2 steps of 1e-4 s
    assert "restarted from" in "\n".join(report_lines(result))
    with pytest.raises(JobError, match="no such checkpoint"):
        run_bench(scene="full", steps=4, warmup=2, job=job_path, restart=tmp_path / "none.ckpt.h5")
    # a checkpoint of another job (here the same barge in denser water) is refused by the restart's
    # physics check (io/restore.py), naming the key, before any step is timed
    other = tmp_path / "other.toml"
    other.write_text(job_path.read_text().replace("[water]\ndensity = 1025.0", "[water]\ndensity = 1030.0", 1))
    assert load_job(other).water.density == 1030.0
    with pytest.raises(CheckpointError, match="physics differs.*water.density"):
        run_bench(scene="full", steps=4, warmup=2, job=other, restart=ckpt)


def test_the_plain_step_reads_no_clock_and_the_timed_step_gives_its_numbers_bit_for_bit(tick_clock):
    serial_only()
    reads = tick_clock
    job = scenes.job_from_text(scenes.barge_job(mooring="dem"))  # ice, hull contact, bodies and DEM lines
    plain, timed = Simulation(job), Simulation(job)
    assert plain.timers is None and "step" not in vars(plain)  # the class's plain step
    plain.advance(30)
    assert reads == []  # nothing in the plain step, its exchange or its health check reads the clock
    timers = timed.enable_timers()
    timed.advance(30)
    laps = len(reads) - 1                                   # every read but the start's is a lap
    assert timers.steps == 30 and laps > 30 and timers.total() == pytest.approx(1e-3 * laps)
    for name in ("x", "v", "w", "force", "torque", "bond_hist", "contact_hist", "hull_hist"):
        assert np.array_equal(getattr(plain.p, name), getattr(timed.p, name)), name
    assert np.array_equal(plain.platform.poses(), timed.platform.poses())
    assert np.array_equal(plain.body_total, timed.body_total)
    timed.disable_timers()
    reads.clear()
    timed.advance(3)
    assert reads == [] and timed.timers is None and "step" not in vars(timed)


def test_the_median_block_leaves_out_a_preempted_block_and_takes_the_slowest_rank():
    """bench.measure.block_median: the median over blocks of the slowest rank's ms per step. One block
    stretched 50 times (a process preempted on a shared machine) moves the mean, not the median."""
    from pice.parallel.comm import SerialComm

    blocks = [1.0, 1.1, 50.0, 0.9, 1.05]
    assert pice.bench.measure.block_median(SerialComm(), {"block_ms": blocks}) == pytest.approx(1.05)

    class TwoRanks(SerialComm):  # rank 1's blocks, gathered on rank 0 after its own
        def gather(self, obj):
            return [obj, np.array([1.2, 1.0, 1.0, 1.0, 1.0])]

    assert pice.bench.measure.block_median(TwoRanks(), {"block_ms": blocks}) == pytest.approx(1.1)


def test_the_efficiency_script_pairs_one_and_two_rank_runs_of_each_tree(tmp_path, capsys):
    """benchmarks/efficiency.py (issue 12's measurement: interleaved 1- and 2-rank rounds, medians)
    on a small sheet, one round: each efficiency is the 2-rank throughput over twice the 1-rank one
    of the same round, read back from the launches' JSON; a path that is no checkout is refused.
    No assertion on speed (this module's docstring says why)."""
    serial_only()
    import importlib.util
    import pathlib

    root = pathlib.Path(__file__).resolve().parents[2]
    spec = importlib.util.spec_from_file_location("efficiency", root / "benchmarks" / "efficiency.py")
    eff = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(eff)
    out = tmp_path / "eff"
    medians = eff.main(["--rounds", "1", "--steps", "6", "--warmup", "2", "--length", "12", "--width", "8",
                        "--out", str(out), "--trees", str(root)])
    one = json.loads((out / "tree0_1r_round1.json").read_text())
    two = json.loads((out / "tree0_2r_round1.json").read_text())
    assert one["ranks"] == 1 and two["ranks"] == 2
    expected = two["sheet"]["particle_steps_per_second"] / (2 * one["sheet"]["particle_steps_per_second"])
    assert medians == {str(root): pytest.approx(expected, rel=1e-12)}
    assert "median efficiency" in capsys.readouterr().out
    with pytest.raises(SystemExit, match="not a pice checkout"):
        eff.main(["--trees", str(tmp_path)])
    with pytest.raises(SystemExit):  # argparse's error: "--ranks 1: give at least 2"
        eff.main(["--ranks", "1"])
    assert "--ranks 1: give at least 2" in capsys.readouterr().err
