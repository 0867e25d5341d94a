"""Output users open: the XDMF beside the run, `pice export --vtk`, `pice plot` and the run summary.

One tiny run (a 6 m x 4 m sheet pushed onto a 45-degree plane, plus a triangle and a mesh wall off
to the side) is made once for the module; every check reads it back with standard readers.
"""

import types
import xml.etree.ElementTree as ET

import h5py
import meshio
import numpy as np
import pytest
from scenes import slope_job

from pice.cli import main

JOB = slope_job(duration=0.1, snapshots=4) + """[[walls]]
name = "side_triangle"
type = "triangle"
vertices = [[0.0, 8.0, -1.0], [4.0, 8.0, -1.0], [2.0, 8.0, 2.0]]
[[walls]]
name = "side_panel"
type = "mesh"
file = "panel.stl"
"""


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    d = tmp_path_factory.mktemp("export")
    # a vertical 4 m square at y = -3 m (two triangles), well clear of the sheet
    panel = meshio.Mesh(np.array([[0.0, -3.0, -2.0], [4.0, -3.0, -2.0], [4.0, -3.0, 2.0], [0.0, -3.0, 2.0]]),
                        [("triangle", np.array([[0, 1, 2], [0, 2, 3]]))])
    meshio.write(d / "panel.stl", panel)
    job = d / "tiny.toml"
    job.write_text(JOB)
    out = d / "tiny.h5"
    import contextlib
    import io

    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        assert main(["run", str(job), "-o", str(out)]) == 0
    with h5py.File(out) as f:
        snaps = [f["snapshots"][k] for k in sorted(f["snapshots"])]
        data = [dict(time=float(g.attrs["time"]), **{k: g[k][()] for k in g}) for g in snaps]
    return types.SimpleNamespace(dir=d, path=out, snaps=data, stdout=buf.getvalue())


def _png(path):
    from PIL import Image

    with Image.open(path) as im:
        assert im.format == "PNG"
        return np.asarray(im.convert("RGB"))


def _not_blank(img):
    colours = len(np.unique(img.reshape(-1, 3), axis=0))
    assert colours > 50, f"only {colours} distinct colours"
    assert img.std() > 10.0


def test_summary_block(run):
    out = run.stdout
    assert f"pice: wrote {run.path}" in out and "ParaView" in out
    for words in ("wall time", "particle-steps/s", "broken bonds", "peak |F| on slope:", "peak |F| on side_panel:"):
        assert words in out, out
    with h5py.File(run.path) as f:
        peak = np.linalg.norm(f["series/wall_force"][:, 0], axis=1).max() / 1e3
    line = next(x for x in out.splitlines() if "peak |F| on slope:" in x)
    assert float(line.split(":")[1].split("kN")[0].replace(",", "")) == pytest.approx(peak, rel=1e-3)
    assert peak > 0


def test_xdmf_beside_the_run_opens_with_meshio_and_vtk(run):
    xdmf = run.path.with_suffix(".xdmf")
    assert xdmf.is_file()
    root = ET.parse(xdmf).getroot()  # well-formed XML
    assert root.tag == "Xdmf" and root.get("Version") == "3.0"
    n_snap = len(run.snaps)

    with meshio.xdmf.TimeSeriesReader(xdmf) as r:  # the last collection: the particles
        assert r.num_steps == n_snap
        for k, s in enumerate(run.snaps):
            r.mesh_grid = r.collection[k]  # points and cells of this step (they change every step)
            points, cells = r.read_points_cells()
            n = len(s["gid"])
            assert points.shape == (n, 3) and np.array_equal(points, s["x"])
            assert [c.type for c in cells] == ["vertex"] and len(cells[0].data) == n
            t, pd, _ = r.read_data(k)
            assert t == pytest.approx(s["time"])
            assert set(pd) == {"radius", "velocity", "angular_velocity", "kind", "gid", "crush_depth"}
            assert pd["velocity"].shape == (n, 3) and np.array_equal(pd["velocity"], s["v"])
            assert np.array_equal(pd["gid"], s["gid"])

    bonds_grid = next(g for g in root.find("Domain") if g.get("Name") == "bonds")
    with meshio.xdmf.TimeSeriesReader(xdmf) as r:  # the same reader on the bonds collection
        r.collection = list(bonds_grid)
        for k, s in enumerate(run.snaps):
            r.mesh_grid = r.collection[k]
            points, cells = r.read_points_cells()
            assert [c.type for c in cells] == ["line"]
            assert np.array_equal(cells[0].data, s["bonds"])  # gids 0..n-1 are the point indices
            assert r.read_data(k)[0] == pytest.approx(s["time"])

    import vtk  # ParaView's XDMF reader

    reader = vtk.vtkXdmfReader()
    reader.SetFileName(str(xdmf))
    reader.UpdateInformation()
    times = reader.GetOutputInformation(0).Get(vtk.vtkStreamingDemandDrivenPipeline.TIME_STEPS())
    assert np.allclose(times, [s["time"] for s in run.snaps])
    reader.UpdateTimeStep(times[-1])
    blocks = reader.GetOutputDataObject(0)
    names = [blocks.GetMetaData(i).Get(vtk.vtkCompositeDataSet.NAME()) for i in range(blocks.GetNumberOfBlocks())]
    assert names == ["bonds", "ice"]
    last = run.snaps[-1]
    assert blocks.GetBlock(0).GetNumberOfCells() == len(last["bonds"])
    assert blocks.GetBlock(1).GetNumberOfPoints() == len(last["gid"])
    assert blocks.GetBlock(1).GetPointData().GetArray("angular_velocity").GetNumberOfComponents() == 3


def test_xdmf_with_gids_that_are_not_indices(tmp_path):
    """The writer adds point_index/bond_index when gids are not 0..n-1, and the XDMF uses them."""
    from pice.io.run_file import RunFile
    from pice.io.xdmf import write_xdmf

    job = types.SimpleNamespace(text="", source="<test>")
    rf = RunFile(tmp_path / "g.h5", job=job)
    gid = np.array([30, 10, 20])
    x = np.arange(9.0).reshape(3, 3)
    rf.write_snapshot_arrays(0, time=0.5, step=1, arrays=dict(
        gid=gid, x=x, v=x, w=x, radius=np.ones(3), kind=np.zeros(3, np.int8), crush_depth=np.zeros(3), bonds=np.array([[20, 30], [10, 20]])))
    rf.close()
    with h5py.File(tmp_path / "g.h5") as f:
        assert np.array_equal(f["snapshots/00000/bond_index"][()], [[0, 1], [1, 2]])
    with meshio.xdmf.TimeSeriesReader(write_xdmf(tmp_path / "g.h5")) as r:
        points, cells = r.read_points_cells()
        assert np.array_equal(points, x[[1, 2, 0]]) and np.array_equal(cells[0].data, [0, 1, 2])
        bonds = next(g for g in ET.parse(tmp_path / "g.xdmf").getroot().find("Domain") if g.get("Name") == "bonds")
        r.mesh_grid = list(bonds)[0]
        assert np.array_equal(r.read_points_cells()[1][0].data, [[0, 1], [1, 2]])


def test_vtk_export_round_trip(run, capsys):
    import pyvista as pv

    out = run.dir / "vtk"
    assert main(["export", str(run.path), "--vtk", str(out)]) == 0
    assert ".pvd" in capsys.readouterr().out
    init = run.snaps[0]
    init_count = np.bincount(init["bonds"].ravel(), minlength=len(init["gid"]))
    for k, s in enumerate(run.snaps):
        n, m = len(s["gid"]), len(s["bonds"])
        path = out / f"ice_{k:05d}.vtu"
        mesh = meshio.read(path)
        assert mesh.points.shape == (n, 3) and np.allclose(mesh.points, s["x"])
        assert len(mesh.cells_dict["vertex"]) == n
        assert np.array_equal(mesh.cells_dict["line"], s["bonds"])
        for name, ref in (("radius", s["radius"]), ("velocity", s["v"]), ("angular_velocity", s["w"]),
                          ("kind", s["kind"]), ("gid", s["gid"])):
            assert np.array_equal(mesh.point_data[name], ref), name
        now = np.bincount(s["bonds"].ravel(), minlength=n)
        assert np.allclose(mesh.point_data["damage"], np.where(init_count > 0, 1 - now / np.maximum(init_count, 1), 0))

        grid = pv.read(path)
        assert grid.n_points == n
        assert np.count_nonzero(grid.celltypes == pv.CellType.LINE) == m
        assert np.count_nonzero(grid.celltypes == pv.CellType.VERTEX) == n
        assert set(grid.point_data.keys()) >= {"radius", "velocity", "angular_velocity", "kind", "gid", "damage"}
        assert grid.point_data["velocity"].shape == (n, 3)

    walls = pv.read(out / "walls.vtu")  # plane patch (2), triangle (1), mesh (2)
    assert walls.n_cells == 5 and np.all(walls.celltypes == pv.CellType.TRIANGLE)
    assert list(walls.cell_data["wall"]) == [0, 0, 1, 2, 2]
    assert meshio.read(out / "walls.vtu").cells_dict["triangle"].shape == (5, 3)
    ice = np.concatenate([run.snaps[0]["x"], run.snaps[-1]["x"]])
    plane = walls.extract_cells([0, 1])
    assert plane.bounds[3] - plane.bounds[2] > ice[:, 1].max() - ice[:, 1].min()  # the patch spans the ice

    pvd = out / "tiny.pvd"
    sets = ET.parse(pvd).getroot().find("Collection").findall("DataSet")
    ice_sets = [d for d in sets if d.get("name") == "ice"]
    assert [d.get("file") for d in ice_sets] == [f"ice_{k:05d}.vtu" for k in range(len(run.snaps))]
    assert np.allclose([float(d.get("timestep")) for d in ice_sets], [s["time"] for s in run.snaps])
    assert all((out / d.get("file")).is_file() for d in sets)
    reader = pv.get_reader(str(pvd))
    assert np.allclose(reader.time_values, [s["time"] for s in run.snaps])
    reader.set_active_time_point(len(run.snaps) - 1)
    blocks = reader.read()
    assert blocks[0].n_points == len(run.snaps[-1]["gid"]) and blocks[1].n_cells == 5


def test_bond_damage():
    from pice.io.run_reader import bond_damage

    init_gid = np.array([0, 1, 2, 3])
    init_counts = np.array([2, 2, 2, 0])
    dmg = bond_damage(np.array([0, 1, 2, 3]), np.array([[0, 1]]), init_gid, init_counts)
    assert np.allclose(dmg, [0.5, 0.5, 1.0, 0.0])


def test_plots_and_render_are_non_blank_pngs(run, capsys):
    from pice.postproc.plots import DPI, FIGSIZE
    from pice.postproc.render import WINDOW_SIZE

    out = run.dir / "plots"
    assert main(["plot", str(run.path), "--out", str(out)]) == 0
    assert "4 PNG" in capsys.readouterr().out
    for name in ("ice_loads", "energies", "broken_bonds"):
        img = _png(out / f"{name}.png")
        assert img.shape == (int(FIGSIZE[1] * DPI), int(FIGSIZE[0] * DPI), 3), name
        _not_blank(img)
    img = _png(out / "render_velocity.png")
    assert img.shape == (WINDOW_SIZE[1], WINDOW_SIZE[0], 3)
    _not_blank(img)

    from pice.postproc.render import render_snapshot

    small = render_snapshot(run.path, out / "first_damage.png", snapshot=0, color_by="damage", window_size=(400, 300))
    img = _png(small)
    assert img.shape == (300, 400, 3)
    assert img.std() > 10.0


def test_export_and_plot_errors(tmp_path, capsys):
    assert main(["export", str(tmp_path / "missing.h5"), "--vtk", str(tmp_path / "v")]) == 5
    assert "no such run file" in capsys.readouterr().err
    assert main(["plot", str(tmp_path / "missing.h5")]) == 5
    assert main(["export", str(tmp_path / "missing.h5")]) == 2


def test_the_progress_line_names_what_the_scene_has():
    """The progress line's figures come from the series row, for the physics the scene declares: a
    sheet's broken bonds, the rigid ice's contacts, the first body's ice load along x in kN (the mean
    over the row's steps where it is kept), and nothing of physics the scene lacks."""
    from pice.io.output import progress_figures

    body = types.SimpleNamespace(name="uikku")
    ship = types.SimpleNamespace(has_sheet=False, job=types.SimpleNamespace(bodies=[body], keel=object()))
    row = dict(broken_bonds=0.0, floe_contacts=12345.0, ice_force=np.array([[-1.0e5, 0.0, 0.0]]),
               ice_force_mean=np.array([[-2.5e5, 0.0, 0.0]]))
    assert progress_figures(ship, row) == "block contacts 12,345, ice load x on uikku -250 kN"
    sheet = types.SimpleNamespace(has_sheet=True, job=types.SimpleNamespace(bodies=[], keel=None))
    assert progress_figures(sheet, dict(broken_bonds=7.0)) == "broken bonds 7"
    assert progress_figures(sheet, dict(broken_bonds=7.0, floe_contacts=3.0)) == "broken bonds 7, floe contacts 3"
