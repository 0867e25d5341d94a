"""The water's drag on level ice: skin friction per unit area (the default) or Morison form drag.

References: the ice-ocean stress tau = rho_w C_w |u_r| u_r on the sheet's underside (McPhee; C_w of
0.003-0.006 under sea ice, 0.0055 the default, ../shared/notes/ice_failure.md), so a sheet at rest
in a current u feels rho_w C_w u^2 times its area in all, whatever its element size; and Eq. 8 of
Zhu & Ji (2022) (../shared/seeds/000_d6dfa5ea71378166.txt): 1/2 C_d D^2 rho_w u^2 on every element.
"""

import pytest

from pice.job import parse_job
from pice.simulation import Simulation

U, RHO_W = 0.8, 1030.0


def _sheet_force(d, thickness=1.0, volume="cell", **water):
    job = parse_job({
        "run": {"duration": 1.0},
        "water": {"density": RHO_W, "current": [U, 0.0], **water},
        "ice": {"length": 24.0, "width": 12.0, "thickness": thickness, "element_diameter": d,
                "element_volume": volume, "youngs_modulus": 1e9, "flexural_strength": 5e5,
                "compressive_strength": 2.5e6},
    })
    sim = Simulation(job)
    p = sim.p
    return float(p.force[:p.nlocal, 0].sum()), float(p.cell_area[:p.nlocal].sum()), p.nlocal


@pytest.mark.parametrize("d", [1.0, 2.0])
def test_skin_drag_is_the_stress_times_the_sheet_area(d):
    """At rest in the current the sheet's x force is rho_w C_w u^2 times its area (1e-12: the bonds
    and contacts are at rest and carry nothing), for 1 m and 2 m elements alike."""
    fx, area, _ = _sheet_force(d)
    assert fx == pytest.approx(RHO_W * 0.0055 * U * U * area, rel=1e-12)
    assert area == pytest.approx(24.0 * 12.0, rel=0.2)  # the sheet's plan area (edges of a hexagonal packing)


def test_morison_drag_is_eq8_on_every_element():
    """ice_drag = "morison": 1/2 C_d D^2 rho_w u^2 times the submerged fraction on each element; the
    sheet's total then grows as 1/D with the element size D at a fixed area (1e-9: the floating
    height is found by a root solve)."""
    fx, _, n = _sheet_force(1.0, ice_drag="morison", drag_coefficient=1.0)
    frac = 920.0 / RHO_W  # the submerged fraction of a floating cell element's height (ice density 920)
    assert fx == pytest.approx(n * 0.5 * 1.0 * 1.0 * RHO_W * U * U * frac, rel=1e-9)


def test_skin_drag_of_a_sheet_of_two_layers_acts_once():
    """A 1.6 m sheet of 1 m spheres is two HCP layers, both submerged: the underside's stress acts
    once, rho_w C_w u^2 times the plan area (the bottom layer's footprints, sqrt(3)/2 d^2 each), not
    once a layer. 1.5 %: each element takes half its footprint's stress, and the upper layer lacks a
    row and a column at the edges (1.1 % of the bottom layer's count here)."""
    fx, _, n = _sheet_force(1.0, thickness=1.6, volume="sphere")
    from pice.scenes.level_ice import hcp_positions, layer_count

    assert layer_count(thickness=1.6, element_diameter=1.0) == 2
    bottom = len(hcp_positions(length=24.0, width=12.0, d=1.0, n_layers=1))
    assert n > 1.8 * bottom
    assert fx == pytest.approx(RHO_W * 0.0055 * U * U * bottom * 3 ** 0.5 / 2, rel=0.015)
