"""Triangle meshes read with meshio (STL, OBJ, VTU, PLY, ...): the one place a mesh file is read.

Wall meshes (physics/walls.py, and the export through io/run_reader.py) and hull meshes (the
bodies' set-up) call ``read_triangle_mesh`` and word its ValueError for the key that named the file.
"""

from __future__ import annotations

import contextlib
import io
import pathlib
import warnings

import numpy as np


class NoTrianglesError(ValueError):
    """The file was read but holds no triangle cells."""


def read_triangle_mesh(path: str | pathlib.Path) -> tuple[np.ndarray, np.ndarray]:
    """(vertices (nv, 3) [m], triangles (nt, 3) int64) of a meshio-readable file.

    Raises ValueError with a one-line reason when the file cannot be read, NoTrianglesError (a
    ValueError) when it holds no triangles.
    """
    import meshio

    chatter = io.StringIO()  # meshio prints (and for some formats calls sys.exit) on a bad file
    try:
        with warnings.catch_warnings(), contextlib.redirect_stdout(chatter), contextlib.redirect_stderr(chatter):
            warnings.simplefilter("ignore")
            mesh = meshio.read(path)
    except (Exception, SystemExit) as exc:  # meshio raises many types for unreadable files
        text = chatter.getvalue() if isinstance(exc, SystemExit) else str(exc)
        raise ValueError("; ".join(" ".join(line.split()) for line in text.splitlines() if line.strip())
                         or type(exc).__name__) from None
    tris = [block.data for block in mesh.cells if block.type == "triangle"]
    if not tris:
        raise NoTrianglesError("no triangles in it")
    return np.asarray(mesh.points[:, :3], float), np.vstack(tris).astype(np.int64)
