"""The bad-input table (tests/bad_jobs.py) under ``mpiexec -n 2 python -m pytest -m mpi tests``: every
broken job gives, on two ranks, the same single line and exit status 2 as on one, and writes nothing.

Each case runs in-process on both ranks (``pice run JOB -o OUT``, as tests/unit/test_job_errors.py
runs it on one): both ranks must return 2, rank 1 print nothing, rank 0 print the case's lines.
Then rank 0 runs the case again on one rank (the serial communicator in place of COMM_WORLD) while
rank 1 waits, and the two outputs must be the same line. The one figure allowed to differ is the
memory available on the machine (MemAvailable moves between the two runs), which the comparison
masks.
"""

from __future__ import annotations

import pathlib
import re

import pytest
from bad_job_kit import Case, check_error_lines, inputs, params, write_job
from bad_jobs import CASES
from launch import need_two_ranks

from pice.cli import main

pytestmark = pytest.mark.mpi

AVAILABLE = re.compile(r"the [\d.,]+ [KMGT]iB available")


def _same(line: str) -> str:
    return AVAILABLE.sub("the (machine's) available", line)


@pytest.mark.timeout(120)
@pytest.mark.parametrize("c", params(CASES))
def test_two_ranks_refuse_broken_job_with_the_line_of_one(c: Case, tmp_out, capsys, monkeypatch):
    comm = need_two_ranks()
    folder = tmp_out / c.id
    if comm.rank == 0:
        folder.mkdir()
        path = write_job(folder, c)
    path = pathlib.Path(comm.bcast(str(path) if comm.rank == 0 else None))
    out = folder / "out.h5"
    comm.barrier()
    code = main(["run", str(path), "-o", str(out)])
    captured = capsys.readouterr()
    results = comm.gather((code, captured.out, captured.err))
    comm.barrier()
    if comm.rank == 0:
        (code0, out0, err0), (code1, out1, err1) = results
        assert (code0, code1) == (2, 2), (err0, err1)
        assert out0 == out1 == "" and err1 == "", (out0, out1, err1)
        check_error_lines(err0, path, c)
        assert not out.exists() and {p.name for p in folder.iterdir()} == inputs(c)
        # the same case on one rank, in this process: the same line
        import pice.simulation
        from pice.parallel.comm import SerialComm

        monkeypatch.setattr(pice.simulation, "world", SerialComm)
        assert main(["run", str(path), "-o", str(out)]) == 2
        one = capsys.readouterr()
        assert one.out == "" and _same(one.err) == _same(err0), (one.err, err0)
        assert not out.exists()
    comm.barrier()

