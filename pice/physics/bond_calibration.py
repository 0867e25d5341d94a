"""Bond parameters from the job: given springs (Table 4 of Zhu & Ji 2022) or the plate they stand for.

Three calibrations (docs/bond_calibration.md):

* **springs**: [bond] normal_stiffness (and shear_stiffness) given [N/m]; the section is the paper's
  disk of radius R = radius_ratio * r; the normal strength from [bond] or Eq. 6 (the paper's size
  effect), the friction from [bond] or Eq. 7.
* **plate** (one layer of elements, ice.youngs_modulus given): the springs give the sheet the
  plate's in-plane stiffness E h and bending stiffness D = E h^3 / (12 (1 - nu^2)) at any element
  size d. The triangular lattice of normal and shear springs has E h = 2 sqrt(3) k_n (k_n + k_s) /
  (3 k_n + k_s) and nu = (k_n - k_s) / (3 k_n + k_s) (Griffiths & Mustoe 2001), so

      k_n = E h / (sqrt(3) (1 - nu)),   k_s = k_n (1 - 3 nu) / (1 + nu)            [N/m]
      k_b = D (1 + nu) / sqrt(3),       k_t = D (1 - 3 nu) / sqrt(3)              [N m/rad]

  none of which depends on d. The section on which a bond's stresses are taken is the strip of
  plate it carries: width w = d / sqrt(3) (a uniform stress sigma puts T = sigma h w on every bond),
  height h: A = w h, I = w h^3 / 12, c_b = h / 2, so the bond stresses do not depend on d either.
  In a beam bent along a bond (free sides) the bond's bending stress is the beam's fibre stress
  divided by (1 - nu), hence the default normal strength sigma_f / (1 - nu): the sheet then fails in
  bending at the flexural strength (checked by `pice lab`).
* **rods** (several layers, from E): each bond as a rod of length d (approximate, not plate-calibrated).
"""

from __future__ import annotations

import math

from ..errors import JobError
from .bond import BondParams


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


def single_layer_membrane_springs(*, youngs_modulus: float, poissons_ratio: float, thickness: float):
    """Normal and shear spring constants [N/m] giving a single-layer triangular lattice the plate's
    in-plane modulus E h [N/m] and Poisson's ratio nu (module docstring); independent of the element size."""
    nu = poissons_ratio
    if nu > 1.0 / 3.0:
        raise ValueError("a single layer of elements can represent Poisson's ratio <= 1/3 only")
    k_n = youngs_modulus * thickness / (math.sqrt(3.0) * (1.0 - nu))
    return k_n, k_n * (1.0 - 3.0 * nu) / (1.0 + nu)


def lattice_membrane_modulus(*, k_n: float, k_s: float) -> tuple[float, float]:
    """In-plane modulus E h [N/m] and Poisson's ratio of a triangular lattice of springs k_n, k_s [N/m]."""
    return 2.0 * math.sqrt(3.0) * k_n * (k_n + k_s) / (3.0 * k_n + k_s), (k_n - k_s) / (3.0 * k_n + k_s)


def plate_section(*, spacing: float, thickness: float) -> dict:
    """The plate strip a bond of a single layer carries: area, inertia, polar [m^2, m^4], fibres [m]."""
    w, h = spacing / math.sqrt(3.0), thickness
    return dict(area=w * h, inertia=w * h**3 / 12.0, polar=w * h * (w * w + h * h) / 12.0,
                bend_fiber=0.5 * h, twist_fiber=0.5 * math.hypot(w, h))


def disk_section(radius: float) -> dict:
    """The paper's bonding disk of radius R [m]: A = pi R^2, I = pi R^4 / 4, J = pi R^4 / 2."""
    return dict(area=math.pi * radius**2, inertia=math.pi * radius**4 / 4.0, polar=math.pi * radius**4 / 2.0,
                bend_fiber=radius, twist_fiber=radius)


def bond_params_from_job(job, *, n_layers: int, spacing: float) -> BondParams:
    """Derive the ice bond parameters from the job ([bond] and [ice] sections)."""
    ice, bond = job.ice, job.bond
    nu = ice.poissons_ratio
    if bond.normal_stiffness is not None:
        calibration = "springs"
        sec = disk_section(bond.radius_ratio * 0.5 * ice.element_diameter)
        kn = bond.normal_stiffness
        ks = bond.shear_stiffness if bond.shear_stiffness is not None else kn / 10.0
        kb, kt = kn / sec["area"] * sec["inertia"], ks / sec["area"] * sec["polar"]
    elif n_layers == 1:
        calibration = "plate"
        try:
            kb, kt = single_layer_bending_springs(youngs_modulus=ice.youngs_modulus, poissons_ratio=nu,
                                                  thickness=ice.thickness)
            kn, ks = single_layer_membrane_springs(youngs_modulus=ice.youngs_modulus, poissons_ratio=nu,
                                                   thickness=ice.thickness)
        except ValueError as exc:
            raise JobError(f"{job.source}: ice.poissons_ratio = {nu}: {exc}; use bond stiffnesses "
                           "directly or a thicker (multi-layer) sheet") from None
        sec = plate_section(spacing=spacing, thickness=ice.thickness)
    else:
        calibration = "rods"
        sec = disk_section(bond.radius_ratio * 0.5 * ice.element_diameter)
        kbar_n = ice.youngs_modulus / spacing
        kbar_s = kbar_n / (2.0 * (1.0 + nu))
        kn, ks, kb, kt = kbar_n * sec["area"], kbar_s * sec["area"], kbar_n * sec["inertia"], kbar_s * sec["polar"]
    sn, ss, mu = _strengths(job, calibration)
    sc = bond.compressive_strength if (bond.compressive_strength is not None and bond.breakable) else math.inf
    return BondParams(kn=kn, ks=ks, kt=kt, kb=kb, **sec, normal_strength=sn, shear_strength=ss, friction=mu,
                      damping_ratio=bond.damping_ratio, compressive_strength=sc,
                      shear_law=bond.shear_strength_law, calibration=calibration)


def _strengths(job, calibration: str) -> tuple[float, float, float]:
    """(normal strength [Pa], shear strength sigma_s [Pa], friction mu) of the bond."""
    ice, bond = job.ice, job.bond
    if not bond.breakable:
        return math.inf, math.inf, 0.0
    if bond.normal_strength is not None:
        sn = bond.normal_strength
    elif calibration == "plate":
        sn = ice.flexural_strength / (1.0 - ice.poissons_ratio)
    else:
        sn = eq6_bond_strength(flexural_strength=ice.flexural_strength, thickness=ice.thickness,
                               element_diameter=ice.element_diameter)
    ss = bond.shear_strength if bond.shear_strength is not None else sn
    if bond.friction is not None:
        return sn, ss, bond.friction
    if ice.compressive_strength is not None and ice.flexural_strength is not None:
        mu = eq7_bond_friction(compressive_strength=ice.compressive_strength, flexural_strength=ice.flexural_strength)
        if mu < 0:
            raise JobError(f"{job.source}: ice.compressive_strength = {ice.compressive_strength}: Eq. 7 "
                           f"gives a negative bond friction (0.23 sc/sf - 0.5 = {mu:.3g}); "
                           "give bond.friction explicitly")
        return sn, ss, mu
    return sn, ss, 0.0
