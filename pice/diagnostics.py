"""What a simulation reports: its energy budget, the series row, and the facts `pice check` prints.

Each function reads a Simulation and returns plain numbers; those that reduce over ranks are
collective (every rank calls them, every rank gets the totals).
"""

from __future__ import annotations

import numpy as np

ENERGY_NAMES = ("kinetic_energy", "rotational_energy", "gravity_energy", "buoyancy_energy", "bond_energy",
                "contact_energy", "wall_energy")


PLATFORM_ENERGY_NAMES = ("hull_contact_energy", "body_kinetic_energy", "mooring_kinetic_energy",
                         "mooring_elastic_energy")


def energies(sim) -> dict[str, float]:
    """Energy budget [J], summed over the ranks (collective), and its total.

    The ice: kinetic, rotational, gravity and buoyancy potentials, bonds, contacts, walls. With
    bodies also the elastic energy of the ice-hull contacts and (rank 0's) the bodies' kinetic energy
    and the mooring lines' kinetic and elastic energies. The hydrostatics and drag of the bodies and
    lines are external work, not counted: the total is conserved only by a scene without them.
    """
    p, n = sim.p, sim.p.nlocal
    ke = 0.5 * float(np.sum(p.mass[:n] * np.einsum("ij,ij->i", p.v[:n], p.v[:n])))
    kr = 0.5 * float(np.sum(p.inertia[:n] * np.einsum("ij,ij->i", p.w[:n], p.w[:n])))
    pg = float(np.sum(p.mass[:n] * sim.gravity * p.x[:n, 2]))
    pb = sim.water_term.buoyancy_energy(p) if sim.water_term is not None else 0.0
    eb = sim.bond_term.energy(p) if sim.bond_term is not None else 0.0
    values, names = [ke, kr, pg, pb, eb, sim.c.contact_energy, sim.c.wall_energy], ENERGY_NAMES
    if sim.hull_term is not None:
        platform = sim.platform.energies() if sim.platform is not None else {}
        values += [sim.hull_term.energy] + [platform.get(k, 0.0) for k in PLATFORM_ENERGY_NAMES[1:]]
        names += PLATFORM_ENERGY_NAMES
    parts = sim.comm.sum(np.array(values))
    out = {k: float(v) for k, v in zip(names, parts)}
    total = float(parts.sum())
    if sim.floes is not None:  # the same on every rank: not summed
        out["floe_kinetic_energy"] = sim.floes.kinetic_energy()
        total += out["floe_kinetic_energy"]
    out["total_energy"] = total
    return out


def series_row(sim) -> dict[str, np.ndarray | float]:
    """One row of /series (collective): counts, energies, wall loads, the drive, the bodies and lines."""
    c = sim.c
    counts = sim.comm.sum(np.array([sim.p.bond_count(), c.broken, c.contacts], dtype=np.float64))
    row = dict(time=c.time, step=float(c.step), bonds=counts[0], broken_bonds=counts[1], contacts=counts[2])
    # the logged breaks so far by failure mode (kernels.bonds: 1 tension/bending, 2 shear/twist,
    # 3 compression, 4 crushed through)
    modes = np.bincount(np.fromiter((e[4] for e in c.events), np.int64, len(c.events)), minlength=5)[1:5]
    row["broken_by_mode"] = sim.comm.sum(modes.astype(np.float64))
    row.update(energies(sim))
    loads = sim.wall_loads()
    if loads is not None:
        row["wall_force"] = loads[:, :3]
        row["wall_moment"] = loads[:, 3:]
    if sim.floes is not None:
        row.update(sim.floes.series_entries())
    if sim.job.crushing is not None and sim.has_sheet:  # contacts in plastic flow this step: ice-ice, ice-structure
        structure = sum(getattr(t, "crushing", 0) for t in (sim.walls, sim.hull_term) if t is not None)
        row["crushing_contacts"] = sim.comm.sum(np.array([sim.ice_contact_term.crushing, structure], dtype=np.float64))
        row["crushed_elements"] = float(sim.n_initial - sim.comm.sum(sim.p.nlocal))  # removed so far
    if sim.boundary_term is not None:  # the far field's push on the sheet [N]
        row["boundary_force"] = sim.comm.sum(sim.boundary_term.force)
        if sim.boundary_term.far_mass is not None:  # a finite far field's speed [m/s]
            row["far_field_speed"] = float(sim.boundary_term.velocity[0])
    if sim.platform is not None:
        from .platform.output import series_entries

        row.update(series_entries(sim.platform, sim.body_total, sim.peaks.take()))
    return row


def describe(sim) -> dict:
    """Facts for `pice check` and the run file's attributes (collective)."""
    p, b, limit = sim.p, sim.bond, sim.limit
    nbytes = sum(a.nbytes for a in vars(p).values() if isinstance(a, np.ndarray))
    out = dict(elements=int(sim.comm.sum(p.nlocal)), bonds=int(sim.comm.sum(p.bond_count())),
               layers=sim.sheet.n_layers, thickness_modelled=sim.sheet.actual_thickness, memory_bytes=nbytes,
               dt_stable=limit.stable, dt=sim.dt, dt_safety=limit.safety, dt_governed_by=limit.governed_by,
               steps_per_second=1.0 / sim.dt)
    if b is not None:
        out.update(bond_kn=b.kn, bond_ks=b.ks, bond_kb=b.kb, bond_kt=b.kt, normal_strength=b.normal_strength,
                   shear_strength=b.shear_strength, bond_friction=b.friction, element_mass=float(p.mass[0]))
    if sim.floes is not None:
        f = sim.floes.f
        out.update(floes=sim.floes.n, floe_mass_range=[float(f.mass.min()), float(f.mass.max())] if sim.floes.n
                   else [0.0, 0.0])
        if sim.job.floes is not None:
            out["floe_concentration"] = float(f.area.sum()) / _area(sim.job.floes.area)
    if sim.platform is not None:
        from .platform.output import describe as describe_platform

        out.update(describe_platform(sim.platform, sim.dt))
    return out


def runaway(sim, i, ratio: float, nonfinite: bool):
    """The InstabilityError of a runaway element ``i`` of this rank (None: another rank holds it),
    naming the step, the element and the likely cause."""
    from .errors import InstabilityError

    c, p = sim.c, sim.p
    if i is None:  # another rank holds the runaway element: it reports, we stop with it
        return InstabilityError(f"unstable at step {c.step}: reported by another rank")
    what = "a non-finite velocity (NaN/inf)" if nonfinite else f"a displacement of {ratio:.3g} radii in one step"
    if sim.dt > sim.limit.stable:
        cause = (f"run.dt = {sim.dt:.4g} s is above the stability limit {sim.limit.stable:.4g} s "
                 f"({sim.limit.governed_by}); use dt = \"auto\"")
    else:
        cause = ("a force spike: overlapping elements in the initial geometry, a load too large for "
                 "the elements, or a wall/contact stiffness far above the bond stiffness")
    return InstabilityError(
        f"unstable at step {c.step} (t = {c.time:.6g} s): element gid {int(p.gid[i])} at "
        f"{np.array2string(p.x[i], precision=3)} m shows {what}; likely cause: {cause}")


def _area(box) -> float:
    """Area [m^2] of (x0, y0, x1, y1)."""
    return (box[2] - box[0]) * (box[3] - box[1])
