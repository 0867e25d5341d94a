"""ISO 19906 global ice loads: the yardsticks DEM ice loads are set beside (docs/iso19906.md).

Crushing on a vertical structure, ISO 19906 A.8.2.4.3, Eq. 15 of Zhu & Ji (2022)::

    F_h = C_R h D (h / h1)^n (D / h)^m

C_R = 1.5 MPa (the paper's value), h1 = 1 m, m = -0.16, and n = -0.5 + h/5 for h < 1 m and
n = -0.3 for h >= 1 m (ISO 19906; the paper writes n = -0.5 + h/5, which agrees at h = 1 m).
The reference a DEM ice load on the semi-submersible is set against: 40.1 MN for D = 50 m and
h = 1 m (the paper's text says "kN", a slip: ../shared/seeds/README.md).

Level ice failing in bending on a cone: ``cone_load`` (ISO 19906 A.8.2.4.4.2, Croasdale &
Cammaert 1994) and ``ralston_cone_load`` (A.8.2.4.4.3, Ralston 1977). ``python -m
pice.physics.iso19906`` prints both beside Eq. 15 for the reference sizes.
"""

from __future__ import annotations

import argparse
import math
from typing import NamedTuple

GRAVITY = 9.81  # [m/s^2]
TRESCA, JOHANSEN = 2.711, 3.422  # Ralston's Y for the two yield criteria of the plate


def crushing_load(*, thickness: float, diameter: float, cr: float = 1.5e6, h1: float = 1.0,
                  m: float = -0.16) -> float:
    """Global crushing load F_h [N] of level ice ``thickness`` [m] on a structure of width ``diameter`` [m]."""
    if thickness <= 0.0 or diameter <= 0.0:
        raise ValueError("thickness and diameter must be > 0 m")
    n = -0.5 + thickness / 5.0 if thickness < 1.0 else -0.3
    return cr * thickness * diameter * (thickness / h1) ** n * (diameter / thickness) ** m


def crushing_pressure(*, thickness: float, width: float, cr: float = 1.5e6, h1: float = 1.0,
                      m: float = -0.16) -> float:
    """The global crushing pressure p_G = C_R (h/h1)^n (w/h)^m [Pa] of Eq. 15 (ISO 19906 A.8.2.4.3)."""
    return crushing_load(thickness=thickness, diameter=width, cr=cr, h1=h1, m=m) / (thickness * width)


class ConeLoad(NamedTuple):
    """Croasdale's loads on a cone [N]: the totals and the five parts of F_H's numerator."""

    horizontal: float   # F_H
    vertical: float     # F_V, magnitude: down on an upward-breaking cone, up on a downward one
    breaking: float     # H_B, to break the sheet in bending
    rubble_push: float  # H_P, to push the sheet through the rubble on top of it
    ride_up: float      # H_R, to push the ride-up ice up the slope through the rubble
    rubble_lift: float  # H_L, to lift the rubble on top of the ride-up ice before it breaks
    block_turn: float   # H_T, to turn the ice blocks at the top of the slope
    amplification: float  # 1 / (1 - H_B / (sigma_f l_c h)) on the sum of the five


def cone_load(*, diameter: float, angle_deg: float, thickness: float, flexural_strength: float,
              youngs_modulus: float, rubble_height: float, poissons_ratio: float = 0.3,
              ice_density: float = 920.0, water_density: float = 1035.0, friction: float = 0.15,
              ice_friction: float = 0.15, rubble_porosity: float = 0.3, rubble_angle_deg: float = 40.0,
              rubble_friction_angle_deg: float = 45.0, rubble_cohesion: float = 0.0,
              three_d: bool = True, downward: bool = False, block_turning: bool = True,
              gravity: float = GRAVITY) -> ConeLoad:
    """Level-ice load on a cone failing the ice in bending: ISO 19906 A.8.2.4.4.2 (Croasdale).

    Arguments, SI units and degrees: ``diameter`` w, the waterline diameter [m]; ``angle_deg``
    alpha, the slope from the horizontal; ``thickness`` h [m]; ``flexural_strength`` sigma_f
    [Pa]; ``youngs_modulus`` E [Pa] and ``poissons_ratio`` nu of the ice; ``rubble_height`` h_r
    [m], the height the ride-up ice and the rubble on it reach up the slope (0: the broken ice
    clears at once, leaving H_B and H_T); densities rho_i, rho_w [kg/m^3]; ``friction`` mu
    (ice-structure), ``ice_friction`` mu_i (ice-ice); the rubble's porosity e, angle theta from
    the horizontal (< alpha), internal friction angle phi and cohesion c [Pa]. ``three_d`` adds
    the circumferential crack of a cone to the width; ``downward`` takes a downward-breaking
    cone (the rubble's buoyancy (rho_w - rho_i) g in place of its weight rho_i g);
    ``block_turning`` False leaves H_T out (a cone with no vertical neck above the rubble)::

        xi  = (sin a + mu cos a) / (cos a - mu sin a)
        L_c = (E h^3 / (12 rho_w g (1 - nu^2)))^(1/4),   l_c = w + pi^2 L_c / 4   (2D: l_c = w)
        H_B = 0.68 xi sigma_f (rho_w g h^5 / E)^(1/4) l_c
        H_P = w h_r^2 mu_i rho_i g (1 - e) (1 - tan t / tan a)^2 / (2 tan t)
        H_R = w P / (cos a - mu sin a), with
        P   = 0.5 mu_i (mu_i + mu) rho_i g (1 - e) h_r^2 sin a (cot t - cot a)(1 - tan t / tan a)
            + 0.5 (mu_i + mu) rho_i g (1 - e) h_r^2 cos a cot a (1 - tan t / tan a)
            + h_r h rho_i g (sin a + mu cos a) / sin a
        H_L = w h_r xi (1 - tan t / tan a) [0.5 h_r rho_i g (1 - e)
                                             (cot t - cot a + tan phi (1 - tan t / tan a)) + c]
        H_T = 1.5 w h^2 rho_i g cos a / (sin a - mu cos a)
        F_H = (H_B + H_P + H_R + H_L + H_T) / (1 - H_B / (sigma_f l_c h))
        F_V = F_H / xi

    F_V is Croasdale's H = xi V for a load passed through a slope at limiting friction, applied to
    the total (our choice: docs/iso19906.md). Checked against the IceFloe example (DNV KEMA 2014)
    to its printed digits and H_B's 0.68 against a beam on an elastic foundation
    (tests/physics/test_iso19906.py).
    """
    w, h, h_r = float(diameter), float(thickness), float(rubble_height)
    if w <= 0.0 or h <= 0.0 or h_r < 0.0:
        raise ValueError("diameter and thickness must be > 0 m, rubble_height >= 0 m")
    if flexural_strength <= 0.0 or youngs_modulus <= 0.0:
        raise ValueError("flexural_strength and youngs_modulus must be > 0 Pa")
    a = math.radians(angle_deg)
    sin_a, cos_a = math.sin(a), math.cos(a)
    mu, mu_i = friction, ice_friction
    if not 0.0 < a < math.pi / 2 or cos_a - mu * sin_a <= 0.0:
        raise ValueError(f"the ice cannot slide up a {angle_deg} deg slope with friction {mu}: "
                         "give 0 < angle_deg < 90 with friction < 1/tan(angle)")
    weight = (water_density - ice_density if downward else ice_density) * gravity  # [N/m^3]
    if weight <= 0.0:
        raise ValueError("water_density must exceed ice_density")
    xi = (sin_a + mu * cos_a) / (cos_a - mu * sin_a)
    char_length = (youngs_modulus * h ** 3
                   / (12.0 * water_density * gravity * (1.0 - poissons_ratio ** 2))) ** 0.25
    crack = w + math.pi ** 2 * char_length / 4.0 if three_d else w
    h_b = 0.68 * xi * flexural_strength * (water_density * gravity * h ** 5 / youngs_modulus) ** 0.25 * crack
    h_p = h_r_part = h_l = 0.0
    if h_r > 0.0:
        t = math.radians(rubble_angle_deg)
        if not 0.0 < t < a:
            raise ValueError(f"rubble_angle_deg must lie between 0 and the cone's {angle_deg} deg")
        tan_t, tan_a = math.tan(t), math.tan(a)
        fill = 1.0 - tan_t / tan_a          # (1 - tan t / tan a)
        cots = 1.0 / tan_t - 1.0 / tan_a    # (cot t - cot a)
        rubble = weight * (1.0 - rubble_porosity)  # weight (or buoyancy) of the rubble [N/m^3]
        h_p = w * h_r ** 2 * mu_i * rubble * fill ** 2 / (2.0 * tan_t)
        p = (0.5 * mu_i * (mu_i + mu) * rubble * h_r ** 2 * sin_a * cots * fill
             + 0.5 * (mu_i + mu) * rubble * h_r ** 2 * cos_a / tan_a * fill
             + h_r * h * weight * (sin_a + mu * cos_a) / sin_a)
        h_r_part = w * p / (cos_a - mu * sin_a)
        phi = math.radians(rubble_friction_angle_deg)
        h_l = w * h_r * xi * fill * (0.5 * h_r * rubble * (cots + math.tan(phi) * fill) + rubble_cohesion)
    h_t = 0.0
    if block_turning:
        if sin_a - mu * cos_a <= 0.0:
            raise ValueError(f"H_T needs friction < tan(angle) ({mu} on {angle_deg} deg): "
                             "give block_turning=False")
        h_t = 1.5 * w * h ** 2 * weight * cos_a / (sin_a - mu * cos_a)
    relief = 1.0 - h_b / (flexural_strength * crack * h)
    if relief <= 0.0:
        raise ValueError("H_B >= sigma_f l_c h: the sheet would crush before it bends; "
                         "use crushing_load")
    f_h = (h_b + h_p + h_r_part + h_l + h_t) / relief
    return ConeLoad(f_h, f_h / xi, h_b, h_p, h_r_part, h_l, h_t, 1.0 / relief)


class RalstonLoad(NamedTuple):
    """Ralston's horizontal load on a cone [N] and its two parts."""

    horizontal: float   # F_H = H_B + H_R
    breaking: float     # H_B, the plastic limit of the plate bent up (or down) by the cone
    ride_up: float      # H_R, to push the ride-up ice up the cone's surface


def _agm_elliptic(k: float) -> tuple[float, float]:
    """Complete elliptic integrals K(k), E(k) of modulus k < 1 by the arithmetic-geometric mean."""
    a, b, c_sum, power = 1.0, math.sqrt(1.0 - k * k), 0.5 * k * k, 0.5
    while abs(a - b) > 1e-15 * a:
        c = 0.5 * (a - b)
        a, b = 0.5 * (a + b), math.sqrt(a * b)
        power *= 2.0
        c_sum += power * c * c
    big_k = math.pi / (2.0 * a)
    return big_k, big_k * (1.0 - c_sum)


def ralston_cone_load(*, diameter: float, top_diameter: float, angle_deg: float, thickness: float,
                      flexural_strength: float, ride_up_thickness: float, ice_density: float = 920.0,
                      water_density: float = 1035.0, friction: float = 0.15, y: float = TRESCA,
                      downward: bool = False, gravity: float = GRAVITY) -> RalstonLoad:
    """Horizontal level-ice load on a cone by Ralston's plastic limit: ISO 19906 A.8.2.4.4.3.

    ``diameter`` D at the waterline and ``top_diameter`` D_T where the ride-up ends [m];
    ``ride_up_thickness`` h_r [m] of the ice riding up the cone; ``y`` Y = 2.711 (Tresca, default)
    or 3.422 (Johansen); the rest as in ``cone_load``. With a in radians, K and E the complete
    elliptic integrals of modulus sin a::

        G   = rho_i g D^2 / (4 sigma_f h),   x = 1 + (3 G + Y / 2)^(-1/2)
        g_R = (1/2 + a / sin 2a) / (pi/4 sin a + mu a cos a / sin a),   f = sin a + mu K cos a
        H_B = tan a / (1 - mu g_R) sigma_f h^2 / 3 [(1 + Y x ln x) / (x - 1) + G (x - 1)(x + 2)]
        W   = rho_i g h_r (D^2 - D_T^2) / (4 cos a)
        H_R = W [tan a + mu E - mu f g_R cos a] / (1 - mu g_R)
        F_H = H_B + H_R

    rho_i g in G and W is the weight of the ice lifted out of the water; a ``downward`` cone pushes
    it under, and (rho_w - rho_i) g, its buoyancy, takes its place in both. The standard's
    vertical load (Ralston's B coefficients) is not given here: docs/iso19906.md says why.
    """
    d, d_t, h, h_r = float(diameter), float(top_diameter), float(thickness), float(ride_up_thickness)
    if h <= 0.0 or not 0.0 <= d_t <= d or d <= 0.0 or h_r < 0.0 or flexural_strength <= 0.0:
        raise ValueError("give thickness > 0, 0 <= top_diameter <= diameter, ride_up_thickness >= 0 "
                         "and flexural_strength > 0")
    a = math.radians(angle_deg)
    if not 0.0 < a < math.pi / 2:
        raise ValueError("angle_deg must lie between 0 and 90")
    sin_a, cos_a, tan_a, mu = math.sin(a), math.cos(a), math.tan(a), friction
    big_k, big_e = _agm_elliptic(sin_a)
    g_r = (0.5 + a / math.sin(2.0 * a)) / (0.25 * math.pi * sin_a + mu * a * cos_a / sin_a)
    if 1.0 - mu * g_r <= 0.0:
        raise ValueError(f"friction {mu} is too high for Ralston's solution on a {angle_deg} deg cone")
    weight = (water_density - ice_density if downward else ice_density) * gravity  # [N/m^3]
    if weight <= 0.0:
        raise ValueError("water_density must exceed ice_density")
    big_g = weight * d ** 2 / (4.0 * flexural_strength * h)
    x = 1.0 + (3.0 * big_g + 0.5 * y) ** -0.5
    h_b = (tan_a / (1.0 - mu * g_r) * flexural_strength * h ** 2 / 3.0
           * ((1.0 + y * x * math.log(x)) / (x - 1.0) + big_g * (x - 1.0) * (x + 2.0)))
    w_ride = weight * h_r * (d ** 2 - d_t ** 2) / (4.0 * cos_a)
    f = sin_a + mu * big_k * cos_a
    h_r_part = w_ride * (tan_a + mu * big_e - mu * f * g_r * cos_a) / (1.0 - mu * g_r)
    return RalstonLoad(h_b + h_r_part, h_b, h_r_part)


def reference_table(*, thicknesses=(1.0, 1.2, 1.4, 1.6), diameter: float = 50.0, angle_deg: float = 60.0,
                    flexural_strength: float = 0.5e6, youngs_modulus: float = 5.0e9,
                    rubble_height: float = 0.0) -> list[str]:
    """Lines of the table: Eq. 15 on a ``diameter`` column beside both cone methods [MN]."""
    lines = [f"ISO 19906 global ice loads [MN]: a vertical column and a {angle_deg:g} deg cone, both {diameter:g} m "
             f"wide at the waterline",
             f"{'h [m]':>6} {'crushing':>9} {'cone H_B':>9} {'cone F_H':>9} {'cone F_V':>9} {'Ralston':>9}"]
    for h in thicknesses:
        crush = crushing_load(thickness=h, diameter=diameter)
        cone = cone_load(diameter=diameter, angle_deg=angle_deg, thickness=h, flexural_strength=flexural_strength,
                         youngs_modulus=youngs_modulus, rubble_height=rubble_height)
        ralston = ralston_cone_load(diameter=diameter, top_diameter=0.0, angle_deg=angle_deg, thickness=h,
                                    flexural_strength=flexural_strength, ride_up_thickness=0.0)
        lines.append(f"{h:6.2f} {crush / 1e6:9.2f} {cone.breaking / 1e6:9.2f} {cone.horizontal / 1e6:9.2f} "
                     f"{cone.vertical / 1e6:9.2f} {ralston.horizontal / 1e6:9.2f}")
    lines += ["crushing: Eq. 15 (A.8.2.4.3); cone: A.8.2.4.4.2 (Croasdale), F_V down on the cone; "
              "Ralston: A.8.2.4.4.3, F_H",
              f"sigma_f {flexural_strength / 1e6:g} MPa, E {youngs_modulus / 1e9:g} GPa, rubble height h_r "
              f"{rubble_height:g} m (Ralston: no ride-up), rho_i 920, rho_w 1035 kg/m^3, mu 0.15, nu 0.3"]
    return lines


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m pice.physics.iso19906",
                                     description="ISO 19906 crushing (Eq. 15) and cone loads [MN] by ice thickness "
                                                 "(docs/iso19906.md)")
    parser.add_argument("--thickness", type=float, nargs="+", default=[1.0, 1.2, 1.4, 1.6], metavar="H")
    parser.add_argument("--diameter", type=float, default=50.0, help="[m] (default 50, seed 000)")
    parser.add_argument("--angle", type=float, default=60.0, help="cone slope from the horizontal [deg]")
    parser.add_argument("--flexural-strength", type=float, default=0.5e6, help="[Pa]")
    parser.add_argument("--youngs-modulus", type=float, default=5.0e9, help="[Pa]")
    parser.add_argument("--rubble-height", type=float, default=0.0, help="h_r [m]")
    args = parser.parse_args(argv)
    print("\n".join(reference_table(thicknesses=args.thickness, diameter=args.diameter, angle_deg=args.angle,
                                    flexural_strength=args.flexural_strength,
                                    youngs_modulus=args.youngs_modulus, rubble_height=args.rubble_height)))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
