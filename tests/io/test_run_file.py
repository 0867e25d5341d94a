"""`pice run`: the HDF5 run file holds the job, a time series, snapshots and the broken-bond log."""

import h5py
import numpy as np
from scenes import slope_job

from pice.cli import main
from pice.provenance import code

JOB = slope_job(duration=0.1, snapshots=3)


def test_run_writes_series_snapshots_and_attributes(tmp_path, capsys):
    job = tmp_path / "tiny.toml"
    job.write_text(JOB)
    out = tmp_path / "tiny.h5"
    assert main(["run", str(job), "-o", str(out)]) == 0
    with h5py.File(out) as f:
        assert f.attrs["status"] == "finished"
        assert "duration = 0.1" in f.attrs["job_text"]
        assert f.attrs["ranks"] == 1
        # the code that made it: this checkout's commit (with +dirty when edited), "" outside git
        assert f.attrs["commit"].split("+")[0] == (code()["commit"] or "")
        s = f["series"]
        n = len(s["time"])
        dt = f.attrs["dt"]
        steps = int(np.ceil(0.1 / dt - 1e-9))
        assert n == 1 + int(np.ceil(steps / 2))  # t = 0, every 2 steps, and the last step
        for key in ("kinetic_energy", "bonds", "broken_bonds", "total_energy"):
            assert s[key].shape == (n,)
        assert s["wall_force"].shape == (n, 1, 3)
        assert np.all(np.isfinite(s["total_energy"][:]))
        # the sheet reaches the slope: the wall is pushed along +x and down (the ice rides up),
        # inside the Coulomb cone of the wall friction 0.1: on a 45-degree slope with normal
        # (-1, 0, 1)/sqrt(2), |F_tangential| = |Fx + Fz|/sqrt(2) <= 0.1 |F_normal| = 0.1 |Fx - Fz|/sqrt(2)
        fw = s["wall_force"][:, 0, :]
        k = int(np.argmax(fw[:, 0]))
        assert fw[k, 0] > 0 and fw[k, 2] < 0
        assert abs(fw[k, 0] + fw[k, 2]) <= 0.1 * abs(fw[k, 0] - fw[k, 2]) * (1 + 1e-6)
        snaps = sorted(f["snapshots"])
        assert len(snaps) == 3
        last = f["snapshots"][snaps[-1]]
        assert np.all(np.diff(last["gid"][:]) > 0)  # sorted by gid
        assert last["x"].shape == (len(last["gid"]), 3)
        bonds = last["bonds"][:]
        assert bonds.shape[1] == 2 and np.all(bonds[:, 0] < bonds[:, 1])
        assert len(bonds) == s["bonds"][-1]
    assert "wrote" in capsys.readouterr().out


def test_existing_run_file_is_not_replaced_without_overwrite(tmp_path, capsys):
    job = tmp_path / "tiny.toml"
    job.write_text(JOB)
    out = tmp_path / "tiny.h5"
    out.write_bytes(b"precious")
    assert main(["run", str(job), "-o", str(out)]) == 4
    assert out.read_bytes() == b"precious"
    assert "--overwrite" in capsys.readouterr().err


def test_series_rows_held_in_blocks_are_all_written_in_order(tmp_path, monkeypatch):
    """Rows are written SERIES_BLOCK at a time, and what is held is written before a snapshot, at a
    flush (a checkpoint) and at the close: the file then holds every row in order, the same as row
    by row (block 1), including a key that first appears in a later row (zeros before it, as row by
    row) and a block cut short by a snapshot."""
    import types

    from pice.io import run_file
    from pice.io.run_file import RunFile

    job = types.SimpleNamespace(text="# synthetic\n", source="synthetic.toml")
    rows = [dict(time=0.1 * k, force=np.arange(3.0) * k) for k in range(23)]
    for row in rows[9:]:
        row["late"] = np.array([[1.0, 2.0]]) * row["time"]
    arrays = dict(gid=np.arange(2), x=np.zeros((2, 3)), v=np.zeros((2, 3)), w=np.zeros((2, 3)),
                  radius=np.ones(2), kind=np.zeros(2, np.int8), crush_depth=np.zeros(2), bonds=np.zeros((0, 2)))

    def write(path, block):
        monkeypatch.setattr(run_file, "SERIES_BLOCK", block)
        f = RunFile(path, job=job)
        for k, row in enumerate(rows):
            f.append_series(row)
            if k == 6:
                f.write_snapshot_arrays(0, time=row["time"], step=k, arrays=arrays)
                assert f.h5["series/time"].shape == (7,)  # written before the snapshot
            if k == 15:
                f.flush()
        f.close("finished")
        with h5py.File(path) as g:
            return {key: g["series"][key][()] for key in g["series"]}

    by_row, by_block = write(tmp_path / "a.h5", 1), write(tmp_path / "b.h5", 4)
    assert by_row.keys() == by_block.keys() == {"time", "force", "late"}
    for key in by_row:
        np.testing.assert_array_equal(by_block[key], by_row[key])
    np.testing.assert_array_equal(by_block["time"], [r["time"] for r in rows])
    np.testing.assert_array_equal(by_block["late"][:9], 0.0)
    np.testing.assert_array_equal(by_block["late"][9:], [r["late"] for r in rows[9:]])
