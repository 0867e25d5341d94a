"""Stable time step of the explicit integrator.

For velocity Verlet on a linear system the step is stable when dt < 2 / omega_max, omega_max^2 the
largest eigenvalue of M^-1 K. We bound it per element with the block Gershgorin theorem on the
mass-normalised stiffness of its z springs (bonds or contacts), each with normal k_n, shear k_s at
lever r, and rotational k_r = max(k_bend, k_twist):

    translation rows:  z [2 max(k_n, k_s)/m + 2 k_s r / sqrt(m I)]
    rotation rows:     z [2 (k_s r^2 + k_r)/I + 2 k_s r / sqrt(m I)]

plus k_wall/m for a wall contact. The bound is an upper bound on omega_max^2, so
dt_stable = 2/sqrt(bound) * (sqrt(1 + zeta^2) - zeta) (the last factor for dashpots at damping
ratio zeta) is a safe limit; `dt = "auto"` uses ``run.dt_safety`` (default 0.5) of it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class StepLimit:
    """The stability limit [s] and the step chosen [s], with what sets the limit."""

    stable: float
    chosen: float
    safety: float
    governed_by: str


def stable_step(*, mass: float, inertia: float, radius: float, coordination: int, springs,
                wall_stiffness: float = 0.0, damping_ratio: float = 0.0) -> tuple[float, str]:
    """Stability limit [s] for the lightest element with ``coordination`` neighbours.

    springs: iterable of (name, k_n [N/m], k_s [N/m], k_r [N m/rad]) for each kind of neighbour link;
    the stiffest of each term is used.
    """
    kn = max(s[1] for s in springs)
    ks = max(s[2] for s in springs)
    kr = max(s[3] for s in springs)
    m, inertia_, r, z = mass, inertia, radius, coordination
    coupling = 2.0 * ks * r / math.sqrt(m * inertia_)
    trans = z * (2.0 * max(kn, ks) / m + coupling) + wall_stiffness / m
    rot = z * (2.0 * (ks * r * r + kr) / inertia_ + coupling)
    lam = max(trans, rot)
    factor = math.sqrt(1.0 + damping_ratio ** 2) - damping_ratio
    which = "translation" if trans >= rot else "rotation"
    stiffest = max(springs, key=lambda s: max(s[1], s[2]))[0]
    return 2.0 / math.sqrt(lam) * factor, f"{which} of the lightest element (m = {m:.4g} kg) on {stiffest} springs"


def choose_step(*, requested, safety: float, stable: float, governed_by: str, allow_unstable: bool,
                source: str = "<job>") -> StepLimit:
    """Pick dt: ``safety`` x the limit for "auto"; refuse a requested dt above the limit unless allowed."""
    from ..errors import JobError

    if requested == "auto":
        return StepLimit(stable=stable, chosen=safety * stable, safety=safety, governed_by=governed_by)
    if requested > stable and not allow_unstable:
        raise JobError(f"{source}: run.dt = {requested}: above the stability limit {stable:.4g} s "
                       f"({governed_by}); use dt <= {stable:.4g} s or dt = \"auto\" "
                       "(run.allow_unstable_dt = true overrides, for testing only)")
    return StepLimit(stable=stable, chosen=float(requested), safety=float(requested) / stable,
                     governed_by=governed_by)
