"""The job's rigid ice: its [floes] (physics/floe_system.py) or its [keel]'s settled blocks
(physics/keel.py), both FloeSystems; one entry for the Simulation, above both modules."""

from __future__ import annotations

from .floe_system import FloeSystem, floes_from_job
from .keel import keel_from_job


def rigid_pieces_from_job(job, hulls, poses, *, comm, base_dir=None) -> FloeSystem | None:
    """The job's rigid pieces: its [floes] (unless breakable: those are elements of the sheet), or its
    [keel]'s settled blocks, or None."""
    if job.floes is not None and not job.floes.breakable:
        return floes_from_job(job, hulls, poses, comm=comm)
    if job.keel is not None:
        return keel_from_job(job, hulls, poses, comm=comm, base_dir=base_dir)
    return None
