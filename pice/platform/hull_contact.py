"""Contact of ice spheres with a moving rigid hull (triangle mesh in the body frame).

Each rank evaluates its own ice against every body: a particle is taken to the body frame, the
triangles registered in its grid cell are searched for the closest point, and if that point is
nearer than the radius the shared contact law acts (kernels/contact_law.py, as for walls and
ice-ice contacts). The reaction on the body (force, and moment
about its centre of gravity) is summed for the rank-0 reduction.

The triangle grid (body frame): origin (3,), cell size, dims (3,), cell_start (ncell+1,),
cell_tris: triangles whose bounding box, grown by the largest radius, overlaps each cell.
law: physics.contact.ContactLaw (kn, kt [N/m], zeta, mu).

``hull_forces`` is a numba kernel (a pure function of arrays and scalars: no MPI, no I/O), run by
every rank on its own ice; ``Hull`` and ``build_triangle_grid`` set it up (platform.build).
"""

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from ..kernels import JIT
from ..kernels.contact_law import contact_energy, contact_height, crushing_cap, plastic_normal_force, tangential_force
from ..kernels.geometry import closest_point_on_triangle, rotation_matrix
from ..physics.contact import ContactLaw


@dataclass
class Hull:
    """One body's surface for the ice-hull contact kernel (body frame) and its contact law."""

    name: str
    vertices: np.ndarray      # (nv, 3) [m]
    triangles: np.ndarray     # (nt, 3)
    grid: tuple               # build_triangle_grid
    law: ContactLaw           # the ice-hull contact law (kn, kt [N/m], zeta, mu)


def build_triangle_grid(vertices: np.ndarray, triangles: np.ndarray, *, reach: float):
    """Body-frame cell grid over the hull's bounding box grown by ``reach`` [m] (numpy, at set-up)."""
    lo = vertices.min(axis=0) - reach
    hi = vertices.max(axis=0) + reach
    extent = hi - lo
    cell = max(2.0 * reach, float(extent.max()) / 64.0)
    dims = np.maximum(1, np.ceil(extent / cell).astype(np.int64))
    buckets = [[] for _ in range(int(np.prod(dims)))]
    for t, tri in enumerate(triangles):
        p = vertices[tri]
        a = np.clip(((p.min(axis=0) - reach - lo) / cell).astype(np.int64), 0, dims - 1)
        b = np.clip(((p.max(axis=0) + reach - lo) / cell).astype(np.int64), 0, dims - 1)
        for k in range(a[2], b[2] + 1):
            for j in range(a[1], b[1] + 1):
                for i in range(a[0], b[0] + 1):
                    buckets[(k * dims[1] + j) * dims[0] + i].append(t)
    start = np.zeros(len(buckets) + 1, np.int64)
    start[1:] = np.cumsum([len(b) for b in buckets])
    tris = np.array([t for b in buckets for t in b], dtype=np.int64)
    return lo, float(cell), dims, start, tris


@njit(**JIT)
def hull_forces(nlocal, x, v, w, radius, mass, cell_area, half_height, pose, vertices, triangles, grid_origin,
                cell, dims, cell_start, cell_tris, law, hist, dt, force, torque):
    """Add hull contact forces to owned particles; return (load, energy, crushing): the (6,) load on
    the body (force [N], moment about its CG [N m]) from this rank's ice, the elastic energy stored in
    the contacts [J] and the number of contacts in plastic flow (crushing).

    pose: (13,) x_cg, q (w, x, y, z), v_cg, omega (space frame). hist: (n, 4) tangential force [N]
    and plastic penetration [m]. The crushing area is the chord of the sphere's section by the hull's
    surface times the element's contact height, as for walls.
    """
    xc = pose[0:3]
    R = rotation_matrix(pose[3:7])
    vb = pose[7:10]
    om = pose[10:13]
    load = np.zeros(6)
    energy = 0.0
    ncrushing = 0
    pb = np.empty(3)
    cp = np.empty(3)
    best = np.empty(3)
    # the grid's bounding sphere in the space frame: most elements are outside it, and are skipped
    # before the turn into the body frame (their history is zero already, or zeroed now)
    half = 0.5 * cell * dims
    mid0, mid1, mid2 = grid_origin[0] + half[0], grid_origin[1] + half[1], grid_origin[2] + half[2]
    sc0 = xc[0] + R[0, 0] * mid0 + R[0, 1] * mid1 + R[0, 2] * mid2
    sc1 = xc[1] + R[1, 0] * mid0 + R[1, 1] * mid1 + R[1, 2] * mid2
    sc2 = xc[2] + R[2, 0] * mid0 + R[2, 1] * mid1 + R[2, 2] * mid2
    reach2 = (half[0] * half[0] + half[1] * half[1] + half[2] * half[2]) * (1.0 + 1e-6)
    for i in range(nlocal):
        s0, s1, s2 = x[i, 0] - sc0, x[i, 1] - sc1, x[i, 2] - sc2
        if s0 * s0 + s1 * s1 + s2 * s2 > reach2:
            if hist[i, 0] != 0.0 or hist[i, 1] != 0.0 or hist[i, 2] != 0.0 or hist[i, 3] != 0.0:
                hist[i, :] = 0.0
            continue
        r = radius[i]
        d0, d1, d2 = x[i, 0] - xc[0], x[i, 1] - xc[1], x[i, 2] - xc[2]
        for k in range(3):
            pb[k] = R[0, k] * d0 + R[1, k] * d1 + R[2, k] * d2  # R^T (x - x_cg)
        inside = True
        cidx = 0
        for k in range(3):
            c = int(math.floor((pb[k] - grid_origin[k]) / cell))
            if c < 0 or c >= dims[k]:
                inside = False
                break
        if not inside:
            hist[i, :] = 0.0
            continue
        ci = int((pb[0] - grid_origin[0]) / cell)
        cj = int((pb[1] - grid_origin[1]) / cell)
        ck = int((pb[2] - grid_origin[2]) / cell)
        cidx = (ck * dims[1] + cj) * dims[0] + ci
        dmin = r
        found = False
        tbest = -1
        for p in range(cell_start[cidx], cell_start[cidx + 1]):
            t = cell_tris[p]
            closest_point_on_triangle(pb, vertices[triangles[t, 0]], vertices[triangles[t, 1]],
                                      vertices[triangles[t, 2]], cp)
            dd = math.sqrt((pb[0] - cp[0]) ** 2 + (pb[1] - cp[1]) ** 2 + (pb[2] - cp[2]) ** 2)
            if dd < dmin and dd > 0.0:
                dmin = dd
                found = True
                tbest = t
                best[:] = cp
        if not found:
            hist[i, :] = 0.0
            continue
        # outward normal (body frame): from the surface towards the centre, or away from it when the
        # centre has crossed the surface (a crushing element, up to one radius deep), judged by the
        # closest triangle's outward face normal (the hull's triangles face outwards)
        nb0, nb1, nb2 = (pb[0] - best[0]) / dmin, (pb[1] - best[1]) / dmin, (pb[2] - best[2]) / dmin
        va, vb_, vc = vertices[triangles[tbest, 0]], vertices[triangles[tbest, 1]], vertices[triangles[tbest, 2]]
        e10, e11, e12 = vb_[0] - va[0], vb_[1] - va[1], vb_[2] - va[2]
        e20, e21, e22 = vc[0] - va[0], vc[1] - va[1], vc[2] - va[2]
        side = nb0 * (e11 * e22 - e12 * e21) + nb1 * (e12 * e20 - e10 * e22) + nb2 * (e10 * e21 - e11 * e20)
        depth = r - dmin
        if side < 0.0:
            nb0, nb1, nb2 = -nb0, -nb1, -nb2
            depth = r + dmin
        n0 = R[0, 0] * nb0 + R[0, 1] * nb1 + R[0, 2] * nb2
        n1 = R[1, 0] * nb0 + R[1, 1] * nb1 + R[1, 2] * nb2
        n2 = R[2, 0] * nb0 + R[2, 1] * nb1 + R[2, 2] * nb2
        delta = depth
        c0, c1, c2 = x[i, 0] - r * n0, x[i, 1] - r * n1, x[i, 2] - r * n2  # contact point
        a0, a1, a2 = c0 - xc[0], c1 - xc[1], c2 - xc[2]
        # velocity of the sphere's surface point minus the hull's at the contact point
        u0 = v[i, 0] + w[i, 1] * (-r * n2) - w[i, 2] * (-r * n1) - (vb[0] + om[1] * a2 - om[2] * a1)
        u1 = v[i, 1] + w[i, 2] * (-r * n0) - w[i, 0] * (-r * n2) - (vb[1] + om[2] * a0 - om[0] * a2)
        u2 = v[i, 2] + w[i, 0] * (-r * n1) - w[i, 1] * (-r * n0) - (vb[2] + om[0] * a1 - om[1] * a0)
        un = u0 * n0 + u1 * n1 + u2 * n2
        h = hist[i]
        cap = crushing_cap(law.crushing_pressure, 2.0 * r * delta - delta * delta if delta < r else r * r,
                           contact_height(r, cell_area[i], half_height[i]))
        dp0 = h[3]
        fn, h[3] = plastic_normal_force(law.kn, law.zeta, mass[i], delta, dp0, un, cap)
        ncrushing += 1 if h[3] > dp0 else 0
        h[0], h[1], h[2], hm = tangential_force(h[0], h[1], h[2], n0, n1, n2, u0, u1, u2, un, law.kt, dt,
                                                law.mu * fn)
        energy += contact_energy(law.kn, law.kt, delta - h[3], hm)
        f0, f1, f2 = fn * n0 + h[0], fn * n1 + h[1], fn * n2 + h[2]
        force[i, 0] += f0
        force[i, 1] += f1
        force[i, 2] += f2
        torque[i, 0] += (-r * n1) * f2 - (-r * n2) * f1
        torque[i, 1] += (-r * n2) * f0 - (-r * n0) * f2
        torque[i, 2] += (-r * n0) * f1 - (-r * n1) * f0
        load[0] -= f0
        load[1] -= f1
        load[2] -= f2
        load[3] -= a1 * f2 - a2 * f1
        load[4] -= a2 * f0 - a0 * f2
        load[5] -= a0 * f1 - a1 * f0
    return load, energy, ncrushing


class HullContactTerm:
    """Contact of this rank's ice with every hull (``hull_forces``), at the poses rank 0 broadcast.

    ``poses`` (n_bodies, 13) is set by the simulation before each evaluation; after it ``loads``
    (n_bodies, 6) holds this rank's ice load on each body: force [N] and moment about its CG [N m],
    and ``energy`` the elastic energy in this rank's hull contacts [J].
    """

    name = "hull contact"
    reads_poses = True  # computed after the bonds, so that the poses' broadcast travels meanwhile

    def __init__(self, hulls: list[Hull]):
        self.hulls = hulls
        self.poses = np.zeros((len(hulls), 13))
        self.loads = np.zeros((len(hulls), 6))
        self.energy = 0.0
        self.crushing = 0

    def add_forces(self, p, c, dt):
        self.energy, self.crushing = 0.0, 0
        for k, h in enumerate(self.hulls):
            self.loads[k], e, ncrushing = hull_forces(
                p.nlocal, p.x, p.v, p.w, p.radius, p.mass, p.cell_area, p.half_height, self.poses[k], h.vertices,
                h.triangles, *h.grid, h.law, p.hull_hist[:, k, :], dt, p.force, p.torque)
            self.energy += e
            self.crushing += ncrushing
