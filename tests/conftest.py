"""Shared pytest configuration for pice.

Tests are sorted by kind into tests/unit, tests/physics, tests/parallel and tests/io; markers (mpi,
slow, nojit, io) are declared in pyproject.toml.

Shared helpers: tests/scenes.py (small job texts and builders) and tests/launch.py (`pice` and
`mpiexec` in a subprocess). This file puts tests/ first on sys.path, so every test module imports
them as ``import scenes`` / ``from launch import ...`` whatever its folder and however pytest is
started (``python -m pytest tests``, ``mpiexec -n 2 python -m pytest -m mpi tests``, one file, one
folder): pytest always loads this conftest before the test modules below it. The test folders are
not packages (no __init__.py): pytest imports each test module by its basename, so basenames must be
unique across the folders, and no test module imports another.

Under MPI (``mpiexec -n 2 python -m pytest -m mpi``):
  * only rank 0 prints pytest's terminal output;
  * a test failure on any rank prints the traceback to stderr and calls
    ``MPI.COMM_WORLD.Abort(1)`` so the other ranks cannot hang in a collective.
Serial runs never import mpi4py here (MPI is not initialised by the conftest).
"""
import os
import sys
from pathlib import Path

import pytest

_TESTS = str(Path(__file__).resolve().parent)
if _TESTS not in sys.path:
    sys.path.insert(0, _TESTS)

_MPI_ENV_VARS = ("PMI_RANK", "PMI_SIZE", "OMPI_COMM_WORLD_SIZE", "PMIX_RANK")


def _mpi_comm():
    """COMM_WORLD if we were launched by mpiexec with more than one rank, else None."""
    if not any(v in os.environ for v in _MPI_ENV_VARS):
        return None
    try:
        from mpi4py import MPI
    except ImportError:
        return None
    comm = MPI.COMM_WORLD
    return comm if comm.Get_size() > 1 else None


@pytest.hookimpl(trylast=True)  # after the terminal plugin has registered its reporter
def pytest_configure(config):
    comm = _mpi_comm()
    if comm is None or comm.Get_rank() == 0:
        return
    # Non-root rank: keep quiet. Failures are still printed to stderr (see below).
    config.option.verbose = -1
    reporter = config.pluginmanager.get_plugin("terminalreporter")
    if reporter is not None and hasattr(reporter, "_tw"):
        try:
            from _pytest.config import create_terminal_writer

            devnull = open(os.devnull, "w")
            config.add_cleanup(devnull.close)
            reporter._tw = create_terminal_writer(config, devnull)
        except Exception:  # pytest internals changed: stay noisy rather than break
            return


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    outcome = yield
    report = outcome.get_result()
    # setup failures (fixtures doing collectives) can deadlock just like call failures
    if report.failed and report.when in ("setup", "call"):
        comm = _mpi_comm()
        if comm is not None:
            rank = comm.Get_rank()
            sys.stderr.write(
                f"\n[rank {rank}] FAILED {item.nodeid} ({report.when})\n"
                f"{report.longreprtext}\n[rank {rank}] calling MPI.COMM_WORLD.Abort(1)\n"
            )
            sys.stderr.flush()
            sys.stdout.flush()
            comm.Abort(1)


@pytest.fixture
def tmp_out(tmp_path):
    """Output directory for a test. Under MPI all ranks get rank 0's tmp_path."""
    comm = _mpi_comm()
    if comm is None:
        return tmp_path
    from pathlib import Path

    return Path(comm.bcast(str(tmp_path) if comm.Get_rank() == 0 else None, root=0))
