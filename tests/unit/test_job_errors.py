"""Broken jobs on one rank: each problem is ONE line ``FILE: key = value: what is expected``, exit
status 2, nothing written.

The cases are the table of tests/bad_jobs.py (its docstring lists where each rule lives and the
classes of input it covers); each runs through the real command line in-process (``pice run JOB -o
OUT``, and a selection through ``pice check``). tests/parallel/test_job_errors_two_ranks.py runs the
same table under ``mpiexec -n 2``.

Exit statuses are those of pice/errors.py and pice/io/errors.py: JobError 2, OutputError 4.
"""

from __future__ import annotations

import re

import pytest
from bad_job_kit import BASE, Case, check_error_lines, inputs, params, write_job
from bad_jobs import CASES
from scenes import REPO

from pice.cli import main


def test_at_least_twenty_cases_with_distinct_ids():
    ids = [c.id for c in CASES]
    assert len(ids) == len(set(ids)) and len(ids) >= 20


@pytest.mark.parametrize("c", params(CASES))
def test_run_refuses_broken_job(c: Case, tmp_path, capsys):
    """`pice run` on a broken job: exit 2, one line per problem naming the job file, nothing written."""
    path = write_job(tmp_path, c)
    out = tmp_path / "out.h5"
    code = main(["run", str(path), "-o", str(out)])
    captured = capsys.readouterr()
    assert code == 2, captured.err
    assert captured.out == ""
    check_error_lines(captured.err, path, c)
    assert not out.exists()
    assert {p.name for p in tmp_path.iterdir()} == inputs(c)


CHECKED = {"thickness_negative", "unknown_key_in_section", "dt_word", "two_bad_values", "invalid_toml",
           "job_file_not_found", "dt_above_stability_limit", "mesh_wall_file_unreadable",
           "load_region_selects_nothing", "sheet_larger_than_memory", "snapshots_beyond_the_run",
           "hull_contains_ice", "pretension_below_slack", "job_not_utf8"}


@pytest.mark.parametrize("c", params([c for c in CASES if c.id in CHECKED]))
def test_check_refuses_broken_job(c: Case, tmp_path, capsys):
    """`pice check` reports the same problems with the same exit status 2 (and writes nothing)."""
    path = write_job(tmp_path, c)
    code = main(["check", str(path)])
    captured = capsys.readouterr()
    assert code == 2, captured.err
    assert captured.out == ""
    check_error_lines(captured.err, path, c)
    assert {p.name for p in tmp_path.iterdir()} == inputs(c)


def test_check_describes_the_demo_job(capsys, monkeypatch):
    """`pice check jobs/level_ice_demo.toml` (from the repository root): size, cost and time step."""
    monkeypatch.chdir(REPO)
    code = main(["check", "jobs/level_ice_demo.toml"])
    captured = capsys.readouterr()
    assert code == 0, captured.err
    out = captured.out
    assert out.splitlines()[0] == "jobs/level_ice_demo.toml: valid"

    def number(pattern: str) -> float:
        m = re.search(pattern, out, re.MULTILINE)
        assert m, f"{pattern!r} not in\n{out}"
        return float(m.group(1).replace(",", ""))

    num = r"([0-9][0-9,]*(?:\.[0-9]+)?(?:e[+-]?[0-9]+)?)"
    elements = number(rf"^\s*elements\s+{num} in \d+ layer")
    bonds = number(rf"^\s*bonds\s+{num}\s*$")
    memory = number(rf"^\s*memory.*?{num} MiB")
    stable = number(rf"^\s*stable time step\s+{num} s")
    chosen = number(rf"^\s*chosen time step\s+{num} s")
    steps = number(rf"^\s*steps per sim\. s\s+{num}")
    wall = number(rf"^\s*wall time / sim\. s\s+{num} s")
    assert elements > 100 and bonds > elements  # 40 m x 24 m of 1 m elements, ~3 bonds per element
    assert memory > 0 and wall > 0
    assert 0 < chosen <= stable
    assert steps == pytest.approx(1.0 / chosen, rel=2e-3)


@pytest.mark.parametrize("command", ["run", "check"])
def test_dem_lines_that_cannot_settle_are_one_line(command, tmp_path, capsys, monkeypatch):
    """A solve at set-up that cannot converge within its bound (issue 13): the DEM lines' relaxation
    to rest, capped at MAX_RELAX_NODE_STEPS node updates (here 1,000: 90 steps of the 11-node line),
    ends in one line naming moorings[0].relax, its residual and the fix; exit status 2, nothing written."""
    from bad_job_kit import BODY, MOORING, WATER

    from pice.platform import mooring_lines

    monkeypatch.setattr(mooring_lines, "MAX_RELAX_NODE_STEPS", 1.0e3)
    c = Case("relax_cannot_settle", BASE + WATER + BODY + MOORING,
             [["moorings[0].relax = true: its DEM lines did not settle to 1 N within 90 relaxation steps",
               "set relax = false"]], setup=True)
    path = write_job(tmp_path, c)
    code = main([command, str(path)] + (["-o", str(tmp_path / "out.h5")] if command == "run" else []))
    captured = capsys.readouterr()
    assert code == 2 and captured.out == "", captured.err
    check_error_lines("".join(line + "\n" for line in captured.err.splitlines() if " INFO: " not in line), path, c)
    assert {p.name for p in tmp_path.iterdir()} == inputs(c)


TINY_RUNNABLE = BASE  # length 4, width 3, duration 0.01: 12 elements, ~120 steps


def test_existing_output_needs_overwrite(tmp_path, capsys):
    """pice/io/run_file.py: an existing run file is never replaced without --overwrite (exit status 4)."""
    job = tmp_path / "tiny.toml"
    job.write_text(TINY_RUNNABLE, encoding="utf-8")
    out = tmp_path / "out.h5"
    before = b"an earlier run's file: must survive byte for byte\n" + bytes(range(256))
    out.write_bytes(before)
    code = main(["run", str(job), "-o", str(out)])
    captured = capsys.readouterr()
    assert code == 4, captured.err
    assert "Traceback" not in captured.err
    lines = captured.err.splitlines()
    assert len(lines) == 1, captured.err
    assert str(out) in lines[0] and "--overwrite" in lines[0]
    assert out.read_bytes() == before
    assert {p.name for p in tmp_path.iterdir()} == {"tiny.toml", "out.h5"}


def test_utf8_job_with_a_byte_order_mark_and_crlf_is_read_as_before(tmp_path):
    """Encodings (issue 13): a UTF-8 job file is read as Python reads text files (\\r\\n -> \\n, as
    the run file has always stored it), non-ASCII UTF-8 intact, a leading UTF-8 byte-order mark
    (Windows editors write one) dropped instead of failing TOML's first line."""
    from pice.job import load_job

    text = BASE.replace('name = "tiny"', 'name = "tiny (glace, 0 \N{DEGREE SIGN}C)"')
    path = tmp_path / "bom.toml"
    path.write_bytes(b"\xef\xbb\xbf" + text.replace("\n", "\r\n").encode("utf-8"))
    job = load_job(path)
    assert job.text == text and job.run.name == "tiny (glace, 0 \N{DEGREE SIGN}C)"
    plain = tmp_path / "plain.toml"
    plain.write_bytes(text.replace("\n", "\r\n").encode("utf-8"))
    assert load_job(plain).text == plain.read_text(encoding="utf-8") == text
