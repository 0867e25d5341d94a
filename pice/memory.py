"""Memory at set-up: what a job needs on each rank, what the ranks of this machine have, and the
refusal of a job that cannot fit, before anything large is allocated.

Every rank builds the whole sheet at set-up before it keeps its own part (simulation.Simulation),
so each rank needs the particle arrays of the whole sheet at once: the elements (counted from the
HCP lattice, scenes/level_ice.lattice_count) times the bytes of one element, measured on a small sheet of the same lattice with the same walls and bodies (the
arrays `pice check` sums as "memory (particles)"; the peak resident memory of set-up measured
0.85-0.9 of that figure above the interpreter's own, because zeroed pages are only mapped once
written). What the ranks have: MemAvailable of /proc/meminfo, lowered to what the memory cgroup (a
container, a batch job) still allows, shared by the ranks on this node (MPI_LOCALNRANKS of MPICH's
Hydra, OMPI_COMM_WORLD_LOCAL_SIZE of Open MPI, else every rank of the job).
"""

from __future__ import annotations

import os
import pathlib

import numpy as np

from .errors import JobError



def element_count(job) -> int:
    """Elements [-] of the job's sheet, counted from its lattice without building it."""
    from .scenes.level_ice import lattice_count, layer_count

    ice = job.ice
    d = ice.element_diameter
    layers = 1 if ice.element_volume == "cell" else layer_count(thickness=ice.thickness, element_diameter=d)
    if job.floes is not None and job.floes.breakable:  # at most the lattice over the floes' area
        x0, y0, x1, y1 = job.floes.area
        return lattice_count(length=x1 - x0, width=y1 - y0, d=d, n_layers=layers)
    return lattice_count(length=ice.length, width=ice.width, d=d, n_layers=layers)


def _wall_entries(job, base_dir) -> int:
    """Wall triangles and planes the contact history is kept for (a mesh wall: one per face)."""
    from .io.mesh import read_triangle_mesh

    n = 0
    for wall in job.walls:
        if wall.type != "mesh":
            n += 1
            continue
        try:
            n += len(read_triangle_mesh(pathlib.Path(base_dir or ".") / wall.file)[1])
        except (ValueError, OSError):  # reported when the walls are built
            n += 1
    return n


def bytes_per_element(job, base_dir=None) -> float:
    """Bytes [B] of every per-particle array for one element, as set-up allocates them: measured on
    a sheet of 3 x 3 elements of the job's lattice (same layers, bond slots, walls and bodies)."""
    from .scenes.level_ice import build_level_ice

    d = job.ice.element_diameter
    small = job.model_copy(update={"ice": job.ice.model_copy(update={"length": 3.0 * d, "width": 3.0 * d}),
                                   "floes": None})  # breakable floes: the same lattice
    p, _ = build_level_ice(small)
    p.allocate_dynamic(_wall_entries(job, base_dir), len(job.bodies))
    return sum(a.nbytes for a in vars(p).values() if isinstance(a, np.ndarray)) / p.n


def setup_bytes(job, base_dir=None) -> tuple[int, float]:
    """(elements [-], bytes [B] of particle arrays each rank holds at set-up: the whole sheet)."""
    n = element_count(job)
    return n, n * bytes_per_element(job, base_dir)


def available_bytes() -> float | None:
    """Bytes [B] this machine can still give (MemAvailable, capped by the memory cgroup); None when
    neither can be read."""
    found = []
    try:
        for line in pathlib.Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemAvailable:"):
                found.append(float(line.split()[1]) * 1024.0)
    except (OSError, ValueError, IndexError):
        found.clear()  # no readable /proc/meminfo: the cgroup limit alone, if any
    try:  # cgroup v2: this process's group, its limit and what it uses
        rel = next(line[3:] for line in pathlib.Path("/proc/self/cgroup").read_text().splitlines()
                   if line.startswith("0::"))
        group = pathlib.Path("/sys/fs/cgroup") / rel.strip().lstrip("/")
        limit = (group / "memory.max").read_text().strip()
        if limit != "max":
            found.append(float(limit) - float((group / "memory.current").read_text()))
    except (OSError, ValueError, StopIteration):
        return min(found) if found else None  # no cgroup v2 limit readable: /proc/meminfo alone
    return min(found) if found else None


def ranks_on_this_node(comm) -> int:
    """Ranks of this job sharing this machine's memory."""
    for key in ("MPI_LOCALNRANKS", "OMPI_COMM_WORLD_LOCAL_SIZE"):
        try:
            return max(1, int(os.environ[key]))
        except (KeyError, ValueError):
            continue
    return comm.size


def _size(nbytes: float) -> str:
    for unit, scale in (("TiB", 2.0 ** 40), ("GiB", 2.0 ** 30), ("MiB", 2.0 ** 20)):
        if nbytes >= scale:
            return f"{nbytes / scale:,.3g} {unit}"
    return f"{nbytes / 1024.0:,.3g} KiB"


def refuse_oversized(job, comm, base_dir=None) -> None:
    """JobError (on every rank; rank 0 decides) when the ranks on this machine together need more
    memory at set-up than it has available, naming the job's size, what it needs and the fix."""
    from .parallel.comm import on_root

    if job.ice is None:  # no sheet: floes and bodies are small
        return

    def check():
        available = available_bytes()
        if available is None:
            return
        n, need = setup_bytes(job, base_dir)
        ranks = ranks_on_this_node(comm)
        if need * ranks <= available:
            return
        ice = job.ice
        key, value = ("ice.length", ice.length) if ice.length >= ice.width else ("ice.width", ice.width)
        fix = "shorten the sheet (ice.length, ice.width)"
        if job.floes is not None and job.floes.breakable:  # the floes' area sets the lattice
            x0, y0, x1, y1 = job.floes.area
            key, value, fix = "floes.area", max(x1 - x0, y1 - y0), "shrink floes.area"
        # the ranks sharing this machine are named only when they are what exceeds it, so that one rank
        # and several give the same line for a sheet too large for any of them
        share = f"; its {ranks} ranks on this machine need {_size(need * ranks)}" if need <= available else ""
        raise JobError(f"{job.source}: {key} = {value:g}: the sheet of {n:.4g} elements needs {_size(need)} of "
                       f"particle arrays on each rank at set-up (every rank builds the whole sheet){share}, more than "
                       f"the {_size(available)} available on this machine; {fix} or use larger elements "
                       "(ice.element_diameter)")

    on_root(comm, check)
