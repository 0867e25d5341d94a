"""mpi/scaling.py --weak on two ranks (under `mpiexec -n 2 python -m pytest -m mpi`), on a tiny sheet:
the series runs 1 and 2 ranks inside one job and prints the weak efficiency; a sheet the memory check
refuses stops the series on every rank. No assertion on speed (docs/performance.md, "Scaling")."""

from __future__ import annotations

import importlib.util
import pathlib

import pytest
from launch import need_two_ranks

import pice.memory

pytestmark = pytest.mark.mpi
SCRIPT = pathlib.Path(__file__).resolve().parents[2] / "mpi" / "scaling.py"


def _scaling():
    spec = importlib.util.spec_from_file_location("pice_mpi_scaling", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_weak_series_runs_one_and_two_ranks(capsys):
    comm = need_two_ranks()
    _scaling().weak(300, None, 4, 2, 1)
    out = capsys.readouterr().out
    if comm.rank != 0:
        assert out == ""
        return
    rows = [ln for ln in out.splitlines() if ln.startswith("ranks=")]
    assert [r.split()[0] for r in rows] == ["ranks=1", "ranks=2"]
    assert "grid=1x1" in rows[0] and "grid=2x1" in rows[1]
    assert all("weak_efficiency=" in r for r in rows) and "weak_efficiency=1.000" in rows[0]


def test_a_refused_sheet_stops_the_series_on_every_rank(capsys, monkeypatch):
    comm = need_two_ranks()
    monkeypatch.setattr(pice.memory, "available_bytes", lambda: 1.0)  # no memory: every sheet is refused
    _scaling().weak(300, [1, 2], 4, 2, 1)
    out = capsys.readouterr().out
    comm.barrier()
    if comm.rank == 0:
        assert "ranks=1: refused" in out and "ranks=2" not in out
