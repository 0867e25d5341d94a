"""Rigid-body kernels of the moored-platform issue: quaternion attitude (Eq. 11) and mesh buoyancy (Eq. 12)."""

import math

import numpy as np
import pytest
from scipy.spatial import ConvexHull, HalfspaceIntersection

from pice.kernels.geometry import quat_mul, rotation_matrix
from pice.platform.hull_buoyancy import submerged_volume, transform
from pice.platform.rigid_body import angular_velocity, body_rates, free_rotation, rigid_step, rotational_energy

pytestmark = pytest.mark.nojit


def _random_quaternion(rng):
    q = rng.normal(size=4)
    return q / np.linalg.norm(q)


def test_torque_free_asymmetric_body_conserves_norm_energy_and_momentum():
    """Issue 4: a torque-free asymmetric body keeps |q| = 1 and conserves energy and angular
    momentum within 1e-6 relative over 10,000 steps. Reference: conservation laws of the free rigid
    body (Euler's equations). The body spins mainly about its intermediate axis, the unstable one,
    so the attitude tumbles (the hardest case); omega dt ~ 2e-3 rad."""
    inertia = np.array([1.0e9, 2.0e9, 3.0e9])  # principal moments [kg m^2], platform-like scale
    rng = np.random.default_rng(7)
    q = _random_quaternion(rng)
    w_body = np.array([0.01, 0.2, 0.01])  # [rad/s]
    L = rotation_matrix(q) @ (inertia * w_body)
    E0, L0 = rotational_energy(q, L, inertia), L.copy()
    dt = 0.01
    x, v = np.zeros(3), np.zeros(3)
    zero = np.zeros(3)
    worst_e = worst_q = 0.0
    for _ in range(10_000):
        x, v, q, L = rigid_step(x, v, q, L, 1.0, inertia, zero, zero, dt)
        worst_q = max(worst_q, abs(np.linalg.norm(q) - 1.0))
        worst_e = max(worst_e, abs(rotational_energy(q, L, inertia) - E0) / E0)
    assert worst_q < 1e-12
    assert worst_e < 1e-6
    assert np.linalg.norm(L - L0) <= 1e-12 * np.linalg.norm(L0)
    # it really tumbled: the body-frame rates changed sign (intermediate-axis instability)
    assert body_rates(q, L, inertia)[1] < 0.19


def test_free_rotation_matches_euler_equations_for_a_symmetric_top():
    """Reference: the torque-free symmetric top (I1 = I2) precesses in the body frame at
    Omega = (I3 - I1)/I1 * w3 with w3 constant (Goldstein, Classical Mechanics, 5.6)."""
    I1, I3 = 2.0, 5.0
    inertia = np.array([I1, I1, I3])
    w0 = np.array([0.3, 0.0, 1.0])
    q = np.array([1.0, 0.0, 0.0, 0.0])
    L = inertia * w0
    dt, n = 1e-3, 5000
    for _ in range(n):
        q = free_rotation(q, L, inertia, dt)
    wb = body_rates(q, L, inertia)
    omega = (I3 - I1) / I1 * w0[2]
    expected = np.array([0.3 * math.cos(omega * n * dt), 0.3 * math.sin(omega * n * dt), 1.0])
    assert np.allclose(wb, expected, atol=1e-6)


def test_quaternion_kinematics_eq11():
    """dq/dt = 1/2 q (0, w_B): a small step of free_rotation equals the Eq. 11 increment to O(dt^2)."""
    rng = np.random.default_rng(3)
    q = _random_quaternion(rng)
    inertia = np.array([1.0, 1.5, 2.5])
    L = rng.normal(size=3)
    dt = 1e-6
    wb = body_rates(q, L, inertia)
    q_eq11 = q + 0.5 * dt * quat_mul(q, np.r_[0.0, wb])
    assert np.allclose(free_rotation(q, L, inertia, dt), q_eq11, atol=1e-11)
    assert np.allclose(angular_velocity(q, L, inertia), rotation_matrix(q) @ wb)


# -- Eq. 12: submerged volume of a clipped mesh -----------------------------------------------------

def box_mesh(a, b, c):
    """Closed box [-a/2, a/2] x [-b/2, b/2] x [-c/2, c/2] with outward triangles."""
    v = np.array([[x, y, z] for x in (-a / 2, a / 2) for y in (-b / 2, b / 2) for z in (-c / 2, c / 2)])
    hull = ConvexHull(v)
    return v, _outward(v, hull.simplices)


def prism_mesh(radius, height, n, apex=False):
    """Faceted cylinder (n sides) or, with apex, a faceted cone, centred on its axis."""
    ang = 2 * np.pi * np.arange(n) / n
    ring = np.column_stack([radius * np.cos(ang), radius * np.sin(ang)])
    bottom = np.column_stack([ring, np.full(n, -height / 2)])
    top = np.array([[0.0, 0.0, height / 2]]) if apex else np.column_stack([ring, np.full(n, height / 2)])
    v = np.vstack([bottom, top])
    return v, _outward(v, ConvexHull(v).simplices)


def _outward(v, tris):
    c = v.mean(axis=0)
    out = []
    for t in tris:
        a, b, d = v[t]
        if np.dot(np.cross(b - a, d - a), a - c) < 0:
            t = t[[0, 2, 1]]
        out.append(t)
    return np.asarray(out, dtype=np.int64)


def reference_below(vertices):
    """Independent reference: the convex polytope of the mesh cut by z <= 0, via scipy's half-space
    intersection (qhull); volume and centroid from its Delaunay tetrahedra."""
    hull = ConvexHull(vertices)
    halfspaces = np.vstack([hull.equations, [[0.0, 0.0, 1.0, 0.0]]])  # a.x + b <= 0 ; z <= 0
    inside = vertices[vertices[:, 2] < 0].mean(axis=0) if np.any(vertices[:, 2] < 0) else None
    # an interior point strictly below the plane and inside the body
    point = 0.5 * (inside + hull.points[hull.vertices].mean(axis=0))
    point[2] = min(point[2], -1e-6)
    pts = HalfspaceIntersection(halfspaces, point).intersections
    cut = ConvexHull(pts)
    from scipy.spatial import Delaunay

    tet = Delaunay(pts).simplices
    P = pts[tet]
    vols = np.abs(np.einsum("ij,ij->i", P[:, 1] - P[:, 0], np.cross(P[:, 2] - P[:, 0], P[:, 3] - P[:, 0]))) / 6
    centroid = (vols[:, None] * P.mean(axis=1)).sum(axis=0) / vols.sum()
    return cut.volume, centroid


@pytest.mark.parametrize("shape", ["box", "cylinder", "cone"])
def test_clipped_mesh_volume_and_centroid_at_any_attitude(shape):
    """Issue 4: submerged volume and centroid of a box, a cylinder and a cone equal the reference
    within 1e-9 relative at any attitude and immersion. Reference: the exact polytope cut (qhull);
    the faceted shapes are the analytic solids of their facets."""
    if shape == "box":
        vb, tris = box_mesh(4.0, 2.0, 1.0)
    elif shape == "cylinder":
        vb, tris = prism_mesh(1.5, 3.0, 48)
    else:
        vb, tris = prism_mesh(2.0, 3.0, 48, apex=True)
    rng = np.random.default_rng(11)
    for _ in range(12):
        R = rotation_matrix(_random_quaternion(rng))
        vs = transform(vb, R, np.array([0.3, -0.2, rng.uniform(-1.2, 1.2)]))
        if vs[:, 2].min() >= 0 or vs[:, 2].max() <= 0:
            continue
        vol, cob = submerged_volume(vs, tris, 0.0)
        ref_vol, ref_cob = reference_below(vs)
        assert vol == pytest.approx(ref_vol, rel=1e-9)
        assert np.linalg.norm(cob - ref_cob) <= 1e-9 * np.abs(vs).max()


def test_upright_shapes_match_closed_forms():
    """Closed forms: a faceted cylinder (n sides, circumradius R) half immersed displaces
    (n/2) R^2 sin(2 pi/n) h/2, centroid at -h/4; a box fully immersed its whole volume; a fully dry
    mesh nothing."""
    v, t = prism_mesh(1.5, 3.0, 48)
    vol, c = submerged_volume(v, t, 0.0)
    area = 48 / 2 * 1.5 ** 2 * math.sin(2 * math.pi / 48)
    assert vol == pytest.approx(area * 1.5, rel=1e-12)
    assert np.allclose(c, [0.0, 0.0, -0.75], atol=1e-12)
    vb, tb = box_mesh(4.0, 2.0, 1.0)
    assert submerged_volume(vb, tb, 10.0)[0] == pytest.approx(8.0, rel=1e-12)
    dry, centre = submerged_volume(vb, tb, -10.0)
    assert dry == 0.0 and np.all(np.isnan(centre))


def test_brace_buoyancy_eq13_14():
    """Eqs. 13-14 of Zhu & Ji (2022): a horizontal brace half immersed displaces pi R^2 L / 2 with its
    centre of buoyancy 4R/(3 pi) below the axis; fully immersed pi R^2 L; an inclined brace crossing
    the water plane agrees with the clipped mesh of a finely faceted cylinder (platform.hull_buoyancy, 256
    facets: the facet error is ~1e-4 of the volume) within 0.2 %."""
    from pice.platform.hull_buoyancy import brace_submerged

    R, L = 1.5, 20.0
    vol, c = brace_submerged(np.array([0.0, 0.0, 0.0]), np.array([L, 0.0, 0.0]), R, 0.0, 200)
    assert vol == pytest.approx(math.pi * R**2 * L / 2, rel=1e-12)
    assert c[2] == pytest.approx(-4 * R / (3 * math.pi), rel=1e-12)
    vol, _ = brace_submerged(np.array([0.0, 0.0, -5.0]), np.array([L, 0.0, -5.0]), R, 0.0, 10)
    assert vol == pytest.approx(math.pi * R**2 * L, rel=1e-12)
    # inclined 30 degrees, crossing the water plane
    a = math.radians(30.0)
    p0 = np.array([0.0, 0.0, -L / 2 * math.sin(a)])
    p1 = np.array([L * math.cos(a), 0.0, L / 2 * math.sin(a)])
    vol, cob = brace_submerged(p0, p1, R, 0.0, 4000)
    vb, tris = prism_mesh(R, L, 256)  # axis along z in the body frame
    R_y = np.array([[math.cos(math.pi / 2 - a), 0, math.sin(math.pi / 2 - a)], [0, 1, 0],
                    [-math.sin(math.pi / 2 - a), 0, math.cos(math.pi / 2 - a)]])
    vs = transform(vb, R_y, 0.5 * (p0 + p1))
    ref, ref_c = submerged_volume(vs, tris, 0.0)
    assert vol == pytest.approx(ref, rel=2e-3)
    assert np.linalg.norm(cob - ref_c) < 2e-3 * L
