"""What a benchmark figure was measured on: the machine, the software and the commit (pice bench).

Read from /proc on Linux (None where a fact is not available), from the installed packages'
metadata (nothing is imported for its version) and from git in the work tree of this package
(pice/provenance.py).
"""

from __future__ import annotations

import os
import pathlib
import platform
import sys
from importlib import metadata


def _cpuinfo() -> list[dict[str, str]]:
    """/proc/cpuinfo as one dict per logical CPU (empty when unreadable)."""
    try:
        text = pathlib.Path("/proc/cpuinfo").read_text()
    except OSError:
        return []
    cpus = []
    for block in text.strip().split("\n\n"):
        entry = {}
        for line in block.splitlines():
            key, sep, value = line.partition(":")
            if sep:
                entry[key.strip()] = value.strip()
        cpus.append(entry)
    return cpus


def _memory_gib() -> float | None:
    """Total memory [GiB] from /proc/meminfo."""
    try:
        for line in pathlib.Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemTotal:"):
                return int(line.split()[1]) * 1024 / 2**30
    except (OSError, ValueError, IndexError):
        return None
    return None


def machine() -> dict:
    """CPU model, logical CPUs, physical cores, memory [GiB], the load average before the measurement."""
    cpus = _cpuinfo()
    model = next((c.get("model name") or c.get("Processor") or c.get("Hardware") for c in cpus
                  if c.get("model name") or c.get("Processor") or c.get("Hardware")), None)
    cores = {(c.get("physical id", "0"), c.get("core id")) for c in cpus if "core id" in c}
    try:
        usable = len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        usable = os.cpu_count()
    try:
        load = [round(v, 2) for v in os.getloadavg()]
    except OSError:
        load = None
    return {"cpu_model": model or platform.processor() or None, "logical_cpus": os.cpu_count(),
            "usable_cpus": usable, "physical_cores": len(cores) or None, "memory_gib": _memory_gib(),
            "system": f"{platform.system()} {platform.release()}", "hostname": platform.node(),
            "load_average_before": load}


def _version(name: str) -> str | None:
    try:
        return metadata.version(name)
    except metadata.PackageNotFoundError:
        return None


def software(mpi_library: str | None) -> dict:
    """Versions of python, numpy, numba, mpi4py, the MPI library (None on one rank), h5py and pice."""
    return {"python": platform.python_version(), "implementation": sys.implementation.name,
            "numpy": _version("numpy"), "numba": _version("numba"), "mpi4py": _version("mpi4py"),
            "mpi_library": mpi_library, "h5py": _version("h5py"), "pice": _version("pice")}
