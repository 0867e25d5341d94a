"""Parameters of the contact law (kernels/contact_law.py), built once at set-up.

``ContactLaw`` is the record for one kind of contact (ice-ice, one hull); walls carry one record
per wall in a structured array of ``CONTACT_LAW_RECORD``. Numba reads both by field name.
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np

from ..kernels.contacts import contact_forces
from ..kernels.pair_list import build_pair_list, insert_pairs, moved_beyond
from .iso19906 import crushing_pressure

ContactLaw = namedtuple("ContactLaw", ["kn", "kt", "zeta", "mu", "crushing_pressure"], defaults=[math.inf])
ContactLaw.__doc__ = """Linear spring-dashpot with Coulomb friction: kn, kt [N/m], damping ratio zeta, friction mu,
and the crushing pressure p_c [Pa] capping the normal force at p_c A_c (inf: elastic, no crushing)."""

CONTACT_LAW_RECORD = np.dtype([("kn", np.float64), ("kt", np.float64), ("zeta", np.float64), ("mu", np.float64),
                               ("crushing_pressure", np.float64)])


def damping_ratio_from_restitution(e: float) -> float:
    """Damping ratio zeta of a linear spring-dashpot whose normal restitution coefficient is e (0 < e <= 1)."""
    if e >= 1.0:
        return 0.0
    le = math.log(e)
    return -le / math.sqrt(math.pi ** 2 + le * le)


def tangential_ratio(job) -> float:
    """k_t / k_n of every contact: contact.stiffness_ratio, by default the ice's G / E = 1 / (2 (1 + nu)).

    The contact of two elements is elastic-perfectly-plastic (the crushing law): before the cap its
    normal spring is the ice's in-plane stiffness from E (the bond's k_n: compression across a crack
    feels the modulus of the intact sheet), and its tangential spring is the same block's shear
    stiffness, G A / L against E A / L (docs/crushing.md, "Contact stiffness")."""
    ratio = job.contact.stiffness_ratio
    nu = job.ice.poissons_ratio if job.ice is not None else 0.3  # sea ice's nu without a sheet
    return float(ratio) if ratio is not None else 1.0 / (2.0 * (1.0 + nu))


def contact_law(job, *, kn: float, friction: float, crushing_pressure: float = math.inf) -> ContactLaw:
    """The job's contact law ([contact]: stiffness ratio, restitution) with normal stiffness kn [N/m],
    and the crushing pressure [Pa] (inf: none)."""
    c = job.contact
    return ContactLaw(kn=float(kn), kt=float(tangential_ratio(job) * kn),
                      zeta=float(damping_ratio_from_restitution(c.restitution)), mu=float(friction),
                      crushing_pressure=float(crushing_pressure))


def ice_contact_law(job, *, bond_kn: float) -> ContactLaw:
    """The law of ice-ice contact; k_n defaults to the bond's normal spring [N/m]; with [crushing] the
    ice-ice crushing pressure is crushing.ice, else ice.compressive_strength."""
    c, crushing = job.contact, job.crushing
    pressure = math.inf
    if crushing is not None:
        pressure = crushing.ice if crushing.ice is not None else job.ice.compressive_strength
    return contact_law(job, kn=c.normal_stiffness if c.normal_stiffness is not None else bond_kn,
                       friction=c.friction, crushing_pressure=pressure)


def structure_crushing_pressure(job, *, width: float | None) -> float:
    """The crushing pressure [Pa] of the ice on a wall or hull of ``width`` [m] (inf without [crushing]):
    crushing.structure as given, or ISO 19906's p_G for the ice thickness and that width."""
    crushing = job.crushing
    if crushing is None or job.ice is None:  # no level-ice elements to crush
        return math.inf
    if crushing.structure != "iso19906":
        return float(crushing.structure)
    return crushing_pressure(thickness=job.ice.thickness, width=width, cr=crushing.iso_cr)


def law_records(laws) -> np.ndarray:
    """A structured array of CONTACT_LAW_RECORD from a sequence of ContactLaw (one per wall)."""
    out = np.zeros(len(laws), CONTACT_LAW_RECORD)
    for k, law in enumerate(laws):
        out[k] = tuple(law)
    return out


class IceContactTerm:
    """Contact between unbonded ice elements (kernels/contacts.py): sets ``c.contacts`` (the pairs in
    contact on this rank) and ``c.contact_energy`` [J]; ``crushing`` counts the contacts in plastic
    flow (crushing) in the last step.

    The candidates come from a neighbour list with a skin (kernels/pair_list.py), rebuilt when the
    rows were replaced (migration, ghosts, removal: a new ``p.gid`` array) or an element has moved
    half the skin since the list was built; ``builds`` counts the rebuilds. A removed bond
    (``p.topology`` raised) adds its pair to the list from ``p.unbonded`` (``inserts`` counts these);
    a removal not logged there rebuilds it. skin [m]: 0.3 of the largest diameter by default."""

    crushing = 0
    builds = 0
    inserts = 0
    name = "ice contacts"

    def __init__(self, law: ContactLaw, *, skin: float):
        self.law, self.skin = law, float(skin)
        self._built_for = None  # (p.gid, nlocal, topology) the list was built for
        self._x_ref = None

    def _list(self, p):
        built = self._built_for
        if (built is None or built[0] is not p.gid or built[1] != p.nlocal
                or moved_beyond(p.n, p.x, self._x_ref, 0.5 * self.skin)):
            self.pair_start, self.partners = build_pair_list(p.nlocal, p.n, p.gid, p.x, p.radius, p.bond_j, self.skin)
            self._x_ref = p.x.copy()
            self.builds += 1
        elif built[2] != p.topology:
            logged = p.unbonded or []
            if len(logged) == p.topology - built[2] and all(a is not None for a in logged):
                self.pair_start, self.partners = insert_pairs(self.pair_start, self.partners, p.gid,
                                                              np.concatenate(logged))
                self.inserts += 1
            else:  # removals not logged (or more than the log held)
                self.pair_start, self.partners = build_pair_list(p.nlocal, p.n, p.gid, p.x, p.radius, p.bond_j,
                                                                 self.skin)
                self.builds += 1
        else:
            return self.pair_start, self.partners
        self._built_for = (p.gid, p.nlocal, p.topology)
        p.unbonded = []
        return self.pair_start, self.partners

    def add_forces(self, p, c, dt):
        start, partners = self._list(p)
        c.contacts, c.contact_energy, self.crushing = contact_forces(
            p.nlocal, p.gid, p.x, p.v, p.w, p.radius, p.mass, p.cell_area, p.half_height, start, partners,
            p.contact_gid, p.contact_stamp, p.contact_hist, self.law, dt, c.step, p.force, p.torque)
