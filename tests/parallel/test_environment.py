"""Checks that the MPI toolchain of the venv (mpi4py + MPICH's mpiexec) works."""
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

_SNIPPET = (
    "from mpi4py import MPI; c = MPI.COMM_WORLD; "
    "print(f'rank {c.Get_rank()} of {c.Get_size()}', flush=True)"
)


def test_mpi4py_comm_world():
    from mpi4py import MPI

    comm = MPI.COMM_WORLD
    size, rank = comm.Get_size(), comm.Get_rank()
    assert size >= 1
    assert 0 <= rank < size
    assert comm.allreduce(1, op=MPI.SUM) == size
    assert MPI.Get_library_version().strip()


@pytest.mark.mpi
def test_two_ranks_allreduce():
    from mpi4py import MPI

    comm = MPI.COMM_WORLD
    if comm.Get_size() == 1:
        pytest.skip("needs MPI: run as `mpiexec -n 2 python -m pytest -m mpi`")
    assert comm.Get_size() == 2
    assert comm.allreduce(comm.Get_rank() + 1, op=MPI.SUM) == 3


def test_mpiexec_next_to_python_runs_two_ranks():
    mpiexec = Path(sys.executable).parent / "mpiexec"
    assert mpiexec.is_file() and os.access(mpiexec, os.X_OK), f"no mpiexec at {mpiexec}"
    # Drop launcher variables so this also works when pytest itself runs under mpiexec.
    env = {k: v for k, v in os.environ.items()
           if not k.startswith(("PMI_", "PMIX_", "OMPI_", "HYDRA_", "MPIR_"))}
    proc = subprocess.run(
        [str(mpiexec), "-n", "2", sys.executable, "-c", _SNIPPET],
        capture_output=True, text=True, timeout=120, env=env,
    )
    assert proc.returncode == 0, proc.stdout + proc.stderr
    # the two ranks write to one pipe: their lines may interleave, so match the records, not lines
    ranks = sorted(re.findall(r"rank (\d+) of 2", proc.stdout))
    assert ranks == ["0", "1"], proc.stdout + proc.stderr
