"""The toolchain of the venv: mpi4py talks to the MPI library of the mpiexec beside python, and numba
compiles pice's kernels.

What can go wrong, and what each test would then see: mpi4py built against another MPI than the
launcher's (each rank starts a singleton: a communicator of size 1 under `mpiexec -n 2`); a
`mpiexec` from another MPICH than the library mpi4py loads (versions differ); numba missing its
LLVM backend or the kernels falling back to object mode (no native signature).
"""
import os
import re
import subprocess
import sys

import numpy as np
import pytest
from launch import MPIEXEC, clean_env

_SNIPPET = (
    "from mpi4py import MPI; c = MPI.COMM_WORLD; "
    "print(f'rank {c.Get_rank()} of {c.Get_size()}', flush=True)"
)
#: where launchers announce the job: (size variable, rank variable)
_LAUNCHER_VARS = (("PMI_SIZE", "PMI_RANK"), ("OMPI_COMM_WORLD_SIZE", "OMPI_COMM_WORLD_RANK"),
                  ("PMIX_SIZE", "PMIX_RANK"))


def _launched():
    """(size, rank) the launcher announced in the environment, or (1, 0) without a launcher."""
    for size, rank in _LAUNCHER_VARS:
        if size in os.environ:
            return int(os.environ[size]), int(os.environ.get(rank, "0"))
    return 1, 0


def _mpich_version(text: str) -> str:
    m = re.search(r"(?:MPICH )?Version:\s*(\S+)", text)
    assert m, text
    return m.group(1)


def _check_world():
    """COMM_WORLD has the size and this process the rank the launcher announced, and a sum over it
    counts every rank. Returns the size."""
    from mpi4py import MPI

    comm = MPI.COMM_WORLD
    size, rank = _launched()
    assert (comm.Get_size(), comm.Get_rank()) == (size, rank)
    assert comm.allreduce(1, op=MPI.SUM) == size
    assert comm.allreduce(comm.Get_rank() + 1, op=MPI.SUM) == size * (size + 1) // 2
    return size


def test_communicator_is_the_launchers_job():
    """Serial stage: no launcher, a singleton (size 1, rank 0); under mpiexec the same check runs in
    test_two_ranks_form_one_communicator. A mismatch is an mpi4py built against another MPI than the
    launcher's, or launcher variables leaking into the environment."""
    _check_world()


@pytest.mark.mpi
def test_two_ranks_form_one_communicator():
    """Under `mpiexec -n 2`: COMM_WORLD has the 2 ranks Hydra announced (PMI_SIZE, PMI_RANK), not two
    singletons."""
    if _launched()[0] == 1:
        pytest.skip("needs MPI: run as `mpiexec -n 2 python -m pytest -m mpi`")
    assert _check_world() == 2


def test_mpiexec_beside_python_is_the_mpi_librarys():
    """The venv's mpiexec (MPICH's Hydra) is of the same MPICH version as the library mpi4py loaded."""
    from mpi4py import MPI

    library = MPI.Get_library_version()
    assert "MPICH" in library, library
    assert MPIEXEC.is_file() and os.access(MPIEXEC, os.X_OK), f"no mpiexec at {MPIEXEC}"
    proc = subprocess.run([str(MPIEXEC), "--version"], capture_output=True, text=True, timeout=60, env=clean_env())
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "HYDRA" in proc.stdout, proc.stdout
    assert _mpich_version(proc.stdout) == _mpich_version(library), (proc.stdout, library)


def test_mpiexec_next_to_python_runs_two_ranks():
    # Drop launcher variables so this also works when pytest itself runs under mpiexec.
    proc = subprocess.run(
        [str(MPIEXEC), "-n", "2", sys.executable, "-c", _SNIPPET],
        capture_output=True, text=True, timeout=120, env=clean_env(),
    )
    assert proc.returncode == 0, proc.stdout + proc.stderr
    # the two ranks write to one pipe: their lines may interleave, so match the records, not lines
    ranks = sorted(re.findall(r"rank (\d+) of 2", proc.stdout))
    assert ranks == ["0", "1"], proc.stdout + proc.stderr


def test_numba_compiles_the_kernels_to_native_code():
    """A pice kernel (kernels.halo.max_displacement) compiles in nopython mode and gives the right
    answer: the largest of |(3, 4, 0)| = 5 and |(1, 0, 0)| = 1 over the first two rows."""
    from numba.core.config import DISABLE_JIT

    from pice.kernels.halo import max_displacement

    if DISABLE_JIT:
        pytest.skip("NUMBA_DISABLE_JIT=1: the kernels run as plain Python")
    x = np.array([[3.0, 4.0, 0.0], [1.0, 0.0, 0.0], [100.0, 0.0, 0.0]])
    assert max_displacement(x, np.zeros_like(x), 2) == 5.0
    assert max_displacement.nopython_signatures, "max_displacement did not compile in nopython mode"
