"""The level-ice builder: hexagonal close packing, bonds, flotation at rest."""

import math

import numpy as np
import pytest

from pice.job import parse_job
from pice.scenes.level_ice import build_level_ice, layer_count

BASE = {"bond": {"normal_stiffness": 1.72e7, "normal_strength": 1.5e6, "friction": 0.3}}


def _sheet(**ice):
    return build_level_ice(parse_job({**BASE, "water": {"density": 1035.0}, "ice": ice}))


@pytest.mark.nojit
def test_reference_sheet_has_about_92000_elements():
    """Table 4 of Zhu & Ji (2022): a 200 m x 400 m sheet of 1 m elements has 'about 92,000' elements.

    One HCP layer holds 1 / (sqrt(3)/2 d^2) elements per m^2: 80,000 / 0.866 = 92,376 before the
    edge rows are trimmed to fit inside the sheet. Accept within 1 % of 92,000.
    """
    p, geo = _sheet(length=400.0, width=200.0, density=920.0)
    assert geo.n_layers == 1
    assert abs(p.n - 92_000) / 92_000 < 0.01
    # every interior element of a triangular lattice has 6 bonds; the sheet fits inside its footprint
    bonds = np.count_nonzero(p.bond_gid >= 0, axis=1)
    assert bonds.max() == 6 and np.median(bonds) == 6
    assert p.x[:, 0].min() >= 0.5 - 1e-9 and p.x[:, 0].max() <= 400.0 - 0.5 + 1e-9
    assert p.x[:, 1].min() >= 0.5 - 1e-9 and p.x[:, 1].max() <= 200.0 - 0.5 + 1e-9
    # each bond is stored at both ends, the counts agree, and bond rest lengths equal d
    assert p.bond_count() * 2 == np.count_nonzero(p.bond_gid >= 0)
    L0 = p.bond_L0[p.bond_gid >= 0]
    assert np.allclose(L0, 1.0, rtol=1e-12)


@pytest.mark.nojit
def test_thicker_ice_stacks_hcp_layers():
    """HCP layers are d sqrt(2/3) apart; an A-B stack gives 9 bonds (6 in-plane + 3 across) inside."""
    assert layer_count(thickness=1.0, element_diameter=1.0) == 1
    assert layer_count(thickness=1.0 + math.sqrt(2 / 3), element_diameter=1.0) == 2
    assert layer_count(thickness=1.0 + 2 * math.sqrt(2 / 3), element_diameter=1.0) == 3
    p, geo = _sheet(length=12.0, width=10.0, thickness=1.0 + math.sqrt(2 / 3))
    assert geo.n_layers == 2
    z = np.unique(np.round(p.x[:, 2] - p.x[:, 2].min(), 9))
    assert np.allclose(z, [0.0, math.sqrt(2 / 3)])
    bonds = np.count_nonzero(p.bond_gid >= 0, axis=1)
    assert bonds.max() == 9
    # every bond joins touching spheres: rest length = d
    assert np.allclose(p.bond_L0[p.bond_gid >= 0], 1.0, rtol=1e-9)


@pytest.mark.nojit
def test_bond_slots_are_symmetric():
    """Bond i->j in slot s has its mate j->i in slot bond_mate[i, s] with the same rest length."""
    p, _ = _sheet(length=8.0, width=6.0)
    for i in range(p.n):
        for s in range(p.bond_j.shape[1]):
            j = p.bond_j[i, s]
            if j < 0:
                continue
            m = p.bond_mate[i, s]
            assert p.bond_j[j, m] == i and p.bond_gid[j, m] == p.gid[i]
            assert p.bond_L0[j, m] == p.bond_L0[i, s]
