"""Breakable floes (issue 14: "a floe may optionally break, with bonded floes"): the floe field of
[floes] built of the bonded [ice] elements (scenes/bonded_floes.py).

- Geometry: every element's sphere lies inside its floe's polygon, no bond joins two floes, each
  floe is one bonded piece, and the elements cover the field's area to within the jagged rim of
  one element row along each floe's edges.
- Drift: elements of a floe move together, so its bonds carry nothing and each element obeys the
  skin-drag equation m dv/dt = rho_w C_w A (u - v)^2, whose solution from v(0) = 0 is
  v(t) = u - 1 / (1 / u + k t) with k = rho_w C_w A / m = rho_w C_w / (rho_i h) (cell elements).
"""

from __future__ import annotations

import math

import numpy as np
from scenes import bonded_floe_job, job_from_text
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from pice.scenes.bonded_floes import bonded_floe_positions
from pice.scenes.floe_field import floe_field
from pice.scenes.level_ice import build_level_ice, hcp_positions
from pice.simulation import Simulation


def test_bonded_floes_fill_their_polygons_and_bond_within_a_floe():
    job = job_from_text(bonded_floe_job())
    p, geo = build_level_ice(job)
    fl = job.floes
    field = floe_field(area=fl.area, size=fl.size, thickness=(0.5, 0.5), concentration=fl.concentration,
                       seed=fl.seed)
    x0, y0, x1, y1 = fl.area
    lattice = hcp_positions(length=x1 - x0, width=y1 - y0, d=1.0, n_layers=1) + [x0, y0, 0.0]
    x, floe = bonded_floe_positions(lattice, fl, job.ice, d=1.0)
    assert np.array_equal(x[:, :2], p.x[:, :2])
    r = 0.5
    for k, poly in enumerate(field.polygons):  # each sphere inside its polygon, 1e-12 m round-off
        pts = x[floe == k, :2]
        for a, b in zip(poly, np.roll(poly, -1, axis=0)):
            e = b - a
            inward = np.array([-e[1], e[0]]) / math.hypot(*e)
            assert ((pts - a) @ inward).min() >= r - 1e-12
    i, slot = np.nonzero(p.bond_j >= 0)
    j = p.bond_j[i, slot]
    assert len(i) > 0 and np.array_equal(floe[i], floe[j]), "a bond joins two floes"
    graph = coo_matrix((np.ones(len(i)), (i, j)), shape=(p.n, p.n))
    n_pieces, label = connected_components(graph, directed=False)
    assert n_pieces == len(field.polygons)  # one bonded piece a floe
    for k in range(len(field.polygons)):
        assert len(np.unique(label[floe == k])) == 1
    # covered area: the elements' cells against the polygons, short by at most a rim of one element
    # row (width d) along each floe's perimeter, and never more than the polygons
    cells = p.n * geo.cell_area
    areas = field.areas
    perimeter = sum(np.linalg.norm(np.roll(q, -1, axis=0) - q, axis=1).sum() for q in field.polygons)
    assert areas.sum() - 1.0 * perimeter <= cells <= areas.sum()


def test_bonded_floes_drift_up_to_the_current_as_the_skin_drag_equation_says():
    u, cw = 0.3, 0.05
    job = job_from_text(bonded_floe_job(wall_x=100.0, speed=0.0, current=u, skin=cw))
    sim = Simulation(job)
    k = 1025.0 * cw / (920.0 * 0.5)
    sim.advance(int(round(10.0 / sim.dt)))
    t = sim.c.time
    v = sim.p.v[:sim.p.nlocal]
    expected = u - 1.0 / (1.0 / u + k * t)
    # explicit integration of a smooth ODE at dt ~ 2e-4 s: its error is ~dt k u^2 ~ 1e-6 m/s; the
    # bonds carry no load, so every element moves at the same speed (1e-9 m/s: round-off)
    assert abs(v[:, 0].mean() - expected) < 1e-5 * u
    assert np.ptp(v[:, 0]) < 1e-9 and np.abs(v[:, 1]).max() < 1e-9
