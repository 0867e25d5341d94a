"""The exact stability limit of the ice lattice under pice's integrator, by Bloch waves.

The lattice of ``scenes.level_ice`` is periodic in x and y with a rectangular cell of d x sqrt(3) d
holding 2 elements per layer. A displacement u_j = U_b(j) exp(i k . x_j) turns the stiffness K and
the dashpot matrix C of the infinite lattice into 6 n_b x 6 n_b Hermitian matrices K(k), C(k) for
each wave vector k (n_b the elements of the cell). Mass-normalised (M^-1/2 K M^-1/2), they give the
step's amplification matrix for every k exactly.

The step (``Simulation.step``) is velocity Verlet with the rate terms evaluated at the half-step
velocity. With w_n = v_(n-1/2), the velocity the forces at x_n see, one step of M a = -K x - C w is

    w' = w - h M^-1 (K x + C w),    x' = x + h w',

so (x', w') = A (x, w) with A = [[I - h^2 M^-1 K, h (I - h M^-1 C)], [-h M^-1 K, I - h M^-1 C]].
The step is stable when every eigenvalue of A lies in the unit disk, for every k. For one mode
(K, C commuting) this is omega^2 h^2 / 4 + c h / 2 < 1; in the lattice K and C do not commute (the
highest mode of K is the elements' rotation on tangential springs, that of C their translation on
the normal dashpots), and the exact limit is 20-25 % above the bound from the two largest
eigenvalues taken together.

Each link carries, in each direction, the stiffer of the bond's and the contact's springs and the
stronger of their dashpots: every link matrix is linear in its spring constants with positive
semi-definite parts, so this lattice is stiffer (in the PSD order) than any mixture of bonded links
and contacts that a breaking sheet reaches. A wall or hull adds one more link to a fixed surface
on every element (each element touching the structure at once), in each of the three axis
directions; the worst of the three is taken.
"""

from __future__ import annotations

import functools
import math

import numpy as np

#: an eigenvalue of the amplification matrix counts as unstable above this modulus; rigid-body
#: modes at k = 0 give a defective double eigenvalue 1, which eigvals returns within ~1e-8
RADIUS_TOLERANCE = 1e-6
GRID = 12           # k points per reciprocal axis: a multiple of 6 holds the K and M points
COARSE_GRID = 6     # the bisection's grid (20 wave vectors), checked on GRID's afterwards
BISECTIONS = 20     # the limit to a relative 1e-6 of the undamped bound


def unit_cell(*, d: float, n_layers: int) -> tuple[np.ndarray, np.ndarray]:
    """(basis (2 n_layers, 3) [m], cell (2,) [m]): the elements of one d x sqrt(3) d cell of the lattice."""
    from ..scenes.level_ice import LAYER_SPACING, ROW_SPACING

    basis = []
    for layer in range(n_layers):
        ox = 0.5 * d if layer % 2 else 0.0
        oy = d * ROW_SPACING / 3.0 if layer % 2 else 0.0
        z = layer * d * LAYER_SPACING
        basis += [(ox, oy, z), (ox + 0.5 * d, oy + d * ROW_SPACING, z)]
    return np.array(basis), np.array([d, 2.0 * ROW_SPACING * d])


def cell_links(basis: np.ndarray, cell: np.ndarray, d: float) -> list[tuple[int, int, np.ndarray]]:
    """Every (a, b, r) with element b's image at x_b + shift within d of x_a (r = that vector, m):
    each link of the lattice once from each end."""
    links = []
    for a, xa in enumerate(basis):
        for b, xb in enumerate(basis):
            for i in range(-2, 3):
                for j in range(-2, 3):
                    r = xb + np.array([i * cell[0], j * cell[1], 0.0]) - xa
                    if 1e-9 < np.linalg.norm(r) <= d * (1 + 1e-6):
                        links.append((a, b, r))
    return links


def k_grid(cell: np.ndarray, n: int = GRID) -> np.ndarray:
    """(m, 3) wave vectors [rad/m] of an n x n grid over the cell's reciprocal cell, one of each pair
    k, -k (their matrices are complex conjugates, with the same eigenvalues): m = n^2 / 2 + 2."""
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    i, j = i.ravel(), j.ravel()
    keep = (i * n + j) <= ((-i) % n) * n + (-j) % n
    return np.column_stack([2 * np.pi / cell[0] * i[keep] / n, 2 * np.pi / cell[1] * j[keep] / n,
                            np.zeros(keep.sum())])


def link_stiffness_matrix(n, ca, cb, kn, ks, kt, kb) -> np.ndarray:
    """12 x 12 stiffness of one link (parallel bond or contact) in (u_a, theta_a, u_b, theta_b).

    n: unit vector a -> b; ca, cb: distances of the contact point from the centres [m].
    The contact point moves by delta = u_b - u_a + cb [n]x theta_b + ca [n]x theta_a; the relative
    rotation is theta_b - theta_a; normal/shear and twist/bend springs act on their parts.
    """
    nx = np.array([[0.0, -n[2], n[1]], [n[2], 0.0, -n[0]], [-n[1], n[0], 0.0]])
    nn = np.outer(n, n)
    tang = np.eye(3) - nn
    eye = np.eye(3)
    b_delta = np.hstack([-eye, ca * nx, eye, cb * nx])
    b_theta = np.hstack([np.zeros((3, 3)), -eye, np.zeros((3, 3)), eye])
    return (b_delta.T @ (kn * nn + ks * tang) @ b_delta) + (b_theta.T @ (kt * nn + kb * tang) @ b_theta)


def _link_matrix(n, ca, cb, springs):
    return link_stiffness_matrix(n, ca, cb, *springs)


def bloch_matrices(links, nb: int, ks: np.ndarray, springs, d: float, ground=None) -> np.ndarray:
    """(len(ks), 6 nb, 6 nb) complex K(k) of the links, each with ``springs`` = (k_n, k_s, k_twist, k_bend).

    ground: None, or (springs, normal) of a link from every element to a fixed surface along unit
    ``normal`` (the element's contact point at d/2 along it).
    """
    D = np.zeros((len(ks), 6 * nb, 6 * nb), complex)
    for a, b, r in links:
        L = np.linalg.norm(r)
        k = _link_matrix(r / L, 0.5 * L, 0.5 * L, springs)
        phase = np.exp(1j * ks @ r)
        D[:, 6 * a:6 * a + 6, 6 * a:6 * a + 6] += k[:6, :6]
        D[:, 6 * a:6 * a + 6, 6 * b:6 * b + 6] += phase[:, None, None] * k[:6, 6:]
    if ground is not None:
        g_springs, normal = ground
        g = _link_matrix(np.asarray(normal, float), 0.5 * d, 0.5 * d, g_springs)[:6, :6]
        for a in range(nb):
            D[:, 6 * a:6 * a + 6, 6 * a:6 * a + 6] += g
    return D


def spectral_radius(MK: np.ndarray, MC: np.ndarray, h: float) -> float:
    """Largest |eigenvalue| over k of the step's amplification matrix A(h) (module docstring)."""
    n = MK.shape[-1]
    E = np.broadcast_to(np.eye(n), MK.shape)
    B = E - h * MC
    A = np.concatenate([np.concatenate([E - h * h * MK, h * B], axis=-1),
                        np.concatenate([-h * MK, B], axis=-1)], axis=-2)
    return float(np.abs(np.linalg.eigvals(A)).max())


@functools.lru_cache(maxsize=64)
def exact_limit(*, mass: float, inertia: float, d: float, n_layers: int, springs, dashpots,
                ground=None, grid: int = GRID) -> tuple[float, float]:
    """(the largest stable step h [s], the undamped limit 2 / omega_max [s]) of the lattice.

    Cached: a set-up asks once per parameter set.
    springs, dashpots: (k_n, k_s, k_twist, k_bend) [N/m, N m/rad] and (c_n, c_s, c_twist, c_bend)
    [N s/m, N m s/rad] of every link. ground: None, or (springs, dashpots) of a link from every
    element to a fixed surface (walls, hulls, far-field springs), tried along x, y and z.
    The bisection runs on a coarse grid of wave vectors (COARSE_GRID, which holds the zone
    boundary's K and M points), and its result is checked on the full grid, where the bisection
    goes on only if a mode of the full grid is unstable there.
    """
    from threadpoolctl import threadpool_limits

    # many small eigenproblems: one BLAS thread (threads only contend, and with more MPI ranks than
    # cores they oversubscribe: 4-5x slower measured beside a 2-rank run)
    with threadpool_limits(limits=1):
        return _exact_limit(mass, inertia, d, n_layers, springs, dashpots, ground, grid)


def _exact_limit(mass, inertia, d, n_layers, springs, dashpots, ground, grid):
    basis, cell = unit_cell(d=d, n_layers=n_layers)
    nb = len(basis)
    links = cell_links(basis, cell, d)
    s = np.tile(np.r_[np.full(3, 1 / math.sqrt(mass)), np.full(3, 1 / math.sqrt(inertia))], nb)
    scale = s[:, None] * s[None, :]
    normals = [None] if ground is None else np.eye(3)
    worst = math.inf
    undamped = math.inf
    for normal in normals:
        gk = None if normal is None else (ground[0], normal)
        gc = None if normal is None else (ground[1], normal)
        full = [bloch_matrices(links, nb, k_grid(cell, grid), pair, d, g) * scale
                for pair, g in ((springs, gk), (dashpots, gc))]
        coarse = [bloch_matrices(links, nb, k_grid(cell, min(grid, COARSE_GRID)), pair, d, g) * scale
                  for pair, g in ((springs, gk), (dashpots, gc))]
        hi = 2.0 / math.sqrt(float(np.linalg.eigvalsh(full[0]).max()))
        undamped = min(undamped, hi)
        lo = _bisect(*coarse, 0.0, hi)
        if spectral_radius(*full, lo) > 1 + RADIUS_TOLERANCE:
            lo = _bisect(*full, 0.0, lo)
        worst = min(worst, lo)
    return worst, undamped


def _bisect(MK, MC, lo: float, hi: float) -> float:
    """The largest h in [lo, hi] with every mode of (MK, MC) stable, to 2^-BISECTIONS of hi."""
    if spectral_radius(MK, MC, hi) <= 1 + RADIUS_TOLERANCE:
        return hi  # the dashpots do not lower the undamped limit (none, or too weak to matter)
    for _ in range(BISECTIONS):
        mid = 0.5 * (lo + hi)
        if spectral_radius(MK, MC, mid) <= 1 + RADIUS_TOLERANCE:
            lo = mid
        else:
            hi = mid
    return lo
