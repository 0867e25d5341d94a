"""Ridge keel resistance on a ship by Malmberg's formula (1983), as seed 002 quotes it (Gong, Polojärvi &
Tuhkuri 2017, Eqs. 1-2; issue 15), with the seed's known slip in Eq. 2 corrected
(../shared/seeds/README.md: C2 = (1 - p)(rho_w - rho_i) g mu_s).

    R_A = C1 T h (B/2 + h tan(psi) cos(alpha)) (mu_s cos(alpha) + sin(psi) sin(alpha))
          + C2 T L_m [K0 h + max(h/T - 1/2, 0) B]
    C1 = (1 - p)(rho_w - rho_i) g K_p,   K_p = tan^2(45 deg + phi/2),   C2 = (1 - p)(rho_w - rho_i) g mu_s
    psi = atan(tan(stem angle) / sin(alpha))

T the ship's draft, B its breadth, L_m its parallel midbody, alpha the waterline half-angle [m,
deg]; h the keel depth [m]; p the rubble's porosity, phi its internal friction angle; K0 the
coefficient of pressure at rest (0.27, Riska 1997); mu_s the ship-ice friction. The keel's width
does not enter: the formula is for a keel wider than the ship's bow.
"""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class KeelResistance:
    """Malmberg's R_A [N] and its two terms: the bow's passive failure and the midbody's friction."""

    bow: float
    midbody: float

    @property
    def total(self) -> float:
        return self.bow + self.midbody


def malmberg_resistance(*, draft: float, breadth: float, midbody: float, waterline_angle_deg: float,
                        stem_angle_deg: float, keel_depth: float, porosity: float = 0.3,
                        friction_angle_deg: float = 40.0, k0: float = 0.27, ship_friction: float = 0.1,
                        water_density: float = 1010.0, ice_density: float = 920.0,
                        g: float = 9.81) -> KeelResistance:
    """Malmberg's keel resistance (module docstring). Defaults: seed 002's values (Table 1, and phi 40
    deg, p 0.3 with which it quotes about 1000 kN)."""
    alpha = math.radians(waterline_angle_deg)
    psi = math.atan(math.tan(math.radians(stem_angle_deg)) / math.sin(alpha))
    kp = math.tan(math.radians(45.0 + 0.5 * friction_angle_deg)) ** 2
    buoyant = (1.0 - porosity) * (water_density - ice_density) * g  # [N/m^3]
    c1, c2 = buoyant * kp, buoyant * ship_friction
    t, h, b = draft, keel_depth, breadth
    bow = c1 * t * h * (0.5 * b + h * math.tan(psi) * math.cos(alpha)) * (
        ship_friction * math.cos(alpha) + math.sin(psi) * math.sin(alpha))
    side = c2 * t * midbody * (k0 * h + max(h / t - 0.5, 0.0) * b)
    return KeelResistance(bow=bow, midbody=side)
