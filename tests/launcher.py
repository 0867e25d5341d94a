"""Helpers for tests that start `mpiexec` or `pice` in a subprocess (not a test module)."""

import os
import pathlib
import sys

BIN = pathlib.Path(sys.executable).parent  # the venv's bin: pice, mpiexec


def clean_env() -> dict:
    """This environment without the MPI launcher's variables (so a child `mpiexec` starts its own
    job even when pytest itself runs under mpiexec), with the venv's bin first on PATH."""
    env = {k: v for k, v in os.environ.items() if not k.startswith(("PMI_", "OMPI_", "PMIX_", "HYDRA_", "MPI_"))}
    env["PATH"] = f"{BIN}{os.pathsep}{env.get('PATH', '')}"
    return env
