"""Global ice crushing load on a vertical structure: ISO 19906 (A.8.2.4.3), Eq. 15 of Zhu & Ji (2022).

    F_h = C_R h D (h / h1)^n (D / h)^m

C_R = 1.5 MPa (the paper's value), h1 = 1 m, m = -0.16, and n = -0.5 + h/5 for h < 1 m and
n = -0.3 for h >= 1 m (ISO 19906; the paper writes n = -0.5 + h/5, which agrees at h = 1 m).
The reference a DEM ice load on the semi-submersible is set against: 40.1 MN for D = 50 m and
h = 1 m (the paper's text says "kN", a slip: ../shared/seeds/README.md).
"""

from __future__ import annotations


def crushing_load(*, thickness: float, diameter: float, cr: float = 1.5e6, h1: float = 1.0,
                  m: float = -0.16) -> float:
    """Global crushing load F_h [N] of level ice ``thickness`` [m] on a structure of width ``diameter`` [m]."""
    if thickness <= 0.0 or diameter <= 0.0:
        raise ValueError("thickness and diameter must be > 0 m")
    n = -0.5 + thickness / 5.0 if thickness < 1.0 else -0.3
    return cr * thickness * diameter * (thickness / h1) ** n * (diameter / thickness) ** m
