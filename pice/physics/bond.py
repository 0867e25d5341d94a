"""Parallel bond (Zhu & Ji 2022, 000_d6dfa5ea71378166.txt, Eqs. 1-7): parameters and calibration.

A bond is a disk of radius R = radius_ratio * r on the contact plane. Unit-area stiffnesses
k_n, k_s [Pa/m] give the springs used by the kernel (Eqs. 1-2):

    normal   k_n A  [N/m]        shear    k_s A  [N/m]
    twisting k_s J  [N m/rad]    bending  k_n I  [N m/rad]

with A = pi R^2, I = pi R^4 / 4, J = pi R^4 / 2. Failure (Eqs. 3-5): sigma_max = T/A + |M_b| R / I
(tension T > 0) reaches the normal strength, or tau_max = |F_s|/A + |M_t| R / J reaches
tau_c = mu sigma_max + sigma_s.

From an effective Young's modulus E and Poisson's ratio nu, a single layer of elements is
calibrated so that the hexagonal lattice bends exactly as a plate of thickness t
(D = E t^3 / (12 (1 - nu^2)), including the plate's Poisson coupling); see docs/bond_calibration.md.
"""

from __future__ import annotations

import math
from collections import namedtuple
from dataclasses import dataclass

import numpy as np

from ..errors import JobError
from ..kernels.bonds import bond_energy, bond_forces


def eq6_bond_strength(*, flexural_strength: float, thickness: float, element_diameter: float) -> float:
    """Normal bond strength [Pa] from the flexural strength [Pa] (Eq. 6, size effect L/D)."""
    ratio = thickness / element_diameter
    return flexural_strength / (1.77 - 1.81 * math.exp(-ratio / 4.78))


def eq7_bond_friction(*, compressive_strength: float, flexural_strength: float) -> float:
    """Inner friction coefficient mu of Eq. 5 from the compressive/flexural strength ratio (Eq. 7)."""
    return 0.23 * compressive_strength / flexural_strength - 0.5


def single_layer_bending_springs(*, youngs_modulus: float, poissons_ratio: float, thickness: float):
    """Bending and twisting spring constants [N m/rad] of a single-layer hexagonal sheet.

    Matching the lattice's bending energy to Kirchhoff plate theory gives
    D = sqrt(3) k_b / (1 + nu_lattice) with nu_lattice = (k_b - k_t) / (3 k_b + k_t),
    independent of the element size. Returns (k_b, k_t) for the plate's D and nu.
    """
    nu = poissons_ratio
    if nu > 1.0 / 3.0:
        raise ValueError("a single layer of elements can represent Poisson's ratio <= 1/3 only")
    flexural_rigidity = youngs_modulus * thickness**3 / (12.0 * (1.0 - nu * nu))
    k_b = flexural_rigidity * (1.0 + nu) / math.sqrt(3.0)
    k_t = k_b * (1.0 - 3.0 * nu) / (1.0 + nu)
    return k_b, k_t


BondLaw = namedtuple("BondLaw", ["kn", "ks", "kt", "kb", "area", "inertia", "polar", "disk_radius",
                                 "normal_strength", "shear_strength", "friction", "cn", "cs", "ct", "cb"])
BondLaw.__doc__ = """The parallel bond's parameters as the kernel reads them (kernels/bonds.py), by name:
springs kn, ks [N/m], kt, kb [N m/rad]; disk area [m^2], inertia, polar [m^4], disk_radius [m];
normal_strength, shear_strength [Pa] and friction of Eqs. 3-5; dashpots cn, cs [N s/m], ct, cb [N m s/rad]."""


@dataclass(frozen=True)
class BondParams:
    """Spring constants, disk geometry and strengths of one bond type (SI units)."""

    kn: float          # normal spring k_n A [N/m]
    ks: float          # shear spring k_s A [N/m]
    kt: float          # twisting spring k_s J [N m/rad]
    kb: float          # bending spring k_n I [N m/rad]
    area: float        # A [m^2]
    inertia: float     # I [m^4]
    polar: float       # J [m^4]
    disk_radius: float  # R [m]
    normal_strength: float  # [Pa]; inf when unbreakable
    shear_strength: float   # sigma_s of Eq. 5 [Pa]
    friction: float         # mu of Eq. 5
    damping_ratio: float

    def kernel_law(self, *, mass: float, inertia: float) -> BondLaw:
        """The kernel's record (BondLaw), with dashpots at ``damping_ratio`` of critical for a pair of
        elements of ``mass`` [kg] and ``inertia`` [kg m^2]."""
        z = self.damping_ratio
        m_red, i_red = 0.5 * mass, 0.5 * inertia
        cn = 2 * z * math.sqrt(m_red * self.kn)
        cs = 2 * z * math.sqrt(m_red * self.ks)
        ct = 2 * z * math.sqrt(i_red * self.kt)
        cb = 2 * z * math.sqrt(i_red * self.kb)
        return BondLaw(kn=self.kn, ks=self.ks, kt=self.kt, kb=self.kb, area=self.area, inertia=self.inertia,
                       polar=self.polar, disk_radius=self.disk_radius, normal_strength=self.normal_strength,
                       shear_strength=self.shear_strength, friction=self.friction, cn=cn, cs=cs, ct=ct, cb=cb)


def bond_params_from_job(job, *, n_layers: int, spacing: float) -> BondParams:
    """Derive the ice bond parameters from the job ([bond] and [ice] sections)."""
    ice, bond = job.ice, job.bond
    r = 0.5 * ice.element_diameter
    R = bond.radius_ratio * r
    A, I, J = math.pi * R**2, math.pi * R**4 / 4.0, math.pi * R**4 / 2.0
    if bond.normal_stiffness is not None:
        kn = bond.normal_stiffness
        ks = bond.shear_stiffness if bond.shear_stiffness is not None else kn / 10.0
        kbar_n, kbar_s = kn / A, ks / A
        kb, kt = kbar_n * I, kbar_s * J
    else:
        E, nu = ice.youngs_modulus, ice.poissons_ratio
        if n_layers == 1:
            try:
                kb, kt = single_layer_bending_springs(youngs_modulus=E, poissons_ratio=nu,
                                                      thickness=ice.thickness)
            except ValueError as exc:
                raise JobError(f"{job.source}: ice.poissons_ratio = {nu}: {exc}; use bond stiffnesses "
                               "directly or a thicker (multi-layer) sheet") from None
            kbar_n, kbar_s = kb / I, kt / J
        else:
            # multi-layer sheet: each bond as a rod of length `spacing` (approximate, not plate-calibrated)
            kbar_n = E / spacing
            kbar_s = kbar_n / (2.0 * (1.0 + nu))
            kb, kt = kbar_n * I, kbar_s * J
        kn, ks = kbar_n * A, kbar_s * A
    if not bond.breakable:
        sn, ss, mu = math.inf, math.inf, 0.0
    else:
        if bond.normal_strength is not None:
            sn = bond.normal_strength
        else:
            sn = eq6_bond_strength(flexural_strength=ice.flexural_strength, thickness=ice.thickness,
                                   element_diameter=ice.element_diameter)
        ss = bond.shear_strength if bond.shear_strength is not None else sn
        if bond.friction is not None:
            mu = bond.friction
        elif ice.compressive_strength is not None and ice.flexural_strength is not None:
            mu = eq7_bond_friction(compressive_strength=ice.compressive_strength,
                                   flexural_strength=ice.flexural_strength)
            if mu < 0:
                raise JobError(f"{job.source}: ice.compressive_strength = {ice.compressive_strength}: Eq. 7 "
                               f"gives a negative bond friction (0.23 sc/sf - 0.5 = {mu:.3g}); "
                               "give bond.friction explicitly")
        else:
            mu = 0.0
    return BondParams(kn=kn, ks=ks, kt=kt, kb=kb, area=A, inertia=I, polar=J, disk_radius=R,
                      normal_strength=sn, shear_strength=ss, friction=mu, damping_ratio=bond.damping_ratio)


class BondTerm:
    """The parallel bonds' forces and moments, and their breaking (kernels/bonds.py).

    Each broken bond is counted in ``c.broken`` and logged in ``c.events`` as
    (step, time, gid_a, gid_b, mode) with the mode of kernels.bonds.FAILURE_MODES.
    """

    name = "bonds"
    max_events = 100_000  # bonds logged per step at most (all are counted)

    def __init__(self, law: BondLaw):
        self.law = law
        self._events = np.zeros((self.max_events, 3), dtype=np.int64)  # gid_a, gid_b, mode

    def add_forces(self, p, c, dt):
        nb = bond_forces(p.nlocal, p.gid, p.x, p.v, p.w, p.radius, p.bond_j, p.bond_mate, p.bond_gid,
                         p.bond_L0, p.bond_hist, self.law, dt, p.force, p.torque, self._events)
        if nb:
            c.broken += nb
            for a, b, mode in self._events[:min(nb, self.max_events)]:
                c.events.append((c.step, c.time, int(a), int(b), int(mode)))

    def energy(self, p) -> float:
        """Elastic energy stored in the intact bonds of the owned elements [J] (each bond once)."""
        return bond_energy(p.nlocal, p.gid, p.bond_gid, p.bond_hist, self.law)
