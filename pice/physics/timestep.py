"""Stable time step of the explicit integrator.

The limit is computed exactly for pice's step (velocity Verlet, rate terms at the half-step
velocity) on the infinite lattice of the sheet's elements, by Bloch waves
(physics/lattice_modes.py): the largest dt for which no mode of the linearised lattice grows. Every
neighbour link carries the stiffer of the bond and the contact springs in each direction (normal
k_n, shear k_s at the contact point, twisting and bending) and the stronger of their dashpots, so
the limit also holds once bonds have broken and contacts have taken their place. A structure
(walls, hulls, the far-field springs) adds a link to a fixed surface on every element, with its
normal and tangential springs and its normal dashpot.

Without dashpots the limit is 2 / omega_max. Dashpots lower it: for one mode the step is stable
when omega^2 dt^2 / 4 + c dt / 2 < 1; in the lattice the stiffest modes (rotation on tangential
springs) are not the most damped (translation on normal dashpots), and the exact limit lies
20-25 % above the bound that takes the two together. `dt = "auto"` uses ``run.dt_safety`` (default
0.5) of it. Assumption: no element gains more contacts than it had lattice neighbours (rafting
piles can; the health check stops such a run with a diagnostic).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .lattice_modes import exact_limit


@dataclass(frozen=True)
class StepLimit:
    """The stability limit [s] and the step chosen [s], with what sets the limit."""

    stable: float
    chosen: float
    safety: float
    governed_by: str


def stable_step(*, mass: float, inertia: float, d: float, n_layers: int, bond, contact,
                structure=None, damping_ratio: float = 0.0,
                contact_damping_ratio: float = 0.0) -> tuple[float, str]:
    """Stability limit [s] of the lattice with, per link, the stiffer of bond and contact springs
    and the stronger of their dashpots, computed exactly for the step (physics/lattice_modes.py).

    bond: (k_n, k_s, k_twist, k_bend); contact: (k_n, k_t); damping ratios of the bond dashpots and
    of the contact's normal dashpot (from its restitution). structure: None, or (k_n, k_t [N/m], c_n
    [N s/m]) of the stiffest link of an element to a structure (walls, hulls, far-field springs),
    put on every element. Returns (limit, what governs it).
    """
    kn = max(bond[0], contact[0])
    ks = max(bond[1], contact[1])
    z, m_red, i_red = damping_ratio, 0.5 * mass, 0.5 * inertia
    # the bond dashpots of BondParams.as_array and the contact's normal dashpot (kernels.contacts)
    cn = max(2 * z * math.sqrt(m_red * bond[0]), 2 * contact_damping_ratio * math.sqrt(m_red * contact[0]))
    dashpots = (cn, 2 * z * math.sqrt(m_red * bond[1]), 2 * z * math.sqrt(i_red * bond[2]),
                2 * z * math.sqrt(i_red * bond[3]))
    ground = None
    if structure is not None and structure[0] > 0.0:
        ground = ((structure[0], structure[1], 0.0, 0.0), (structure[2], 0.0, 0.0, 0.0))
    limit, undamped = exact_limit(mass=mass, inertia=inertia, d=d, n_layers=n_layers,
                                  springs=(kn, ks, bond[2], bond[3]), dashpots=dashpots, ground=ground)
    parts = ["bond" if bond[0] >= contact[0] else "contact"]
    if ks > bond[1]:
        parts.append("contact tangential")
    if ground is not None:
        parts.append("structure")
    damped = f", dashpots: {limit / undamped:.3g} of the undamped {undamped:.4g} s" if limit < undamped else ""
    return limit, (f"highest lattice mode of elements of {mass:.4g} kg with {' and '.join(parts)} "
                   f"springs (k_n {kn:.3g} N/m){damped}")


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


def sheet_time_step(job, p, sheet, bond, law, walls, hulls) -> StepLimit:
    """The step of a scene with a sheet: the limit of its lattice (``stable_step``) with every
    structure's link to an element, walls' and hulls' (k_n, k_t [N/m], damping ratio) and the far
    field's springs, taken on the lightest element; then ``choose_step`` with the job's run.dt."""
    push = job.ice.push
    m, inertia = float(p.mass.min()), float(p.inertia[int(np.argmin(p.mass))])
    # every structure's link to an element: (k_n, k_t [N/m], c_n [N s/m]), the element's own mass
    links = [(r[0], r[1], 2.0 * r[2] * math.sqrt(m * r[0])) 
             for r in [tuple(w) for w in walls] + [tuple(h) for h in hulls]]
    if push is not None and push.stiffness is not None:
        links.append((push.stiffness, 0.0, 2.0 * push.damping_ratio * math.sqrt(m * push.stiffness)))
    structure = tuple(max(link[k] for link in links) for k in range(3)) if links else None
    stable, why = stable_step(mass=m, inertia=inertia, d=sheet.spacing, n_layers=sheet.n_layers,
                              bond=(bond.kn, bond.ks, bond.kt, bond.kb), contact=(law.kn, law.kt),
                              structure=structure, damping_ratio=bond.damping_ratio, contact_damping_ratio=law.zeta)
    run = job.run
    return choose_step(requested=run.dt, safety=run.dt_safety, stable=stable, governed_by=why,
                       allow_unstable=run.allow_unstable_dt, source=job.source)
