"""Rigid convex floes: their state, their build from polygons, and their step (issue 14; one rank: the
contact law, the water (current, waves) and the rigid-body step that the broken-ice scenes will
use; not yet part of a job or the MPI step).

A floe is a right prism over a convex polygon (pice/scenes/floe_field.py), rigid: six degrees of
freedom, the attitude a unit quaternion and the angular momentum carried in space, stepped as the
platform's bodies are (platform/rigid_body.py: velocity Verlet with the exact free rotation). Its
stable step comes from the contact law alone (kernels/floe_contact.py), not from springs inside it:
for k_n and the pair's m_eff, dt < 2 / sqrt(k_n / m_eff) (``contact_step_limit``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InstabilityError
from ..kernels.box_contact import box_half_extents
from ..kernels.floe_contact import PAIR_RECORD, apply_pair_records, boxes_within, build_floe_pairs, floe_boxes, floe_contacts
from ..kernels.structure_contact import (STRUCTURE_RECORD, apply_structure_records, hull_contacts, plane_contacts,
                                        structure_contacts)
from ..kernels.floe_hydro import SEA_COLUMNS, floe_sea, floe_water
from ..kernels.floe_motion import floe_omegas, floe_rotations, turn_all, world_polyhedra
from ..kernels.polyhedra import prism
from ..scenes.floe_field import polygon_area, polygon_centroid
from ..state import MAX_CONTACTS

PAIR_SKIN = 0.05  # the pair list's skin, of the largest bounding radius (a 1.4 m block: 4 cm; a 40 m floe: 1 m)
RECORDS_PER_FLOE = 24  # room for the floe-floe contacts of one floe at once (a convex floe in a field touches fewer)


def _refuse_overflow(nrec: int, rec: np.ndarray, what: str) -> None:
    if nrec > rec.shape[0]:
        raise InstabilityError(f"{nrec} {what} contacts at once, more than the {rec.shape[0]} the step has room for: "
                               "floes piled on each other (a blow-up, or a time step too large for the contact law)")


@dataclass
class FloeWater:
    """The water floes float in: density [kg/m^3], level [m], gravity [m/s^2], current (2,) [m/s], skin
    drag C_w, form drag C_d, and the damping ratio of heave, roll and pitch (kernels/floe_hydro.py)."""

    density: float = 1025.0
    level: float = 0.0
    gravity: float = 9.81
    current: tuple = (0.0, 0.0)
    skin: float = 0.0055
    form: float = 1.0
    damping_ratio: float = 0.1
    sea: object = None  # physics.waves.Sea, or None: still water
    wave_interval: float = 0.05  # [s] the sea is summed at the floes every this long and interpolated


@dataclass
class FloeLaw:
    """Seed 003's contact parameters (Table 3): k_n [N/m], c_n [N s/m], k_t [N/m], mu, sigma_c [Pa];
    zeta >= 0 replaces c_n by that fraction of each pair's critical damping 2 sqrt(m_eff k_n)
    (negative: c_n for every pair)."""

    kn: float = 1.3e6
    cn: float = 2.6e6
    kt: float = 0.78e6
    mu: float = 0.3
    pressure: float = 2.5e6
    zeta: float = -1.0

    def damping(self, m_eff: float) -> float:
        """c_n [N s/m] of a pair of effective mass m_eff [kg]."""
        return 2.0 * self.zeta * math.sqrt(m_eff * self.kn) if self.zeta >= 0.0 else self.cn

    @classmethod
    def from_spec(cls, c) -> "FloeLaw":
        """The law of a [floes.contact] or [keel.contact] table (job/floes.FloeContactSpec)."""
        return cls(kn=c.normal_stiffness, cn=c.damping, kt=c.tangential_stiffness, mu=c.friction,
                   pressure=c.compressive_strength, zeta=-1.0 if c.damping_ratio is None else c.damping_ratio)


def prism_inertia(polygon: np.ndarray, thickness: float, density: float):
    """(mass [kg], principal moments (3,) [kg m^2], angle [rad] of the first in-plane principal axis
    from x) of a homogeneous right prism over a convex polygon (k, 2) about its centroid."""
    p = polygon - polygon_centroid(polygon)
    x, y = p[:, 0], p[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cross = x * yn - xn * y
    area = 0.5 * cross.sum()
    ixx = (cross * (y * y + y * yn + yn * yn)).sum() / 12.0   # integral of y^2 dA
    iyy = (cross * (x * x + x * xn + xn * xn)).sum() / 12.0   # integral of x^2 dA
    ixy = (cross * (x * yn + 2 * x * y + 2 * xn * yn + xn * y)).sum() / 24.0
    angle = 0.5 * math.atan2(2.0 * ixy, iyy - ixx)  # principal axes of the area's second moments
    c, s = math.cos(angle), math.sin(angle)
    i_u = iyy * c * c + ixx * s * s + 2 * ixy * c * s  # integral of u^2 along the first axis
    i_v = iyy * s * s + ixx * c * c - 2 * ixy * c * s
    mass = density * area * thickness
    t2 = thickness * thickness / 12.0
    moments = density * thickness * np.array([i_v + area * t2, i_u + area * t2, i_u + i_v])
    return mass, moments, angle


class Floes:
    """n rigid floes: world x, v, q, L and the body-frame prisms (module docstring)."""

    def __init__(self, polygons, thickness, *, density: float = 920.0, base=None, velocity=(0.0, 0.0, 0.0),
                 law: FloeLaw | None = None, water: FloeWater | None = None, added_mass: bool = False):
        """polygons: convex (k, 2) [m] counter-clockwise; thickness (n,) [m]; base (n,) the z of each
        floe's bottom [m] (default: -density/1025 of its thickness, afloat); water: None (no water,
        no gravity) or FloeWater."""
        n = len(polygons)
        self.law = law or FloeLaw()
        self.water = water
        self.area = np.array([polygon_area(np.asarray(p, float)) for p in polygons])
        self.gid = np.arange(n, dtype=np.int64)
        self.x, self.v, self.L = np.zeros((n, 3)), np.tile(np.asarray(velocity, float), (n, 1)), np.zeros((n, 3))
        self.q = np.zeros((n, 4))
        self.mass, self.inertia = np.zeros(n), np.zeros((n, 3))
        self.bound = np.zeros(n)
        self.body = []
        self.polygons = []  # each floe's polygon (k, 2) [m] in its principal axes (its top and bottom faces)
        thickness = np.asarray(thickness, float)
        self.thickness = thickness.copy()
        base = -thickness * density / 1025.0 if base is None else np.asarray(base, float)
        for k, poly in enumerate(polygons):
            poly = np.asarray(poly, float)
            centre = polygon_centroid(poly)
            m, moments, angle = prism_inertia(poly, thickness[k], density)
            self.mass[k], self.inertia[k] = m, moments
            self.x[k] = [centre[0], centre[1], base[k] + 0.5 * thickness[k]]
            self.q[k] = [math.cos(0.5 * angle), 0.0, 0.0, math.sin(0.5 * angle)]
            c, s = math.cos(angle), math.sin(angle)
            local = (poly - centre) @ np.array([[c, -s], [s, c]])  # into the principal axes
            self.body.append(prism(local, -0.5 * thickness[k], 0.5 * thickness[k]))
            self.polygons.append(local)
            self.bound[k] = math.hypot(np.linalg.norm(local, axis=1).max(), 0.5 * thickness[k])
        # as tight as the largest floe (faces_array pads to the polyhedra's maximum): the world polyhedra
        # are rebuilt every step, and the clips grow their arrays as they need
        nf = max((int(np.count_nonzero(b[1])) for b in self.body), default=1)
        nv = max((int(b[1].max()) for b in self.body), default=1)
        self.body_pts = np.array([b[0][:nf, :nv] for b in self.body]).reshape(n, nf, nv, 3)
        # the water's added mass [kg] along x, y, z and added inertia about the principal axes [kg m^2]
        # (``plate_added_mass``); the rigid moments stay in inertia_rigid, inertia carries both
        self.added = np.zeros((n, 3))
        self.wave_ends = None  # (interval, (2, n, SEA_COLUMNS)): the sea at the floes at an interval's ends
        self.inertia_rigid = self.inertia.copy()
        if added_mass and water is not None:
            draft = thickness * density / water.density
            self.added[:], extra = plate_added_mass(self.area, draft, water.density)
            self.inertia[:, :2] += extra[:, None]
        self.body_counts = np.array([b[1][:nf] for b in self.body], np.int64).reshape(n, nf)
        # (n, 3) the half extents [m] when every floe is a box (a keel's blocks): their overlaps then take
        # kernels/box_contact.py, the same to round-off in fewer operations; else (0, 3)
        self.box_half = box_half_extents(self.body_pts, self.body_counts)
        self.force, self.torque = np.zeros((n, 3)), np.zeros((n, 3))
        self.cgid = np.full((n, MAX_CONTACTS), -1, np.int64)
        self.stamp = np.full((n, MAX_CONTACTS), -10, np.int64)
        self.hist = np.zeros((n, MAX_CONTACTS, 4))
        self.step_count = 0
        self.time = 0.0  # [s]
        # the floe-floe candidates (kernels/floe_contact.build_floe_pairs): ((lo, hi, stride), start,
        # partners, held boxes), rebuilt when a floe's box leaves its held box; not state (a restart
        # builds its own and adds the same forces in the same order)
        self.near = None
        self.pair_lists = 0  # lists built
        self.stats = (0, 0, 0.0)
        self.structures = []  # fixed convex structures: (pts, counts, centre, bound)
        self.hull_pieces = []  # runs of structure indices that are one hull's pieces (join_pieces)
        self.structure_load = np.zeros((0, 6))

    def add_structure(self, vertices: np.ndarray, triangles: np.ndarray, centre=None, friction=None) -> None:
        """A convex structure: a closed, outward triangle mesh [m] (e.g. a revolved hull) in the frame of
        its reference point ``centre`` (default: the mean of its vertices), placed at that point, still.
        Every triangle is a face (coplanar ones clip once). ``move_structure`` sets its pose and
        motion; its load (force, moment about the reference point) is ``structure_load[k]``. ``friction``:
        the ice-structure Coulomb coefficient (default: the floes' law's)."""
        v = np.asarray(vertices, float)
        centre = v.mean(axis=0) if centre is None else np.asarray(centre, float)
        local = np.zeros((len(triangles), 3, 3))
        local[:] = (v - centre)[np.asarray(triangles)]
        _require_convex(local, v - centre)
        bound = float(np.linalg.norm(v - centre, axis=1).max())
        self.structures.append({"local": local, "counts": np.full(len(triangles), 3, np.int64), "bound": bound,
                                "x": centre.copy(), "q": np.array([1.0, 0.0, 0.0, 0.0]), "v": np.zeros(3),
                                "w": np.zeros(3), "mu": self.law.mu if friction is None else float(friction)})
        self.structure_load = np.zeros((len(self.structures), 6))

    def add_wall(self, normal, offset: float, friction: float | None = None) -> None:
        """A fixed wall filling the half-space normal . x >= offset [m] (normal: a unit vector into the
        wall), with the contact law's friction (whichever law is current) unless ``friction`` is given
        (0: a symmetry plane); its load's moment is about the origin."""
        n = np.asarray(normal, float)
        self.structures.append({"plane": (n / np.linalg.norm(n), float(offset)), "x": np.zeros(3),
                                "mu": None if friction is None else float(friction)})
        self.structure_load = np.zeros((len(self.structures), 6))

    def move_structure(self, k: int, *, x, q, v, w) -> None:
        """Pose (reference point x [m], attitude q) and motion (v [m/s], w [rad/s]) of structure k."""
        s = self.structures[k]
        s["x"], s["q"] = np.asarray(x, float).copy(), np.asarray(q, float).copy()
        s["v"], s["w"] = np.asarray(v, float).copy(), np.asarray(w, float).copy()

    @property
    def omega(self) -> np.ndarray:
        return floe_omegas(self.q, self.L, self.inertia)

    def world(self):
        """(pts, counts) of every floe's prism at its pose."""
        return world_polyhedra(self.body_pts, self.body_counts, self.x, self.q), self.body_counts

    def compute_forces(self, dt: float) -> None:
        """Forces [N] and torques [N m] on every floe at the current state (one rank: all floes)."""
        self.force[:] = 0.0
        self.torque[:] = 0.0
        n = len(self.mass)
        pts, counts = self.world()
        omega = self.omega
        self.water_loads(0, n, pts, counts, omega, dt)
        for k, (rec, nrec, _) in enumerate(self.all_structure_records(0, n, pts, counts, omega, dt)):
            self.structure_load[k] = 0.0
            apply_structure_records(rec, nrec, self.force, self.torque, self.structure_load[k])
        rec, nrec, nplastic, worst = self.pair_records(0, n, pts, counts, omega, dt)
        apply_pair_records(rec, nrec, self.force, self.torque)
        self.stats = (nrec, nplastic, worst)

    def water_loads(self, lo, hi, pts, counts, omega, dt, stride=1) -> None:
        """The water's loads on floes range(lo, hi, stride) added to force and torque (nothing without
        water)."""
        w = self.water
        if w is None:
            return
        rot = floe_rotations(self.q)
        wave = self.sea_at_floes(lo, hi, dt, stride) if w.sea is not None else np.zeros((0, SEA_COLUMNS))
        floe_water(lo, hi, stride, self.x, self.v, omega, rot, self.mass, self.inertia_rigid, self.area,
                   self.area * self.thickness, pts, counts,
                   w.level, w.density, w.gravity, np.asarray(w.current, float), w.skin, w.form, w.damping_ratio, wave,
                   self.added, self.force, self.torque)

    def sea_at_floes(self, lo, hi, dt, stride=1) -> np.ndarray:
        """(n, SEA_COLUMNS) the sea at the floes' centres of mass now (kernels/floe_hydro.floe_sea), rows
        range(lo, hi, stride).

        The sums over the sea's components are the cost of a floe in waves (200 components against a
        few dozen operations for the rest of its water), and the sea changes slowly against the step:
        they are taken at the start and the end of every interval of N = wave_interval / dt steps, at
        the floes' places at its start, and interpolated linearly in time between (error
        (omega T)^2 / 8 of a component's amplitude over an interval T: 3.4e-4 for the shortest
        JONSWAP component of seed 003's sea at 0.05 s; a floe drifting at 0.4 m/s moves 2 cm, 0.2 %
        of that component's wavelength). The intervals are counted in steps and their two ends are
        checkpointed, so a restart continues them bit for bit."""
        w, sea = self.water, self.water.sea
        every = max(1, int(round(w.wave_interval / dt)))
        k, into = divmod(self.step_count, every)
        if self.wave_ends is None or self.wave_ends[0] != k:
            ends = np.zeros((2, len(self.mass), SEA_COLUMNS))
            for e in range(2):
                floe_sea(lo, hi, stride, self.x, sea.amplitude, sea.omega, sea.k, sea.direction, sea.phase, sea.depth,
                         w.gravity, w.density, (k + e) * every * dt, ends[e])
            self.wave_ends = (k, ends)
        a, b = self.wave_ends[1]
        return a + (into / every) * (b - a)

    def pair_records(self, lo, hi, pts, counts, omega, dt, stride=1):
        """(records, count, contacts in plastic flow, largest overlap [m^3]) of the floe-floe contacts of
        floes range(lo, hi, stride) (kernels/floe_contact.py)."""
        law, n = self.law, len(self.mass)
        rec = np.empty((RECORDS_PER_FLOE * max(len(range(lo, hi, stride)), 1), PAIR_RECORD))
        box = floe_boxes(n, pts, counts)
        near = self.near
        if near is None or near[0] != (lo, hi, stride) or not boxes_within(box, near[3]):
            skin = PAIR_SKIN * float(self.bound.max()) if n else 0.0
            near = self.near = ((lo, hi, stride),) + build_floe_pairs(n, lo, hi, stride, self.x, self.bound, box, skin)
            self.pair_lists += 1
        rot = floe_rotations(self.q) if len(self.box_half) else np.empty((0, 3, 3))
        nrec, nplastic, worst = floe_contacts(n, lo, hi, stride, near[1], near[2], box, self.gid, self.x, self.v,
                                              omega, self.mass, self.bound, pts, counts, law.kn, law.cn, law.zeta,
                                              law.kt, law.mu, law.pressure, dt, self.step_count, self.cgid,
                                              self.stamp, self.hist, rec, rot, self.box_half)
        _refuse_overflow(nrec, rec, "floe-floe")
        return rec, nrec, nplastic, worst

    def join_pieces(self, indices) -> None:
        """Structures ``indices`` (added in a row, moved together) are the convex pieces of one hull:
        each floe meets them as one contact (kernels/structure_contact.hull_contacts), its force shared among
        the pieces by their overlaps."""
        indices = [int(k) for k in indices]
        if len(indices) > 1:
            if indices != list(range(indices[0], indices[0] + len(indices))):
                raise ValueError(f"join_pieces: structures {indices} are not consecutive")
            self.hull_pieces.append(indices)

    def all_structure_records(self, lo, hi, pts, counts, omega, dt, stride=1) -> list:
        """``structure_records`` of every structure, in order; a hull of pieces (``join_pieces``) in one
        call of ``hull_records``."""
        out, joined = [], {h[0]: h for h in self.hull_pieces}
        k = 0
        while k < len(self.structures):
            if k in joined:
                out += self.hull_records(joined[k], lo, hi, pts, counts, omega, dt, stride)
                k += len(joined[k])
            else:
                out.append(self.structure_records(k, lo, hi, pts, counts, omega, dt, stride))
                k += 1
        return out

    def hull_records(self, ks, lo, hi, pts, counts, omega, dt, stride=1) -> list:
        """[(records, count, contacts in plastic flow)] of floes range(lo, hi, stride) against each piece
        ks of one hull, one contact per floe and hull (kernels/structure_contact.hull_contacts); the plastic
        contacts counted on the first piece."""
        law, first = self.law, self.structures[ks[0]]
        mu = law.mu if first["mu"] is None else first["mu"]
        most = max(len(self.structures[k]["local"]) for k in ks)
        p_pts = np.zeros((len(ks), most, 3, 3))
        p_counts = np.zeros((len(ks), most), np.int64)
        for j, k in enumerate(ks):
            st = self.structures[k]
            nf = len(st["local"])
            p_pts[j, :nf] = world_polyhedra(st["local"][None], st["counts"][None], st["x"][None], st["q"][None])[0]
            p_counts[j, :nf] = st["counts"]
        p_bound = np.array([self.structures[k]["bound"] for k in ks])
        rec = np.empty((len(ks), max(len(range(lo, hi, stride)), 1), STRUCTURE_RECORD))
        nrec = np.zeros(len(ks), np.int64)
        nplastic = hull_contacts(lo, hi, stride, self.x, self.v, omega, self.mass, self.bound, pts, counts, p_pts,
                                 p_counts, p_bound, first["x"], first["v"], first["w"], law.kn, law.cn, law.zeta,
                                 law.kt, mu, law.pressure, dt, self.step_count, -1 - ks[0], self.cgid, self.stamp,
                                 self.hist, rec, nrec)
        for j in range(len(ks)):
            _refuse_overflow(int(nrec[j]), rec[j], "floe-structure")
        return [(rec[j], int(nrec[j]), nplastic if j == 0 else 0) for j in range(len(ks))]

    def structure_records(self, k, lo, hi, pts, counts, omega, dt, stride=1):
        """(records, count, contacts in plastic flow) of floes range(lo, hi, stride) against structure k."""
        st, law = self.structures[k], self.law
        mu = law.mu if st["mu"] is None else st["mu"]  # a wall without its own: the current law's
        rec = np.empty((max(len(range(lo, hi, stride)), 1), STRUCTURE_RECORD))
        if st.get("plane") is not None:
            normal, offset = st["plane"]
            nrec, nplastic = plane_contacts(lo, hi, stride, self.x, self.v, omega, self.mass, self.bound, pts, counts,
                                            normal, offset, law.kn, law.cn, law.zeta, law.kt, mu, law.pressure, dt,
                                            self.step_count, -1 - k, self.cgid, self.stamp, self.hist, rec)
        else:
            s_pts = world_polyhedra(st["local"][None], st["counts"][None], st["x"][None], st["q"][None])[0]
            nrec, nplastic = structure_contacts(lo, hi, stride, self.x, self.v, omega, self.mass, self.bound, pts,
                                                counts, s_pts, st["counts"], st["x"], st["bound"], st["v"], st["w"],
                                                law.kn, law.cn, law.zeta, law.kt, mu, law.pressure, dt,
                                                self.step_count, -1 - k, self.cgid, self.stamp, self.hist, rec)
        _refuse_overflow(nrec, rec, "floe-structure")
        return rec, nrec, nplastic

    def step(self, dt: float) -> None:
        """Velocity Verlet: half kick, drift with the exact free rotation, forces, half kick."""
        h = 0.5 * dt
        self.v += h * self.force / (self.mass[:, None] + self.added)
        self.L += h * self.torque
        self.x += dt * self.v
        turn_all(self.q, self.L, self.inertia, dt)
        self.step_count += 1
        self.time += dt
        self.compute_forces(dt)
        self.v += h * self.force / (self.mass[:, None] + self.added)
        self.L += h * self.torque

    def momentum(self) -> tuple[np.ndarray, np.ndarray]:
        """(linear [kg m/s], angular about the origin [kg m^2/s]) of all floes."""
        p = self.mass[:, None] * self.v
        return p.sum(axis=0), (np.cross(self.x, p) + self.L).sum(axis=0)


def plate_added_mass(area, draft, rho_w: float):
    """((n, 3) added mass [kg] along x, y, z; (n,) added moment of inertia about a horizontal axis
    [kg m^2]) of floes of water-plane ``area`` [m^2] and ``draft`` [m], as thin floating disks of the
    same area (radius a = sqrt(A / pi)) in the high-frequency limit, half the deeply submerged disk's
    (Newman, Marine Hydrodynamics, 1977, Table 4.2): heave (4/3) rho a^3, roll and pitch (8/45) rho a^5;
    surge and sway as a vertical plate of height d at the free surface, (pi / 2) rho d^2 per unit width,
    over the width 2 a: pi rho d^2 a. Seed 003 took them from WAMIT for its floe shape; these are the
    closed forms for the shape they stand for."""
    a = np.sqrt(np.asarray(area, float) / math.pi)
    d = np.asarray(draft, float)
    out = np.zeros((len(a), 3))
    out[:, 0] = out[:, 1] = math.pi * rho_w * d * d * a
    out[:, 2] = 4.0 / 3.0 * rho_w * a ** 3
    return out, 8.0 / 45.0 * rho_w * a ** 5


def contact_step_limit(law: FloeLaw, m_eff: float) -> float:
    """The stable step [s] of one contact: the spring-dashpot of k_n and c_n on m_eff [kg] under
    velocity Verlet, 2 / omega (sqrt(1 + zeta^2) - zeta)."""
    omega = math.sqrt(law.kn / m_eff)
    zeta = law.damping(m_eff) / (2.0 * math.sqrt(m_eff * law.kn))
    return 2.0 / omega * (math.sqrt(1.0 + zeta * zeta) - zeta)


def _require_convex(faces: np.ndarray, vertices: np.ndarray) -> None:
    """ValueError unless every vertex lies inside every face's plane (to 1e-5 of the body's size): the
    contact geometry (kernels/polyhedron_contact.py) is that of convex bodies only."""
    a, b, c = faces[:, 0], faces[:, 1], faces[:, 2]
    n = np.cross(b - a, c - a)
    size = np.linalg.norm(n, axis=1)
    ok = size > 0.0
    n, a = n[ok] / size[ok, None], a[ok]
    beyond = (vertices @ n.T - np.einsum("ij,ij->i", n, a)).max()
    scale = float(np.ptp(vertices, axis=0).max())
    if beyond > 1e-5 * scale:
        raise ValueError(f"the structure is not convex: a vertex lies {beyond:.3g} m beyond a face's plane; split "
                         "it into convex pieces (a revolved hull: one piece per ring to the next)")
