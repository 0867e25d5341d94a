"""What made a result: the commit of the work tree pice runs from (git), for the files it writes and
the figures pice bench prints. None or "" where it is not known (an installed copy, no git)."""

from __future__ import annotations

import pathlib
import subprocess

REPO = pathlib.Path(__file__).resolve().parents[1]  # the work tree this package sits in (editable install)


def _git(*args: str) -> str | None:
    try:
        done = subprocess.run(["git", "-C", str(REPO), *args], capture_output=True, text=True, timeout=20)
    except (OSError, subprocess.SubprocessError):
        return None
    return done.stdout.strip() if done.returncode == 0 else None


def _commit_and_dirty() -> tuple[str | None, bool | None]:
    """The commit of the work tree (None outside git) and whether tracked files differ from it."""
    commit = _git("rev-parse", "HEAD")
    status = _git("status", "--porcelain", "--untracked-files=no") if commit else None
    return commit, (bool(status) if status is not None else None)


def code() -> dict:
    """The commit of the work tree, whether tracked files differ from it (dirty), the branch.

    ``commit`` is None outside a git work tree (an installed copy)."""
    commit, dirty = _commit_and_dirty()
    return {"commit": commit, "dirty": dirty,
            "branch": _git("rev-parse", "--abbrev-ref", "HEAD") if commit else None,
            "subject": _git("log", "-1", "--format=%s") if commit else None}


def commit_label() -> str:
    """The commit pice runs from, with "+dirty" when tracked files differ from it; "" outside git (two
    git calls: every run file and keel file records it)."""
    commit, dirty = _commit_and_dirty()
    return (commit or "") + ("+dirty" if commit and dirty else "")
