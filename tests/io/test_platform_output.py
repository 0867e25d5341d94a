"""The platform in the output (issues 4 and 5): a checkpoint with a body and its lines restarts bit for
bit; the run file's series carry the pose, the ice load with its extremes between rows and the line
tensions; the VTK hull is the body-frame mesh moved by the snapshot's pose (x = x_cg + R(q) p).
The scene: tests/scenes.py, barge_job.
"""

from __future__ import annotations

import h5py
import meshio
import numpy as np
import pytest
from scenes import barge_job, job_from_text

from pice.io.checkpoint import read_checkpoint, write_checkpoint
from pice.io.vtk_export import export_vtk
from pice.job import load_job
from pice.kernels.geometry import rotation_matrix
from pice.runner import run_job
from pice.simulation import Simulation


@pytest.mark.parametrize("model", ["dem", "quasi_static"])
def test_restart_with_body_and_lines_is_bit_for_bit(tmp_path, model):
    """Checkpoint after 300 steps, go on 300 more; a restart from the checkpoint ends in the same
    body pose, line nodes, ice positions and the load peaks since the last series row, bit for bit (the
    issue 5 contract, now with a platform)."""
    job = job_from_text(barge_job(duration=0.06, current=0.5, drag=1.0, mooring=model), base_dir=tmp_path)
    sim = Simulation(job)
    sim.advance(300)
    ckpt = write_checkpoint(sim, tmp_path / "c.ckpt.h5")
    sim.rebuild_for_checkpoint()
    sim.advance(300)
    again = Simulation.from_checkpoint(job, read_checkpoint(ckpt))
    again.advance(300)
    a, b = sim.platform, again.platform
    assert np.array_equal(a.bodies[0].x, b.bodies[0].x) and np.array_equal(a.bodies[0].q, b.bodies[0].q)
    assert np.array_equal(a.polylines()[0], b.polylines()[0])
    assert np.array_equal(a.fairlead_tensions(), b.fairlead_tensions())
    assert np.array_equal(sim.p.x[np.argsort(sim.p.gid)], again.p.x[np.argsort(again.p.gid)])
    # the loads' sums and extremes since the last series row (none taken here: the set-up's loads and
    # 600 steps') are in the checkpoint, so the next row's mean covers all its steps after a restart too
    peaks, peaks_again = sim.peaks.take(), again.peaks.take()
    assert peaks["n"] == peaks_again["n"] == 601
    for name in ("ice_sum", "ice_max", "ice_min", "tension_max"):
        assert np.array_equal(peaks[name], peaks_again[name]), name


def test_run_file_and_vtk_carry_the_platform(tmp_path):
    """Series rows hold the pose, the ice load with its extremes between rows and the line tensions;
    the VTK hull is the body-frame mesh moved by the snapshot's pose (x = x_cg + R(q) p)."""
    path = tmp_path / "platform.toml"
    path.write_text(barge_job(duration=0.1, series_every=200, mooring="dem"))
    out = tmp_path / "run.h5"
    run_job(load_job(path), output=out, progress=None)
    with h5py.File(out) as f:
        s = f["series"]
        n = len(s["time"])
        assert s["body_position"].shape == (n, 1, 3) and s["fairlead_tension"].shape == (n, 4)
        assert (s["ice_force_max"][:, 0, 0] >= s["ice_force"][:, 0, 0]).all()
        assert (s["ice_force_min"][:, 0, 0] <= s["ice_force"][:, 0, 0]).all()
        assert s["ice_force_max"][:, 0, 0].max() > 1e5
        np.testing.assert_allclose(s["fairlead_tension"][0], 20.0e3, rtol=0.01)  # the pretension
        # the "balance" mass as resolved at set-up: the 20 x 16 x 3 m^3 the box displaces plus the
        # lines' vertical pull of the t = 0 row (Archimedes)
        mass = f.attrs["body_mass"]
        assert f.attrs["bodies"] == 1 and f.attrs["mooring_lines"] == 4 and mass.shape == (1,)
        np.testing.assert_allclose(mass[0], 1025.0 * 960.0 + s["mooring_force"][0, 0, 2] / 9.81, rtol=1e-12)
        last = f["snapshots"][sorted(f["snapshots"])[-1]]
        pose = last["body_pose"][0]
        v0 = f["snapshots/00000/hull0_vertices"][()]
    res = export_vtk(out, tmp_path / "vtk")
    names = sorted(p.name for p in res["files"])
    assert "bodies_00002.vtu" in names and "moorings_00002.vtu" in names
    hull = meshio.read(tmp_path / "vtk" / "bodies_00002.vtu")
    np.testing.assert_allclose(hull.points, v0 @ rotation_matrix(pose[3:7]).T + pose[:3], atol=1e-12)
    lines = meshio.read(tmp_path / "vtk" / "moorings_00002.vtu")
    assert len(lines.cells_dict["line"]) == 4 * 12  # 120 m lines in 10 m elements
