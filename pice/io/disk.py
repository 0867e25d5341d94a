"""The disk side of writing a run file: whether a path may become one, free space, and an error's words.

A write is refused before HDF5 meets a full disk (free space checked against the data plus
SPACE_MARGIN); an OS or HDF5 error is turned into the operating system's words and a hint.
"""

from __future__ import annotations

import errno
import os
import pathlib
import re

import numpy as np

#: bytes that must stay free beyond a write's own data: the HDF5 metadata flushed with it. Checked
#: before every write, so a disk that fills up stops the run cleanly before HDF5 meets ENOSPC.
SPACE_MARGIN = 256 * 1024


_FULL = (errno.ENOSPC, errno.EFBIG, errno.EDQUOT)


def reason(exc: BaseException) -> str:
    """The operating system's words for an h5py/OS error ("No space left on device"), else the text."""
    if isinstance(exc, OSError) and exc.errno and exc.strerror:
        return exc.strerror
    text = str(exc)
    m = re.search(r"errno = (\d+)", text)
    if m and int(m.group(1)):
        return os.strerror(int(m.group(1)))
    for code in (errno.ENOSPC, errno.EDQUOT, errno.EFBIG, errno.EACCES, errno.EROFS, errno.ENOENT, errno.EIO):
        if os.strerror(code) in text:  # e.g. inside an MPI-IO error stack
            return os.strerror(code)
    m = re.search(r"error message = '([^']+)'", text)
    return m.group(1) if m else " ".join(text.split())


def hint(reason: str) -> str:
    if any(os.strerror(e) in reason for e in _FULL):
        return ("the disk is full (or a size limit or quota was reached): free space or choose another "
                "output with -o")
    return "check that the file system is writable, or choose another output with -o"


def free_bytes(folder: pathlib.Path) -> int | None:
    try:
        st = os.statvfs(folder)
    except OSError:
        return None
    return st.f_bavail * st.f_frsize


def nbytes(*arrays) -> int:
    return int(sum(np.asarray(a).nbytes for a in arrays))


def refusal(path: pathlib.Path, overwrite: bool) -> str | None:
    """Why ``path`` cannot become a new run file (None: go ahead). Creates missing parent folders."""
    if path.is_dir():
        return f"{path}: is a directory; give a file name with -o"
    if path.exists() and not overwrite:
        return f"{path}: already exists; pass --overwrite to replace it or choose another output with -o"
    for folder in (path.parent, *path.parent.parents):
        if folder.exists():
            if not folder.is_dir():
                return (f"{path}: cannot create the run file ({folder} is a file, not a folder); "
                        "choose a writable path with -o")
            break
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        return (f"{path}: cannot create its folder {path.parent} ({exc.strerror or exc}); "
                "choose a writable path with -o")
    return None
