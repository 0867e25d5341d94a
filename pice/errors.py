"""Exceptions that end a run with a one-line message and a documented exit status."""


class PiceError(Exception):
    """Base class: a user-facing problem; the CLI prints ``str(err)`` and exits with ``exit_code``."""

    exit_code = 1


class JobError(PiceError):
    """The job file is unreadable or invalid. Nothing has been written. Exit status 2."""

    exit_code = 2

    def __init__(self, lines):
        self.lines = [lines] if isinstance(lines, str) else list(lines)
        super().__init__("\n".join(self.lines))


class InstabilityError(PiceError):
    """The integration blew up (NaN or runaway motion); the run stopped cleanly. Exit status 3."""

    exit_code = 3


class RunInterrupted(PiceError):
    """SIGINT/SIGTERM stopped the run after a final checkpoint. Exit status 130 (as for Ctrl-C)."""

    exit_code = 130
