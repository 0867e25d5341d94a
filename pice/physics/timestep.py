"""Stable time step of the explicit integrator.

Velocity Verlet on a linear system is stable when dt < 2 / omega_max, omega_max^2 the largest
eigenvalue of K v = omega^2 M v. For a lattice of identical elements that eigenvalue is a property
of the lattice, so we compute it exactly on a small periodic patch of the same packing: every
neighbour link carries the stiffer of the bond and the contact springs in each direction (normal
k_n, shear k_s at the contact point, twisting and bending), so the limit also holds once bonds
have broken and contacts have taken their place. A wall adds at most k_wall/m (Weyl's inequality).
Dashpots shrink the limit: with damping rates up to c_max (the largest eigenvalue of M^-1 C, C the
bond dashpots assembled like K) the step is stable when omega_max^2 dt^2 / 4 + c_max dt / 2 < 1, i.e.
for zeta = c_max / (2 omega_max). The bond dashpots are set at ``damping_ratio`` of critical for one
bond between two free elements, so the lattice's highest modes see a zeta several times larger.

dt_stable = 2 / omega_max * (sqrt(1 + zeta^2) - zeta); `dt = "auto"` uses ``run.dt_safety``
(default 0.5) of it. Assumption: no element gains more contacts than it had lattice neighbours
(rafting piles can; the health check stops such a run with a diagnostic).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class StepLimit:
    """The stability limit [s] and the step chosen [s], with what sets the limit."""

    stable: float
    chosen: float
    safety: float
    governed_by: str


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


def lattice_omega_max(*, n_layers: int, d: float, mass: float, inertia: float, kn: float, ks: float,
                      kt: float, kb: float, cells: int = 12) -> float:
    """Largest angular frequency [rad/s] of an infinite HCP lattice with one spring set per link.

    Assembled on a periodic cells x cells patch (even, so the zone-boundary modes are sampled).
    """
    from scipy.linalg import eigh
    from scipy.spatial import cKDTree

    from ..scenes.level_ice import ROW_SPACING, hcp_positions

    lx, ly = cells * d, cells * ROW_SPACING * d
    x = hcp_positions(length=lx + 0.25 * d, width=ly + 0.25 * d, d=d, n_layers=n_layers)
    x = x[(x[:, 0] < lx + 1e-9) & (x[:, 1] < ly + 1e-9)]
    x[:, :2] -= x[:, :2].min(axis=0)
    box = np.array([lx, ly, 1e6])
    tree = cKDTree(np.mod(x, box), boxsize=box)
    pairs = tree.query_pairs(d * (1 + 1e-6), output_type="ndarray")
    ndof = 6 * len(x)
    K = np.zeros((ndof, ndof))
    for a, b in pairs:
        dvec = x[b] - x[a]
        dvec[:2] -= box[:2] * np.round(dvec[:2] / box[:2])  # minimum image
        n = dvec / np.linalg.norm(dvec)
        k = link_stiffness_matrix(n, 0.5 * d, 0.5 * d, kn, ks, kt, kb)
        idx = np.r_[6 * a:6 * a + 6, 6 * b:6 * b + 6]
        K[np.ix_(idx, idx)] += k
    m = np.tile(np.r_[np.full(3, mass), np.full(3, inertia)], len(x))
    scale = 1.0 / np.sqrt(m)
    lam = eigh(K * scale[:, None] * scale[None, :], eigvals_only=True,
               subset_by_index=[ndof - 1, ndof - 1])[0]
    return math.sqrt(max(lam, 0.0))


def stable_step(*, mass: float, inertia: float, d: float, n_layers: int, bond, contact,
                wall_stiffness: float = 0.0, damping_ratio: float = 0.0,
                contact_damping_ratio: float = 0.0) -> tuple[float, str]:
    """Stability limit [s] of the lattice with, per link, the stiffer of bond and contact springs
    and the stronger of their dashpots.

    bond: (k_n, k_s, k_twist, k_bend); contact: (k_n, k_t); damping ratios of the bond dashpots and
    of the contact's normal dashpot (from its restitution). Returns (limit, what governs it).
    """
    kn = max(bond[0], contact[0])
    ks = max(bond[1], contact[1])
    omega = lattice_omega_max(n_layers=n_layers, d=d, mass=mass, inertia=inertia, kn=kn, ks=ks,
                              kt=bond[2], kb=bond[3])
    omega = math.sqrt(omega ** 2 + wall_stiffness / mass)
    zeta = 0.0
    if damping_ratio > 0.0 or contact_damping_ratio > 0.0:
        # the bond dashpots of BondParams.as_array and the contact's normal dashpot (kernels.contacts),
        # assembled like the springs
        z, m_red, i_red = damping_ratio, 0.5 * mass, 0.5 * inertia
        cn = max(2 * z * math.sqrt(m_red * bond[0]), 2 * contact_damping_ratio * math.sqrt(m_red * contact[0]))
        c_max = lattice_omega_max(n_layers=n_layers, d=d, mass=mass, inertia=inertia,
                                  kn=cn, ks=2 * z * math.sqrt(m_red * bond[1]),
                                  kt=2 * z * math.sqrt(i_red * bond[2]), kb=2 * z * math.sqrt(i_red * bond[3])) ** 2
        zeta = c_max / (2.0 * omega)
    factor = math.sqrt(1.0 + zeta ** 2) - zeta
    parts = []
    parts.append("bond" if bond[0] >= contact[0] else "contact")
    if ks > bond[1]:
        parts.append("contact tangential")
    return 2.0 / omega * factor, (f"highest lattice mode of elements of {mass:.4g} kg with {' and '.join(parts)} "
                                  f"springs (k_n {kn:.3g} N/m)")


def choose_step(*, requested, safety: float, stable: float, governed_by: str, allow_unstable: bool,
                source: str = "<job>") -> StepLimit:
    """Pick dt: ``safety`` x the limit for "auto"; refuse a requested dt above the limit unless allowed."""
    from ..errors import JobError

    if requested == "auto":
        return StepLimit(stable=stable, chosen=safety * stable, safety=safety, governed_by=governed_by)
    if requested > stable and not allow_unstable:
        raise JobError(f"{source}: run.dt = {requested}: above the stability limit {stable:.4g} s "
                       f"({governed_by}); use dt <= {stable:.4g} s or dt = \"auto\" "
                       "(run.allow_unstable_dt = true overrides, for testing only)")
    return StepLimit(stable=stable, chosen=float(requested), safety=float(requested) / stable,
                     governed_by=governed_by)
