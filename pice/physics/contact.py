"""Contact parameters: linear spring-dashpot with a damping ratio from the restitution coefficient."""

from __future__ import annotations

import math

import numpy as np


def damping_ratio_from_restitution(e: float) -> float:
    """Damping ratio zeta of a linear spring-dashpot whose normal restitution coefficient is e (0 < e <= 1)."""
    if e >= 1.0:
        return 0.0
    le = math.log(e)
    return -le / math.sqrt(math.pi ** 2 + le * le)


def contact_params(job, *, bond_kn: float) -> np.ndarray:
    """[k_n, k_t, zeta, mu] for ice-ice contact; k_n defaults to the bond's normal spring [N/m]."""
    c = job.contact
    kn = c.normal_stiffness if c.normal_stiffness is not None else bond_kn
    return np.array([kn, c.stiffness_ratio * kn, damping_ratio_from_restitution(c.restitution), c.friction])
