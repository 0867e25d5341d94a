"""pice bench: the solver's speed on this machine, with the machine, the commit and the settings
written next to the figures (docs/performance.md, "Measuring").

    mpiexec -n R pice bench [--steps N] [--scene sheet|full|both] [--job JOB] [--restart CHECKPOINT] [--json PATH]

* ``sheet``: particle-steps per second of the 92,000-element benchmark sheet (bench/sheet.py) on the
  R ranks it is launched with, and the split of one step into its parts (pice/timers.py);
* ``full``: the reference scene (jobs/zhu_ji_2022_semisub.toml as written: its recommended setting)
  over a window of N steps after a warm-up, as wall time per simulated second and the projected
  hours for its 200 s, and the split of its step; with ``--restart`` the window starts from a
  checkpoint of the job's run (its later phase, with fracture and crushing under way).

Figures are only comparable when taken on a quiet machine (nothing else running).
"""

from __future__ import annotations

import datetime
import pathlib

from ..provenance import REPO, code
from .machine import machine, software
from .sheet import BROKEN, SHEET_LENGTH, SHEET_WIDTH

#: the reference scene at its recommended setting (the job file as written)
REFERENCE_JOB = REPO / "jobs" / "zhu_ji_2022_semisub.toml"
FORMAT = 1  # of the JSON file: raised when a key changes meaning

SCENES = ("sheet", "full", "both")


def run_bench(*, scene: str = "both", steps: int = 500, warmup: int = 20, job=None, length: float = SHEET_LENGTH,
              width: float = SHEET_WIDTH, broken: int = BROKEN, json_path=None, restart=None,
              comm=None) -> dict | None:
    """Measure ``scene`` ("sheet", "full" or "both") on the ranks of ``comm`` (collective) and write the
    JSON file (rank 0). ``steps`` per window, ``warmup`` steps before them; ``job`` the full scene's
    job file (default REFERENCE_JOB), ``restart`` a checkpoint of its run to start from (None: t = 0);
    ``length``, ``width`` [m] and ``broken`` bonds of the sheet.
    Returns the result on rank 0 (with "json": the file written), None on the other ranks."""
    from ..errors import JobError
    from ..parallel.comm import mpi_library_version, world
    from .measure import measure_full, measure_sheet
    from .report import default_json_path, write_json

    comm = comm if comm is not None else world()
    if scene not in SCENES:
        raise ValueError(f"scene {scene!r}: one of {', '.join(SCENES)}")
    job_path = pathlib.Path(job) if job else REFERENCE_JOB
    if scene != "sheet" and not job_path.is_file():
        raise JobError(f"{job_path}: the full scene's job file was not found: give it with --job PATH")
    if restart is not None and not pathlib.Path(restart).is_file():
        raise JobError(f"--restart {restart}: no such checkpoint; give a checkpoint of the job's run "
                       "(run.checkpoint, default <run>.ckpt.h5)")
    result = None
    if comm.rank == 0:
        result = {"format": FORMAT, "created_utc": datetime.datetime.now(datetime.timezone.utc).isoformat(
                  timespec="seconds"), "ranks": comm.size, "machine": machine(),
                  "software": software(mpi_library_version()), "code": code()}
        result["settings"] = {"scene": scene, "steps": steps, "warmup": warmup,
                              "sheet": {"length": length, "width": width, "broken": broken},
                              "job": str(job_path), "restart": str(restart) if restart else None}
    path = pathlib.Path(json_path) if json_path else None
    if path is None and comm.rank == 0:
        path = default_json_path(result)
    path = pathlib.Path(comm.bcast(str(path)))
    if scene in ("sheet", "both"):
        sheet = measure_sheet(comm, steps=steps, warmup=warmup, length=length, width=width, broken=broken)
        if result is not None:
            result["sheet"] = sheet
    if scene in ("full", "both"):
        if comm.rank == 0:
            path.parent.mkdir(parents=True, exist_ok=True)
        comm.barrier()
        full = measure_full(comm, job_path, steps=steps, warmup=warmup,
                            scratch=path.with_name(path.stem + "_scratch.h5"), restart=restart)
        if result is not None:
            result["full"] = full
    if result is None:
        return None
    result["machine"]["load_average_after"] = _load()
    result["json"] = str(write_json(result, path))
    return result


def _load() -> list[float] | None:
    import os

    try:
        return [round(v, 2) for v in os.getloadavg()]
    except OSError:
        return None
