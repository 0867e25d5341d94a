"""Rank-tagged logging: rank 0 logs at INFO, the other ranks at WARNING, each line tagged."""

from __future__ import annotations

import logging
import os
import sys


def launch_rank() -> int:
    """This process's MPI rank from the launcher's environment (0 when not launched by MPI)."""
    for var in ("PMI_RANK", "OMPI_COMM_WORLD_RANK", "PMIX_RANK", "SLURM_PROCID"):
        if var in os.environ:
            try:
                return int(os.environ[var])
            except ValueError:
                continue  # not a number: try the next launcher's variable
    return 0


class _StderrHandler(logging.Handler):
    """Writes each record to whatever sys.stderr is at that moment (tests and tools swap it)."""

    def emit(self, record: logging.LogRecord) -> None:
        try:
            sys.stderr.write(self.format(record) + "\n")
            sys.stderr.flush()
        except Exception:  # logging's own policy: report through handleError, never raise
            self.handleError(record)


def configure(level: int | None = None) -> logging.Logger:
    """Set up the 'pice' logger once: '[rank R] message' on stderr."""
    rank = launch_rank()
    log = logging.getLogger("pice")
    if not log.handlers:
        handler = _StderrHandler()
        handler.setFormatter(logging.Formatter(f"pice [rank {rank}] %(levelname)s: %(message)s"))
        log.addHandler(handler)
        log.propagate = False
    log.setLevel(level if level is not None else (logging.INFO if rank == 0 else logging.WARNING))
    return log
