"""Bonded level ice in hexagonal close packing (HCP).

One layer (a triangular lattice in x-y) when the thickness equals the element diameter d; for
thicker ice, HCP layers stacked A-B-A-B at a spacing d sqrt(2/3), as many as fit the thickness.
Neighbours at one diameter are bonded. 200 m x 400 m at d = 1 m gives 92,376 elements, the
"about 92,000" of Table 4 of Zhu & Ji (2022).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq
from scipy.spatial import cKDTree

from ..errors import JobError
from ..state import BOND_HIST, KIND_ICE, MAX_BONDS, Particles
from .bonded_floes import bonded_floe_positions, same_floe

LAYER_SPACING = math.sqrt(2.0 / 3.0)  # HCP layer spacing / d
ROW_SPACING = math.sqrt(3.0) / 2.0    # in-plane row spacing / d


@dataclass(frozen=True)
class SheetGeometry:
    """Lattice facts the rest of the code needs (all lengths in m)."""

    n_layers: int
    spacing: float          # bond rest length = element diameter
    cell_area: float        # in-plane footprint of one element
    layer_height: float     # thickness / n_layers
    actual_thickness: float  # extent of the stacked spheres


def layer_count(*, thickness: float, element_diameter: float) -> int:
    """Number of HCP layers whose stacked extent d + (n-1) d sqrt(2/3) is closest to the thickness."""
    return max(1, int(round((thickness - element_diameter) / (element_diameter * LAYER_SPACING))) + 1)


def lattice_rows_columns(*, length: float, width: float, d: float) -> tuple[int, int]:
    """(rows along y, elements per row along x) of an A layer of HCP in a length x width [m] sheet of
    elements of diameter d [m] (a B layer may hold a row and a column fewer)."""
    nrows = int(math.floor((width - d) / (d * ROW_SPACING) + 1e-9)) + 1
    ncols = int(math.floor((length - d) / d + 1e-9)) + 1
    return nrows, ncols


def lattice_count(*, length: float, width: float, d: float, n_layers: int) -> int:
    """Elements of the HCP block ``hcp_positions`` builds, counted without building it (the memory a
    job needs is known before anything is allocated: pice/memory.py)."""
    nrows, ncols = lattice_rows_columns(length=length, width=width, d=d)
    total = 0
    for layer in range(min(n_layers, 2)):  # layers alternate A, B, A, ...
        ox = 0.5 * d if layer % 2 else 0.0
        oy = d * ROW_SPACING / 3.0 if layer % 2 else 0.0
        rows = min(nrows, max(0, int(math.floor((width - d + 1e-9 - oy) / (d * ROW_SPACING))) + 1))
        per_row = [min(ncols, max(0, int(math.floor((length - d + 1e-9 - ox - shift) / d)) + 1))
                   for shift in (0.0, 0.5 * d)]
        total += (per_row[0] * ((rows + 1) // 2) + per_row[1] * (rows // 2)) * ((n_layers - layer + 1) // 2)
    return total


def hcp_positions(*, length: float, width: float, d: float, n_layers: int) -> np.ndarray:
    """Centres of an HCP block [m] with its lower-left sphere at the origin, bottom layer at z = 0."""
    nrows, ncols = lattice_rows_columns(length=length, width=width, d=d)
    pts = []
    for layer in range(n_layers):
        # B layers sit over the centroids of A-layer triangles
        ox = 0.5 * d if layer % 2 else 0.0
        oy = d * ROW_SPACING / 3.0 if layer % 2 else 0.0
        z = layer * d * LAYER_SPACING
        for row in range(nrows):
            y = oy + row * d * ROW_SPACING
            if y > width - d + 1e-9:
                continue
            shift = 0.5 * d if row % 2 else 0.0
            xs = ox + shift + d * np.arange(ncols)
            xs = xs[xs <= length - d + 1e-9]
            pts.append(np.column_stack([xs, np.full(len(xs), y), np.full(len(xs), z)]))
    return np.concatenate(pts) + 0.5 * d  # the sheet starts at the origin, not at the first centre


def rest_elevation(*, mass: float, radius: float, cell_area: float, half_height: float,
                   rho_w: float, level: float) -> float:
    """Centre height [m] at which one element floats in still water (Archimedes, solved to 1e-12 m;
    gravity cancels: the displaced mass equals the element's)."""
    from ..kernels.hydro import submerged

    def excess(zc):
        return rho_w * submerged(zc, radius, cell_area, half_height, level)[0] - mass

    top = half_height if cell_area > 0 else radius
    if excess(level - top) < 0:
        raise ValueError("the element is denser than water and sinks")
    return brentq(excess, level - top, level + top, xtol=1e-13, rtol=1e-15)


def build_level_ice(job) -> tuple[Particles, SheetGeometry]:
    """Particles and bonds of the level-ice sheet of ``job``, floating at rest if the job has water."""
    ice = job.ice
    if ice is None:  # a scene without level ice (floes, bodies): no elements
        return empty_particles(), SheetGeometry(n_layers=1, spacing=1.0, cell_area=0.0, layer_height=0.0,
                                                actual_thickness=0.0)
    d = ice.element_diameter
    r = 0.5 * d
    # a "cell" element stands for the whole thickness of the plate: one layer whatever the thickness
    n_layers = 1 if ice.element_volume == "cell" else layer_count(thickness=ice.thickness, element_diameter=d)
    bonded_floes = job.floes is not None and job.floes.breakable
    if bonded_floes:  # the floe field of [floes], built of these elements (scenes/bonded_floes.py)
        try:
            x0, y0, x1, y1 = job.floes.area
            lattice = hcp_positions(length=x1 - x0, width=y1 - y0, d=d, n_layers=n_layers) + [x0, y0, 0.0]
            x, floe = bonded_floe_positions(lattice, job.floes, ice, d=d)
        except ValueError as exc:
            raise JobError(f"{job.source}: floes: {exc}") from None
    else:
        x = hcp_positions(length=ice.length, width=ice.width, d=d, n_layers=n_layers)
        x[:, 0] += ice.origin[0]
        x[:, 1] += ice.origin[1]
    n = len(x)
    cell_area = d * d * ROW_SPACING
    layer_height = ice.thickness / n_layers
    if ice.element_volume == "cell":
        volume = cell_area * layer_height
        area_arr, half = np.full(n, cell_area), np.full(n, 0.5 * layer_height)
    else:
        volume = math.pi * d ** 3 / 6.0
        area_arr, half = np.zeros(n), np.full(n, r)
    mass = ice.density * volume
    inertia = 0.4 * mass * r * r
    # float the sheet: the bottom layer's centre at the single-element rest height, so a one-layer
    # sheet starts exactly in hydrostatic equilibrium
    if job.water is not None and job.gravity > 0:
        if n_layers == 1:
            z0 = rest_elevation(mass=mass, radius=r, cell_area=area_arr[0], half_height=half[0],
                                rho_w=job.water.density, level=job.water.level)
            x[:, 2] += z0 - r
        else:
            draft = ice.thickness * ice.density / job.water.density
            x[:, 2] += job.water.level - draft
    v = np.zeros((n, 3))
    v[:, 0], v[:, 1] = job.floes.velocity if bonded_floes else ice.velocity
    slots = 6 if n_layers == 1 else MAX_BONDS  # bonds per element in the lattice: memory follows it
    p = Particles(
        gid=np.arange(n, dtype=np.int64), x=x, v=v, w=np.zeros((n, 3)),
        radius=np.full(n, r), mass=np.full(n, mass), inertia=np.full(n, inertia),
        kind=np.full(n, KIND_ICE, dtype=np.int8), volume=np.full(n, volume),
        cell_area=area_arr, half_height=half,
        bond_gid=np.full((n, slots), -1, dtype=np.int64),
        bond_j=np.full((n, slots), -1, dtype=np.int32),
        bond_mate=np.full((n, slots), -1, dtype=np.int32),
        bond_L0=np.zeros((n, slots)), bond_hist=np.zeros((n, slots, BOND_HIST)), nlocal=n)
    pairs = cKDTree(x).query_pairs(d * (1.0 + 1e-6), output_type="ndarray")
    if bonded_floes:  # no bond between two floes
        pairs = same_floe(pairs, floe)
    add_bonds(p, pairs)
    geo = SheetGeometry(n_layers=n_layers, spacing=d, cell_area=cell_area, layer_height=layer_height,
                        actual_thickness=ice.thickness if ice.element_volume == "cell" and n_layers == 1
                        else d + (n_layers - 1) * d * LAYER_SPACING)
    return p, geo


def add_bonds(p: Particles, pairs: np.ndarray) -> None:
    """Bond the (i, j) local-index pairs at their current distance (the rest length)."""
    nslot = np.count_nonzero(p.bond_j >= 0, axis=1)
    cap = p.bond_j.shape[1]
    for i, j in pairs:
        si, sj = nslot[i], nslot[j]
        if si >= cap or sj >= cap:
            raise ValueError(f"element {p.gid[i]} or {p.gid[j]} has more than {cap} bonds")
        L0 = float(np.linalg.norm(p.x[j] - p.x[i]))
        p.bond_j[i, si], p.bond_j[j, sj] = j, i
        p.bond_gid[i, si], p.bond_gid[j, sj] = p.gid[j], p.gid[i]
        p.bond_mate[i, si], p.bond_mate[j, sj] = sj, si
        p.bond_L0[i, si] = p.bond_L0[j, sj] = L0
        nslot[i] += 1
        nslot[j] += 1


def empty_particles() -> Particles:
    """No elements: the particle arrays of a scene without level ice."""
    return Particles(
        gid=np.zeros(0, np.int64), x=np.zeros((0, 3)), v=np.zeros((0, 3)), w=np.zeros((0, 3)),
        radius=np.zeros(0), mass=np.zeros(0), inertia=np.zeros(0), kind=np.zeros(0, np.int8), volume=np.zeros(0),
        cell_area=np.zeros(0), half_height=np.zeros(0), bond_gid=np.full((0, 6), -1, np.int64),
        bond_j=np.full((0, 6), -1, np.int32), bond_mate=np.full((0, 6), -1, np.int32), bond_L0=np.zeros((0, 6)),
        bond_hist=np.zeros((0, 6, BOND_HIST)), nlocal=0)
