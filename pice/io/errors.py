"""The I/O package's errors: a run file that cannot be written (4) or read back (5).

Both end a command with a one-line message and their exit status (see pice/errors.py). They live
here, below every I/O module, so the writer (io/run_file.py), the parallel mode (io/mpio.py), the
reader (io/run_reader.py) and the exports can all raise them without importing one another.
"""

from __future__ import annotations

from ..errors import PiceError


class OutputError(PiceError):
    """The run file (or an export of it) cannot be created or written. Exit status 4.

    ``hard_exit``: a write failed inside HDF5, which then can neither flush nor close the file and
    crashes when the process ends (HDF5 1.10 and 2.0 alike); the command line ends the process
    with os._exit after the message. Everything flushed before the failure is in the file.
    """

    exit_code = 4
    hard_exit = False


class RunFileError(PiceError):
    """The run file to post-process cannot be read. Exit status 5."""

    exit_code = 5
