"""The parallel bond (Zhu & Ji 2022, 000_d6dfa5ea71378166.txt, Eqs. 1-5): its parameters and force term.

A bond has four springs (Eqs. 1-2): normal k_n and shear k_s [N/m], twisting k_t and bending k_b
[N m/rad], and a section on which its stresses are taken (Eqs. 3-4; kernels/bonds.py): area A,
inertia I, polar J and fibre distances. A job gives the springs directly (Table 4 of the paper:
a disk of radius R, A = pi R^2, I = pi R^4 / 4, J = pi R^4 / 2) or through the plate it stands for
(E, nu, thickness): physics/bond_calibration.py, docs/bond_calibration.md.
"""

from __future__ import annotations

import math
from collections import namedtuple
from dataclasses import dataclass

import numpy as np

from ..kernels.bonds import MOHR_COULOMB, ZHU_JI_EQ5, bond_energy, bond_forces

SHEAR_LAWS = {"mohr_coulomb": MOHR_COULOMB, "zhu_ji_2022_eq5": ZHU_JI_EQ5}

BondLaw = namedtuple("BondLaw", ["kn", "ks", "kt", "kb", "area", "inertia", "polar", "bend_fiber", "twist_fiber",
                                 "normal_strength", "shear_strength", "compressive_strength", "friction",
                                 "shear_law", "cn", "cs", "ct", "cb"])
BondLaw.__doc__ = """The parallel bond's parameters as the kernel reads them (kernels/bonds.py), by name:
springs kn, ks [N/m], kt, kb [N m/rad]; section area [m^2], inertia, polar [m^4], bend_fiber and
twist_fiber [m]; normal_strength, shear_strength, compressive_strength [Pa] (inf: none), friction (mu)
and shear_law (kernels.bonds.MOHR_COULOMB or ZHU_JI_EQ5); dashpots cn, cs [N s/m], ct, cb [N m s/rad]."""


@dataclass(frozen=True)
class BondParams:
    """Spring constants, section and strengths of one bond type (SI units)."""

    kn: float          # normal spring [N/m]
    ks: float          # shear spring [N/m]
    kt: float          # twisting spring [N m/rad]
    kb: float          # bending spring [N m/rad]
    area: float        # A [m^2]
    inertia: float     # I [m^4]
    polar: float       # J [m^4]
    bend_fiber: float   # distance of the outer fibre in bending [m]
    twist_fiber: float  # distance of the outer fibre in twisting [m]
    normal_strength: float  # [Pa]; inf when unbreakable
    shear_strength: float   # sigma_s [Pa]
    friction: float         # mu of the shear strength
    damping_ratio: float
    compressive_strength: float = math.inf  # the bond's compressive cap [Pa]; inf: none
    shear_law: str = "mohr_coulomb"          # or "zhu_ji_2022_eq5" (the paper's Eq. 5 as printed)
    calibration: str = "springs"             # "springs" (given), "plate" (from E), "rods" (multi-layer)

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
                       polar=self.polar, bend_fiber=self.bend_fiber, twist_fiber=self.twist_fiber,
                       normal_strength=self.normal_strength, shear_strength=self.shear_strength,
                       compressive_strength=self.compressive_strength, friction=self.friction,
                       shear_law=SHEAR_LAWS[self.shear_law], cn=cn, cs=cs, ct=ct, cb=cb)


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
        self._removed = np.zeros((self.max_events, 2), dtype=np.int64)  # local i, j

    def add_forces(self, p, c, dt):
        nb, removed = bond_forces(p.nlocal, p.gid, p.x, p.v, p.w, p.radius, p.bond_j, p.bond_mate, p.bond_gid,
                                  p.bond_L0, p.bond_hist, self.law, dt, p.force, p.torque, self._events,
                                  self._removed)
        if removed:
            p.topology += 1  # the contact candidates change (physics/contact.py)
            if p.unbonded is not None:
                p.unbonded.append(self._removed[:removed].copy() if removed <= self.max_events else None)
        if nb:
            c.broken += nb
            for a, b, mode in self._events[:min(nb, self.max_events)]:
                c.events.append((c.step, c.time, int(a), int(b), int(mode)))

    def energy(self, p) -> float:
        """Elastic energy stored in the intact bonds of the owned elements [J] (each bond once)."""
        return bond_energy(p.nlocal, p.gid, p.bond_gid, p.bond_hist, self.law)
