"""A short broken-ice run of the moored Kulluk (jobs/kulluk_2017_clearance70.toml, a 200 m field,
quasi-static lines, 12 s) through the user's commands: `pice run`, `pice export --vtk` (a floes block
per snapshot, every floe a closed prism) and `pice plot` (the mooring load with its spectrum and
events, and the render). Checks that the outputs exist and hold what the run file holds."""

from __future__ import annotations

import pathlib

import h5py
import meshio
import numpy as np
from launch import run_cmd
from pice.cli import main

JOBS = pathlib.Path(__file__).resolve().parents[2] / "jobs"


def _short_kulluk(folder: pathlib.Path) -> pathlib.Path:
    text = (JOBS / "kulluk_2017_clearance70.toml").read_text()
    for old, new in (("area = [-2045.0, -120.0, -45.0, 120.0]", "area = [-245.0, -120.0, -45.0, 120.0]"),
                     ("duration = 4000.0", "duration = 12.0"), ("snapshots = 41", "snapshots = 3"),
                     ("series_every = 200", "series_every = 20"), ('model = "dem"', 'model = "quasi_static"'),
                     ("velocity = [0.4, 0.0]       # [m/s]", "velocity = [2.0, 0.0]       # [m/s]")):
        assert old in text, old
        text = text.replace(old, new)
    job = folder / "kulluk.toml"
    job.write_text(text)
    return job


def test_a_moored_kulluk_in_floes_runs_exports_and_plots(tmp_path):
    job = _short_kulluk(tmp_path)
    out = tmp_path / "k.h5"
    assert main(["run", str(job), "-o", str(out)]) == 0
    with h5py.File(out) as f:
        s = f["series"]
        assert f.attrs["status"] == "finished"
        assert s["floe_structure_contacts"][:].max() > 0, "the floes (2 m/s) must reach the hull"
        assert np.abs(s["mooring_force"][:, 0, 0]).max() > 1e4
        n = len(f["snapshots/00000/floe_pose"])
        poly = f["snapshots/00000/floe_polygon_start"][:]
        assert len(poly) == n + 1
    run_cmd(["pice", "export", str(out), "--vtk", str(tmp_path / "vtk")])
    mesh = meshio.read(tmp_path / "vtk" / "floes_00002.vtu")
    assert len(np.unique(mesh.cell_data["floe"][0])) == n
    plots = tmp_path / "plots"
    assert main(["plot", str(out), "--out", str(plots), "--no-render", "--skip", "0"]) == 0
    assert (plots / "mooring_load.png").stat().st_size > 10_000
    events = (plots / "events.csv").read_text().splitlines()
    assert events[0].startswith("start [s],end [s],ice_max [N],mooring_max [N]") and len(events) >= 2
