"""`pice study`: variants of a job from --vary keys, their metrics from the run files, the report.

* key paths and values: ``moorings[0].element_length`` is ("moorings", 0, "element_length"); values
  read as TOML scalars, a bare word as the string it spells;
* bad input (an unknown key, a bad value, a malformed criterion, a group size that does not divide
  the ranks) is one line naming it, exit status 2, and nothing is run or written; a variant refused
  at set-up (a dt above the stability limit) or stopped in its run is recorded as failed and the
  others run; a killed study runs only its unfinished variants again;
* the metrics of a hand-made run file whose series are known (values worked out in the comments);
* the buoy design criteria (heel, draft, the widest section's freeboard, offset in % of the depth)
  of a hand-made run of jobs/cai_2018_buoy.toml's hull;
* the TOML writer gives back what it was given (tomllib round trip);
* one end-to-end study of two time steps on the 22-element slope job of tests/io/test_run_file.py.
"""

from __future__ import annotations

import csv
import json
import math
import pathlib

import h5py
import numpy as np
import pytest
from scenes import JOBS, barge_job, job_from_text, slope_job, tomllib

from pice.cli import main
from pice.errors import JobError
from pice.io.toml_text import toml_text
from pice.job import load_job, parse_job
from pice.study.metrics import change_percent, compare, run_metrics
from pice.study.report import study_table
from pice.study.variants import key_path, make_variants, parse_vary, split_values, toml_value

# the slope job of tests/io/test_run_file.py, 0.05 s: 22 elements, touching the slope within 0.05 s
WALL_JOB = slope_job(duration=0.05, snapshots=1)

# the moored barge of tests/physics/test_platform_coupling.py, only validated here, never run
MOORED_JOB = barge_job(mooring="dem")


def write(tmp_path: pathlib.Path, text: str, name: str = "tiny.toml") -> pathlib.Path:
    path = tmp_path / name
    path.write_text(text)
    return path


# -- keys and values -------------------------------------------------------------------------------

def test_key_paths_and_values_read_as_toml():
    assert key_path("moorings[0].element_length") == ("moorings", 0, "element_length")
    assert key_path("ice.element_diameter") == ("ice", "element_diameter")
    assert key_path("walls[1].normal[2]") == ("walls", 1, "normal", 2)
    assert split_values('1e-4, auto,[1.0, 0.0],"a,b"') == ["1e-4", "auto", "[1.0, 0.0]", '"a,b"']
    assert toml_value("1e-4") == 1e-4 and isinstance(toml_value("5"), int) and toml_value("5") == 5
    assert toml_value("true") is True
    assert toml_value("auto") == "auto" and toml_value('"auto"') == "auto"
    assert toml_value("[1.0, 0.0]") == [1.0, 0.0]
    vary = parse_vary("moorings[0].element_length=5,10,20")
    assert vary.key == "moorings[0].element_length" and vary.values == (5, 10, 20)


@pytest.mark.parametrize("spec", ["run.dt", "=1,2", "run.dt=1e-4,,2e-4", "ice..thickness=1", "ice.[0]=1",
                                  "run dt=1"])
def test_malformed_vary_is_refused(spec):
    with pytest.raises(JobError) as err:
        parse_vary(spec)
    assert len(err.value.lines) == 1 and err.value.lines[0].startswith("--vary ")


def test_variants_are_the_cartesian_product_in_order(tmp_path):
    job = write(tmp_path, MOORED_JOB)
    out = tmp_path / "study"
    variants = make_variants(job, ["moorings[0].element_length=5,10,20", "ice.velocity[0]=0.5,1.0",
                                   "run.dt=auto,1e-4"], out_dir=out)
    assert len(variants) == 12
    assert not out.exists()  # validation writes nothing
    for k, v in enumerate(variants):
        length, speed, dt = (5, 10, 20)[k // 4], (0.5, 1.0)[k // 2 % 2], ("auto", 1e-4)[k % 2]
        assert v.values == {"moorings[0].element_length": length, "ice.velocity[0]": speed, "run.dt": dt}
        assert v.job.moorings[0].element_length == length
        assert v.job.ice.velocity == (speed, 0.0) and v.job.run.dt == dt
        assert v.toml == out / f"tiny_{k}.toml" and v.run == out / f"tiny_{k}.h5"
        again = tomllib.loads(v.text)  # the variant file is the variant
        assert again["moorings"][0]["element_length"] == length and again["run"]["output"] == str(v.run)
        assert v.job.model_dump() == parse_job(again).model_dump()


@pytest.mark.parametrize(("vary", "key", "why"), [
    ("ice.thicknes=1.0,1.2", "ice.thicknes", "unknown key 'thicknes' in [ice]"),
    ("run.dt=1e-4,-1", "run.dt", "run.dt = -1: must be 'auto' or > 0 s"),
    ("run.dt=1e-4,soon", "run.dt", "run.dt = 'soon': must be 'auto' or a number"),
    ("ice.push.speed=1.0", "ice.push.speed", "the job has no [ice.push] table"),
    ("walls[1].friction=0.1", "walls[1].friction", "walls has 1 entry"),
])
def test_bad_input_is_one_line_exit_2_and_nothing_runs(tmp_path, capsys, monkeypatch, vary, key, why):
    import pice.runner

    def no_run(*args, **kwargs):
        raise AssertionError("a variant was run")

    monkeypatch.setattr(pice.runner, "run_job", no_run)
    job = write(tmp_path, WALL_JOB)
    out = tmp_path / "study"
    assert main(["study", str(job), "--vary", vary, "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    assert key in err[0] and why in err[0]
    assert not out.exists()


def test_a_job_without_vary_is_one_line_exit_2(tmp_path, capsys, monkeypatch):
    """`pice study JOB` with nothing to vary (and not a sweep file): one line naming --vary and the
    sweep file, exit status 2, nothing run and no study folder."""
    import pice.runner

    monkeypatch.setattr(pice.runner, "run_job", lambda *a, **k: (_ for _ in ()).throw(AssertionError("ran")))
    job = write(tmp_path, WALL_JOB)
    assert main(["study", str(job), "--out", str(tmp_path / "study")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--vary" in err[0] and "sweep file" in err[0], err
    assert not (tmp_path / "study").exists()


# -- metrics of a run file ------------------------------------------------------------------------

def hand_made_run(path: pathlib.Path, *, peaks: bool = True) -> pathlib.Path:
    """4 rows at t = 0, 1, 2, 3 s; body 0 is the one measured, body 1 carries larger decoys."""
    time = np.array([0.0, 1.0, 2.0, 3.0])
    position = np.zeros((4, 2, 3))
    position[:, 0] = [[10.0, 5.0, 0.0], [13.0, 9.0, 0.0], [10.0, 5.0, -1.0], [16.0, 13.0, 2.0]]
    position[:, 1] = 1e3 * np.arange(4)[:, None]  # offsets of 1.7 km: not body 0's
    force = np.zeros((4, 2, 3))
    force[:, 0] = [[0.0, 0.0, 0.0], [2.0e5, 1.0, -3.0e4], [5.0e5, 0.0, 1.0e4], [1.0e5, 0.0, 0.0]]
    force[:, 1] = 9e9
    fmax, fmin = force.copy(), force.copy()
    fmax[2, 0] = [7.0e5, 0.0, 2.0e4]    # the Fx peak lies between rows 1 and 2
    fmin[3, 0] = [-1.0e5, 0.0, -8.0e4]  # so does the largest |Fz|, a downward one
    tension = np.array([[1.0, 2.0, 3.0], [4.0e5, 2.0e5, 1.0e5], [3.0e5, 6.0e5, 1.0], [1.0, 1.0, 1.0]])
    tmax = tension.copy()
    tmax[3, 2] = 9.0e5
    with h5py.File(path, "w") as f:
        s = f.create_group("series")
        s["time"], s["body_position"], s["ice_force"], s["fairlead_tension"] = time, position, force, tension
        if peaks:
            s["ice_force_max"], s["ice_force_min"], s["fairlead_tension_max"] = fmax, fmin, tmax
    return path


def test_metrics_of_a_hand_made_run(tmp_path):
    m = run_metrics(hand_made_run(tmp_path / "run.h5"))
    assert m["peak_load_x"] == 7.0e5  # ice_force_max row 2
    assert m["peak_load_z"] == 8.0e4  # |ice_force_min| row 3
    # horizontal distances from (10, 5): 0, 5 (3-4-5), 0 (z ignored), 10 (6-8-10)
    assert m["mean_offset"] == 15.0 / 4 and m["max_offset"] == 10.0
    assert m["max_fairlead_tension"] == 9.0e5  # fairlead_tension_max row 3, line 2
    settled = run_metrics(tmp_path / "run.h5", settle=1.0)  # rows t = 1, 2, 3 s
    assert settled["mean_offset"] == 5.0 and settled["max_offset"] == 10.0
    assert settled["peak_load_x"] == 7.0e5  # loads are taken over the whole run
    assert math.isnan(run_metrics(tmp_path / "run.h5", settle=4.0)["mean_offset"])  # no row that late


def test_metrics_without_peak_series_use_the_rows(tmp_path):
    m = run_metrics(hand_made_run(tmp_path / "run.h5", peaks=False))
    assert m["peak_load_x"] == 5.0e5 and m["peak_load_z"] == 3.0e4 and m["max_fairlead_tension"] == 6.0e5


def test_metrics_without_bodies_sum_the_walls(tmp_path):
    wall = np.zeros((3, 2, 3))
    wall[:, 0] = [[1.0, 0.0, 2.0], [3.0e3, 0.0, -4.0e3], [1.0e3, 0.0, 0.0]]
    wall[:, 1] = [[0.0, 0.0, 0.0], [2.0e3, 0.0, -1.0e3], [5.0e3, 0.0, 0.0]]
    with h5py.File(tmp_path / "walls.h5", "w") as f:
        f["series/time"], f["series/wall_force"] = np.arange(3.0), wall
    m = run_metrics(tmp_path / "walls.h5")
    assert m["peak_load_x"] == 6.0e3 and m["peak_load_z"] == 5.0e3  # sums 5e3, 6e3 in x; -5e3 in z
    for name in ("mean_offset", "max_offset", "max_fairlead_tension"):
        assert math.isnan(m[name])


def test_metrics_of_a_hand_made_keel_run(tmp_path):
    """A ship run through a [keel] gets R^p, where it peaks and the work of R (seed 002, Fig. 5: the
    peak of the 6 m running average of R = -f_x). The record by hand: a row each metre of penetration,
    R = 1, 2, ..., 10 kN up to delta = 10 m and down again to 0 at 20 m. The 6 m average (the rows in
    (delta - 6, delta], six of them) peaks at 51/6 kN, first at the window 7-12 m, i.e. delta = 12 m;
    the work is the triangle's area, 0.5 x 20 m x 10 kN = 100 kJ (the trapezoid rule exact on it).
    The same file without a [keel] in its job has none of them, and the keel run has none of the
    moored body's metrics (its ship moves as prescribed; the study table leaves their columns out)."""
    delta = np.arange(21.0)
    r = 1e3 * np.minimum(delta, 20.0 - delta)
    position = np.zeros((21, 1, 3))
    position[:, 0, 0] = 75.0 + delta
    force = np.zeros((21, 1, 3))
    force[:, 0, 0] = -r
    keel_job = (pathlib.Path(__file__).resolve().parents[2] / "jobs" / "gong_2017_keel_w17_3.toml").read_text()
    for name, text in (("keel.h5", keel_job), ("plain.h5", "")):
        with h5py.File(tmp_path / name, "w") as f:
            f["series/time"], f["series/body_position"], f["series/ice_force_mean"] = delta, position, force
            f["series/ice_force"] = force
            f.attrs["job_text"] = text
    m = run_metrics(tmp_path / "keel.h5")
    assert m["keel_peak_resistance"] == pytest.approx(51.0e3 / 6.0, rel=1e-12)
    assert m["keel_peak_at"] == 12.0 and m["keel_work"] == pytest.approx(1.0e5, rel=1e-12)
    keel_names = ("keel_peak_resistance", "keel_peak_at", "keel_work")
    assert all(math.isnan(v) for k, v in m.items() if k not in keel_names)
    plain = run_metrics(tmp_path / "plain.h5")
    assert all(math.isnan(plain[k]) for k in keel_names)
    assert plain["peak_load_x"] == 0.0 and plain["max_offset"] == 20.0  # the moored body's metrics
    # the printed table of a keel study (the w = 30 m study's end crashed on the work's unit, J): the
    # keel's three columns in kN, m and kJ, the moored body's left out
    rows = [{"variant": k, "values": {"keel.contact.friction": mu}, "wall_time": 1.0, "particle_steps": 10,
             "metrics": dict(m), "error": None} for k, mu in enumerate((0.3, 0.6))]
    compare(rows, reference=0)
    study = {"job": "keel.toml", "varied": ["keel.contact.friction"], "reference": 0, "reference_rule": "--reference",
             "variants": rows, "settle": 0.0, "loads_on": "the ship", "criteria": []}
    lines = study_table(study)
    head, first = next((lines[i], lines[i + 1]) for i, t in enumerate(lines) if t.lstrip().startswith("variant"))
    assert "keel R^p [kN]" in head and "work of R [kJ]" in head and "offset" not in head
    assert "8.5 (ref)" in first and "100 (ref)" in first and "12 (ref)" in first


def test_every_metric_has_a_unit_the_table_can_show():
    """The printed table scales each metric by its unit (N to kN, J to kJ, ...): a metric whose unit
    it does not know would crash the study at its very end, after all its runs (as keel_work's J did
    at the end of a 1.5 h study), so every unit in METRICS must be in the table's scales."""
    from pice.study.metrics import METRICS
    from pice.study.report import _TABLE_SCALE

    assert {unit for _, unit, _ in METRICS} <= set(_TABLE_SCALE)


def test_change_against_the_finest_variant():
    assert change_percent(90.0, 100.0) == -10.0 and change_percent(-110.0, -100.0) == -10.0
    assert change_percent(0.0, 0.0) == 0.0 and math.isnan(change_percent(1.0, 0.0))
    rows = [{"variant": k, "particle_steps": n, "metrics": {"peak_load_x": x, "peak_load_z": 1.0, "mean_offset": float("nan"),
                                               "max_offset": 2.0, "max_fairlead_tension": 3.0, "max_pitch": 4.0,
                                               "max_roll": 5.0}}
            for k, n, x in ((0, 100, 80.0), (1, 400, 100.0), (2, 200, 125.0))]
    assert compare(rows) == 1
    assert [r["change_pct"]["peak_load_x"] for r in rows] == [-20.0, 0.0, 25.0]
    assert math.isnan(rows[0]["change_pct"]["mean_offset"])
    assert compare(rows, reference=0) == 0 and rows[1]["change_pct"]["peak_load_x"] == 25.0
    del rows[0]  # a phase of a sweep: variants keep their numbers in the full product
    assert compare(rows) == 1 and compare(rows, reference=2) == 2 and rows[0]["change_pct"]["peak_load_x"] == -20.0


# -- the TOML writer --------------------------------------------------------------------------------

def test_toml_text_round_trips():
    data = {"gravity": 9.81, "n": 3, "flag": False, "empty": [], "inf": float("-inf"),
            "run": {"dt": "auto", "name": 'say "hi"\n\tüber', "tiny": 1e-300},
            "walls": [{"type": "plane", "normal": [0.0, 0.0, 1.0], "region": {"xmin": 1.0}},
                      {"type": "triangle", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]]}],
            "moorings": [{"body": "b", "segments": [{"length": 1.0}, {"length": 2.0}],
                          "hull": {"size": [1.0, 2.0, 3.0]}}],
            "a key": {"x.y": 1}}
    assert tomllib.loads(toml_text(data, header="two\nlines")) == data
    demo = tomllib.loads((JOBS / "level_ice_demo.toml").read_text())
    assert tomllib.loads(toml_text(demo)) == demo


# -- end to end ------------------------------------------------------------------------------------

def test_study_of_two_time_steps_writes_table_csv_json_and_png(tmp_path, capsys):
    job = write(tmp_path, WALL_JOB)
    out = tmp_path / "study"
    assert main(["study", str(job), "--vary", "run.dt=2e-4,4e-4", "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "run.dt" in printed and "0.0002" in printed and "0.0004" in printed and "(ref)" in printed
    for name in ("tiny_0.toml", "tiny_0.h5", "tiny_1.toml", "tiny_1.h5", "study.csv", "study.json", "study.png"):
        assert (out / name).is_file(), name
    assert load_job(out / "tiny_1.toml").run.dt == 4e-4  # a variant is a job you can run again
    with open(out / "study.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert [r["run.dt"] for r in rows] == ["0.0002", "0.0004"]
    # 0.05 s in 250 and 125 steps of the 22 elements; the finer is the reference
    assert [int(r["particle_steps"]) for r in rows] == [22 * 250, 22 * 125]
    assert [r["reference"] for r in rows] == ["1", "0"]
    for k, r in enumerate(rows):
        with h5py.File(out / f"tiny_{k}.h5") as f:
            fx = f["series/wall_force"][:, :, 0].sum(axis=1).max()
            assert f.attrs["dt"] == (2e-4, 4e-4)[k]
        assert fx > 1e4  # the sheet reached the slope
        assert float(r["peak_load_x_N"]) == pytest.approx(fx, rel=1e-12)
        assert float(r["wall_time_s"]) > 0 and r["mean_offset_m"] == "nan"
    x0, x1 = float(rows[0]["peak_load_x_N"]), float(rows[1]["peak_load_x_N"])
    assert float(rows[0]["peak_load_x_change_pct"]) == 0.0
    assert float(rows[1]["peak_load_x_change_pct"]) == pytest.approx(100 * (x1 - x0) / x0, rel=1e-9)
    study = json.loads((out / "study.json").read_text())
    assert study["reference"] == 0 and study["varied"] == ["run.dt"] and study["loads_on"] == "the walls (sum)"
    assert study["variants"][1]["values"] == {"run.dt": 4e-4} and study["variants"][1]["metrics"]["max_offset"] is None
    png = (out / "study.png").read_bytes()
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    assert int.from_bytes(png[16:20], "big") == 1200 and int.from_bytes(png[20:24], "big") == 700


# -- criteria -------------------------------------------------------------------------------------

@pytest.mark.parametrize(("criterion", "why"), [
    ("max_pitch_deg << 15", "write <metric> <op> <number>"),
    ("max_pitch < 15", "no metric 'max_pitch'; one of"),
    ("max_offset_m < soon", "write <metric> <op> <number>"),
])
def test_bad_criterion_is_one_line_exit_2_and_nothing_runs(tmp_path, capsys, monkeypatch, criterion, why):
    import pice.runner

    monkeypatch.setattr(pice.runner, "run_job", lambda *a, **k: (_ for _ in ()).throw(AssertionError("ran")))
    job = write(tmp_path, WALL_JOB)
    out = tmp_path / "study"
    assert main(["study", str(job), "--vary", "run.dt=2e-4", "--criterion", criterion, "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and why in err[0] and criterion in err[0], err
    assert not out.exists()


def test_judge_marks_pass_fail_and_missing():
    from pice.study.criteria import judge, parse_criterion

    metrics = {"max_pitch": 12.0, "max_offset": 5.0, "peak_load_x": float("nan")}
    ok, failed = judge([parse_criterion("max_pitch_deg < 15"), parse_criterion("max_offset_m <= 4.5")], metrics)
    assert not ok and failed == ["max_offset_m <= 4.5"]
    ok, failed = judge([parse_criterion("peak_load_x_N >= 1e4")], metrics)
    assert not ok and "no peak_load_x_N in this run" in failed[0]
    assert judge([parse_criterion(" max_pitch_deg<15 ")], metrics) == (True, [])


def test_study_with_criteria_marks_each_variant(tmp_path, capsys):
    job = write(tmp_path, WALL_JOB)
    out = tmp_path / "study"
    args = ["study", str(job), "--vary", "run.dt=2e-4,4e-4", "--out", str(out),
            "--criterion", "peak_load_x_N > 1e4", "--criterion", "max_pitch_deg < 15"]
    assert main(args) == 0
    printed = capsys.readouterr().out
    assert "criteria (peak_load_x_N > 10000, max_pitch_deg < 15)" in printed
    with open(out / "study.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    # the sheet reaches the slope in both (> 1e4 N), and a wall has no pitch: each fails on the missing metric
    assert [r["passed"] for r in rows] == ["0", "0"]
    assert all(r["failed"] == "max_pitch_deg < 15 (no max_pitch_deg in this run)" for r in rows)
    study = json.loads((out / "study.json").read_text())
    assert study["criteria"] == ["peak_load_x_N > 10000", "max_pitch_deg < 15"]


# -- failures and restarts ------------------------------------------------------------------------

def test_a_refused_variant_is_recorded_and_the_others_run(tmp_path, capsys):
    """run.dt = 0.01 s is above the stability limit (a set-up check: the scene is built): that variant
    is recorded as failed with the reason, and the other runs (issue 16: one bad variant no longer
    stops the study)."""
    job = write(tmp_path, WALL_JOB)
    out = tmp_path / "study"
    assert main(["study", str(job), "--vary", "run.dt=2e-4,0.01", "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "failed: " in printed and "above the stability limit" in printed
    with open(out / "study.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert rows[0]["error"] == "" and float(rows[0]["peak_load_x_N"]) > 1e4
    assert "above the stability limit" in rows[1]["error"] and rows[1]["peak_load_x_N"] == "nan"
    assert rows[0]["reference"] == "1"


def test_a_restarted_study_runs_only_what_is_not_finished(tmp_path, monkeypatch):
    """A study whose first variant finished before (its outcome recorded, its run file "finished")
    runs only the second when called again, as after a kill; a changed variant runs again."""
    import pice.runner

    job = write(tmp_path, WALL_JOB)
    out = tmp_path / "study"
    assert main(["study", str(job), "--vary", "run.dt=2e-4,4e-4", "--out", str(out)]) == 0
    (out / "tiny_1.outcome.json").unlink()  # as if killed while variant 1 ran
    ran = []
    real = pice.runner.run_job

    def counting(job, **kwargs):
        ran.append(kwargs["output"])
        return real(job, **kwargs)

    monkeypatch.setattr(pice.runner, "run_job", counting)
    assert main(["study", str(job), "--vary", "run.dt=2e-4,4e-4", "--out", str(out)]) == 0
    assert ran == [str(out / "tiny_1.h5")]
    with open(out / "study.csv", newline="") as f:
        assert len(list(csv.DictReader(f))) == 2
    # the same job moved to another folder and renamed: the same study, nothing runs again
    moved = tmp_path / "moved" / "tiny.toml"
    moved.parent.mkdir()
    moved.write_text(job.read_text())
    ran.clear()
    assert main(["study", str(moved), "--vary", "run.dt=2e-4,4e-4", "--out", str(out)]) == 0
    assert ran == []
    # a changed job runs every variant again
    moved.write_text(job.read_text().replace("friction = 0.3", "friction = 0.5", 1))
    assert main(["study", str(moved), "--vary", "run.dt=2e-4,4e-4", "--out", str(out)]) == 0
    assert ran == [str(out / "tiny_0.h5"), str(out / "tiny_1.h5")]



def test_cost_counts_the_mooring_nodes(tmp_path):
    """The cost of a variant counts every element and every DEM mooring-node update (issue 16): the
    barge's 4 lines of 120 m in 10 m elements have 4 x 13 nodes, updated once a step here."""
    from pice.runner import run_job

    job = job_from_text(barge_job(duration=0.01, mooring="dem"), base_dir=tmp_path)
    summary = run_job(job, output=str(tmp_path / "barge.h5"), progress=None)
    assert summary["mooring_node_updates"] == 4 * 13
    job_q = job_from_text(barge_job(duration=0.01, mooring="quasi_static"), base_dir=tmp_path)
    assert run_job(job_q, output=str(tmp_path / "barge_q.h5"), progress=None)["mooring_node_updates"] == 0


def test_a_blowing_up_variant_is_recorded_and_the_others_run(tmp_path, capsys):
    """With run.allow_unstable_dt = true a step of 5x the limit is not refused: that variant blows up
    (the health check stops it with its diagnostic), is recorded as failed with the reason, and the
    other variant runs to its end (issue 16)."""
    text = WALL_JOB.replace("[run]\n", "[run]\nallow_unstable_dt = true\n", 1)
    job = write(tmp_path, text)
    from pice.simulation import Simulation

    stable = Simulation(load_job(job)).limit.stable  # the scene's stability limit [s]
    out = tmp_path / "study"
    assert main(["study", str(job), "--vary", f"run.dt=2e-4,{5 * stable:.6g}", "--out", str(out)]) == 0
    with open(out / "study.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert rows[0]["error"] == "" and float(rows[0]["peak_load_x_N"]) > 1e4
    assert "unstable" in rows[1]["error"] and "stability limit" in rows[1]["error"]
    with h5py.File(out / "tiny_1.h5") as f:  # the stopped run's file is kept, closed with its reason
        status = f.attrs["status"]
        assert (status.decode() if isinstance(status, bytes) else status).startswith("stopped")


def test_sigkill_then_the_same_command_runs_only_the_unfinished(tmp_path):
    """`pice study` killed with SIGKILL once its first variant's outcome is recorded, then run again:
    the second run says the first variant was done before and runs the rest (issue 16)."""
    import time

    from launch import BIN, kill9, run_cmd, start

    job = write(tmp_path, slope_job(duration=0.3, snapshots=1))
    out = tmp_path / "study"
    cmd = [str(BIN / "pice"), "study", str(job), "--vary", "run.dt=2e-4,3e-4,4e-4", "--out", str(out)]
    proc = start(cmd)
    end = time.monotonic() + 300
    while not (out / "tiny_0.outcome.json").exists() and proc.poll() is None and time.monotonic() < end:
        time.sleep(0.05)
    assert proc.poll() is None, "the study ended before it could be killed"
    kill9(proc)
    assert not (out / "tiny_2.outcome.json").exists()
    res = run_cmd(cmd)
    assert "variant 0: done before" in res.stderr
    assert "variant 0 of 0..2" not in res.stderr and "variant 2 of 0..2" in res.stderr
    with open(out / "study.csv", newline="") as f:
        assert [r["error"] for r in csv.DictReader(f)] == ["", "", ""]


@pytest.mark.parametrize("size", ["0", "3"])
def test_group_size_that_does_not_divide_the_ranks_is_refused(tmp_path, capsys, size):
    job = write(tmp_path, WALL_JOB)
    out = tmp_path / "study"
    assert main(["study", str(job), "--vary", "run.dt=2e-4", "--group-size", size, "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"--group-size {size}" in err[0], err
    assert not out.exists()


def test_a_stopped_variant_stops_the_study_and_is_not_recorded(tmp_path, capsys, monkeypatch):
    """SIGINT/SIGTERM during a variant (run_job raises RunInterrupted after its checkpoint): the study
    exits with status 130, says that the same command continues it, and records no outcome for that
    variant (a recorded one would never be run again); the variant before it keeps its outcome."""
    import pice.runner
    from pice.errors import RunInterrupted

    real = pice.runner.run_job

    def stop_second(job, **kwargs):
        if kwargs["output"].endswith("tiny_1.h5"):
            raise RunInterrupted("interrupted at step 3 (t = 0.0006 s); checkpoint written to x; continue with: "
                                 "pice run x --restart y")
        return real(job, **kwargs)

    monkeypatch.setattr(pice.runner, "run_job", stop_second)
    job = write(tmp_path, WALL_JOB)
    out = tmp_path / "study"
    assert main(["study", str(job), "--vary", "run.dt=2e-4,4e-4", "--out", str(out)]) == 130
    err = capsys.readouterr().err
    assert "study stopped (interrupted at step 3" in err and "the same command continues" in err, err
    assert (out / "tiny_0.outcome.json").exists() and not (out / "tiny_1.outcome.json").exists()
