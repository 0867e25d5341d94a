"""Off-screen pyvista render of one snapshot of a run: spheres coloured by speed or bond damage,
the intact bonds as thin lines, the walls as translucent grey surfaces, the floes coloured by speed
and the hulls in grey. Works headless.

Headless: the VTK wheels (9.4 and later) pick the render window at run time, trying X, then EGL,
then OSMesa. Without a display ``render_snapshot`` asks for EGL directly when libEGL is installed
(``VTK_DEFAULT_OPENGL_WINDOW=vtkEGLRenderWindow``: Mesa's llvmpipe renders on the CPU, no X server,
no GPU, and no "bad X server connection" warning from the X attempt); ``pyvista.OFF_SCREEN`` is set.
If the render still fails and an ``Xvfb`` binary exists, it starts a virtual framebuffer and retries.
"""

from __future__ import annotations

import os
import pathlib
import shutil

import numpy as np

from ..io.errors import OutputError, RunFileError
from ..io.run_reader import bond_point_indices, open_run

WINDOW_SIZE = (1280, 800)
COLOR_BY = ("velocity", "damage")


def _prefer_egl() -> None:
    """Without a display, render through EGL when libEGL is there (before any render window exists)."""
    import ctypes.util

    if not os.environ.get("DISPLAY") and "VTK_DEFAULT_OPENGL_WINDOW" not in os.environ \
            and ctypes.util.find_library("EGL"):
        os.environ["VTK_DEFAULT_OPENGL_WINDOW"] = "vtkEGLRenderWindow"


def _scene(run, key, color_by: str):
    import pyvista as pv

    from ..io.vtk_export import bodies_block, floes_block

    g = run.snapshot(key)
    x = g["x"][()]
    gid = g["gid"][()]
    solids = []  # floes coloured by speed, hulls grey (meshio meshes of the VTK export)
    for build, colour in ((floes_block, None), (bodies_block, "lightgray")):
        mesh = build(run, key)
        if mesh is not None:
            solid = pv.from_meshio(mesh)
            if colour is None:
                solid["speed [m/s]"] = np.linalg.norm(solid["velocity"], axis=1)
            solids.append((solid, colour))
    if not len(x):  # no level ice
        return None, "speed [m/s]", "viridis", None, None, float(g.attrs["time"]), solids
    pts = pv.PolyData(x)
    pts["radius"] = g["radius"][()]
    if color_by == "damage":
        label, values, cmap = "bond damage [-]", run.damage(key), "YlOrRd"
    else:
        label, values, cmap = "speed [m/s]", np.linalg.norm(g["v"][()], axis=1), "viridis"
    pts[label] = values
    ball = pv.Sphere(radius=1.0, theta_resolution=14, phi_resolution=10)
    spheres = pts.glyph(scale="radius", orient=False, geom=ball)
    bonds = None
    pairs = bond_point_indices(gid, g["bonds"][()])
    if len(pairs):
        bonds = pv.PolyData(x, lines=np.hstack([np.full((len(pairs), 1), 2), pairs]).ravel())
    walls = None
    tris, _ = run.wall_triangles()
    if len(tris):
        walls = pv.PolyData(tris.reshape(-1, 3), faces=np.hstack([np.full((len(tris), 1), 3),
                                                                  np.arange(3 * len(tris)).reshape(-1, 3)]).ravel())
    return spheres, label, cmap, bonds, walls, float(g.attrs["time"]), solids


def _draw(scene, out_png: pathlib.Path, window_size, title: str) -> None:
    import pyvista as pv

    spheres, label, cmap, bonds, walls, t, solids = scene
    pl = pv.Plotter(off_screen=True, window_size=list(window_size))
    try:
        pl.set_background("white")
        clim = [0.0, 1.0] if label.startswith("bond damage") else None
        bar = dict(title=label, color="black", vertical=True, position_x=0.88, position_y=0.2)
        if spheres is not None:
            pl.add_mesh(spheres, scalars=label, cmap=cmap, clim=clim, smooth_shading=True, scalar_bar_args=bar)
        for solid, colour in solids:
            if colour is None:  # floes
                pl.add_mesh(solid, scalars="speed [m/s]", cmap="viridis", scalar_bar_args=bar if spheres is None
                            else dict(title="floe speed [m/s]", color="black", vertical=True, position_x=0.05,
                                      position_y=0.2))
            else:
                pl.add_mesh(solid, color=colour, opacity=0.8)
        if bonds is not None:
            pl.add_mesh(bonds, color="dimgray", line_width=1.0, opacity=0.5)
        if walls is not None:
            pl.add_mesh(walls, color="lightsteelblue", opacity=0.55, show_edges=True, edge_color="slategray")
        pl.add_text(f"{title}   t = {t:.3f} s", position="upper_left", font_size=11, color="black")
        pl.view_vector((-1.0, -1.4, 1.1), viewup=(0.0, 0.0, 1.0))
        pl.reset_camera()
        pl.camera.zoom(1.25)
        pl.screenshot(str(out_png))
    finally:
        pl.close()


def render_snapshot(run_path, out_png, *, snapshot: int = -1, color_by: str = "velocity",
                    window_size=WINDOW_SIZE) -> pathlib.Path:
    """Render snapshot ``snapshot`` (index, default the last) of a run to ``out_png``; return its path."""
    _prefer_egl()
    import pyvista as pv

    if color_by not in COLOR_BY:
        raise ValueError(f"color_by must be one of {COLOR_BY}, not {color_by!r}")
    pv.OFF_SCREEN = True
    out_png = pathlib.Path(out_png)
    with open_run(run_path) as run:
        if not run.snapshots:
            raise RunFileError(f"{run.path}: the run file holds no snapshots to render")
        try:
            key = run.snapshots[snapshot]
        except IndexError:
            raise RunFileError(f"{run.path}: snapshot {snapshot} out of range (it holds "
                               f"{len(run.snapshots)})") from None
        scene = _scene(run, key, color_by)
        title = pathlib.Path(str(run.attrs.get("job_source", run.path))).stem
    try:
        out_png.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OutputError(f"{out_png.parent}: cannot create the output folder ({exc.strerror or exc})") from None
    try:
        _draw(scene, out_png, window_size, title)
    except OSError as exc:
        raise OutputError(f"{out_png}: cannot write ({exc.strerror or exc})") from None
    except RuntimeError:
        # no usable off-screen context: a virtual X framebuffer, when the machine has one
        if os.environ.get("DISPLAY") or not shutil.which("Xvfb"):
            raise
        pv.start_xvfb()
        _draw(scene, out_png, window_size, title)
    return out_png
