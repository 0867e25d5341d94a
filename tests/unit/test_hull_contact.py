"""Ice-hull contact (platform.hull_contact): action and reaction, moments, moving hulls, friction."""

import math

import numpy as np
import pytest

from pice.physics.contact import ContactLaw
from pice.kernels.geometry import rotation_matrix
from pice.platform.hull_contact import build_triangle_grid, hull_forces
from pice.platform.hulls import box

PARAMS = ContactLaw(kn=1e7, kt=5e6, zeta=0.0, mu=0.3)  # [N/m], [N/m], -, -


def _setup(n, pose, xs, r=0.5, vs=None):
    verts, tris = box(10.0, 6.0, 4.0)
    grid = build_triangle_grid(verts, tris, reach=r)
    x = np.asarray(xs, float).reshape(n, 3)
    v = np.zeros((n, 3)) if vs is None else np.asarray(vs, float).reshape(n, 3)
    return verts, tris, grid, x, v


def _call(x, v, pose, verts, tris, grid, dt=1e-3, hist=None, r=0.5):
    n = len(x)
    force, torque = np.zeros((n, 3)), np.zeros((n, 3))
    hist = np.zeros((n, 4)) if hist is None else hist
    load, _, _ = hull_forces(n, x, v, np.zeros((n, 3)), np.full(n, r), np.full(n, 400.0), np.zeros(n), np.zeros(n),
                             pose, verts, tris,
                       *grid, PARAMS, hist, dt, force, torque)
    return force, torque, load, hist


@pytest.mark.nojit
def test_sphere_on_a_rotated_moved_hull_face():
    """A sphere overlapping the +z face of a box hull by 1 cm: normal force k_n delta along the face's
    normal, whatever the hull's position and attitude; the body gets the opposite force and the
    moment of that force about its CG (Newton's third law, moment balance to 1e-9)."""
    a = math.radians(20.0)
    q = np.array([math.cos(a / 2), 0.3 * math.sin(a / 2), 0.0, math.sqrt(1 - 0.09) * math.sin(a / 2)])
    R = rotation_matrix(q)
    xc = np.array([100.0, -50.0, 3.0])
    pose = np.concatenate([xc, q, np.zeros(6)])
    p_body = np.array([1.0, 0.5, 2.0 + 0.49])  # 1 cm into the top face (z = 2 in the body frame)
    x = (R @ p_body + xc)[None, :]
    verts, tris, grid, x, v = _setup(1, pose, x)
    force, torque, load, _ = _call(x, v, pose, verts, tris, grid)
    n_space = R @ np.array([0.0, 0.0, 1.0])
    assert np.allclose(force[0], 1e7 * 0.01 * n_space, rtol=1e-9, atol=1e-6)
    assert np.allclose(load[:3], -force[0], atol=1e-9)
    contact = x[0] - 0.5 * n_space
    assert np.allclose(load[3:], -np.cross(contact - xc, force[0]), atol=1e-6)
    # total angular momentum change about the origin balances: particle (x F + T) + body (xc F_b + M_b)
    total = np.cross(x[0], force[0]) + torque[0] + np.cross(xc, load[:3]) + load[3:]
    assert np.linalg.norm(total) < 1e-9 * np.linalg.norm(force[0]) * np.linalg.norm(x[0])


@pytest.mark.nojit
def test_no_force_when_clear_and_friction_is_capped():
    """A sphere 1 mm clear of the hull feels nothing; one sliding along a face feels at most mu F_n."""
    pose = np.concatenate([np.zeros(3), [1.0, 0.0, 0.0, 0.0], np.zeros(6)])
    verts, tris, grid, x, v = _setup(1, pose, [[0.0, 0.0, 2.501]])
    force, _, load, _ = _call(x, v, pose, verts, tris, grid)
    assert not force.any() and not load.any()
    verts, tris, grid, x, v = _setup(1, pose, [[0.0, 0.0, 2.49]], vs=[[1.0, 0.0, 0.0]])
    hist = np.zeros((1, 4))
    for _ in range(50):  # keep sliding at 1 m/s: the tangential spring saturates at mu F_n
        force, _, _, hist = _call(x, v, pose, verts, tris, grid, hist=hist)
    fn = 1e7 * 0.01
    assert force[0, 2] == pytest.approx(fn)
    assert force[0, 0] == pytest.approx(-0.3 * fn, rel=1e-9)  # opposes the sliding


@pytest.mark.nojit
def test_hull_velocity_counts_in_the_damping_and_friction():
    """A hull moving at the sphere's velocity is at rest relative to it: no tangential force, and a
    spinning hull drags a touching sphere along its surface velocity."""
    params = PARAMS
    pose = np.concatenate([np.zeros(3), [1.0, 0.0, 0.0, 0.0], [1.0, 0.0, 0.0], np.zeros(3)])
    verts, tris, grid, x, v = _setup(1, pose, [[0.0, 0.0, 2.49]], vs=[[1.0, 0.0, 0.0]])
    hist = np.zeros((1, 4))
    for _ in range(20):
        force, _, _, hist = _call(x, v, pose, verts, tris, grid, hist=hist)
    assert abs(force[0, 0]) < 1e-9 * force[0, 2]
    spin = np.concatenate([np.zeros(3), [1.0, 0.0, 0.0, 0.0], np.zeros(3), [0.0, 0.0, 0.1]])
    verts, tris, grid, x, v = _setup(1, spin, [[0.0, 2.0, 2.49]])
    force, _, _, _ = _call(x, v, spin, verts, tris, grid, hist=np.zeros((1, 4)))
    assert force[0, 0] < 0.0  # surface moves along -x at (0, 2): omega x r = (0,0,0.1) x (0,2,2) -> -0.2 x
    assert params.mu * force[0, 2] >= abs(force[0, 0])


def test_hull_crushing_width_sets_the_iso_pressure():
    """ISO 19906 A.8.2.4.3 (seed 000, Eq. 15): p_G depends on the structure's width w. A hull takes
    its extent across the drift (y, body frame: the barge's 16 m) unless bodies[].crushing_width
    names another (one leg of a multi-leg hull); exact, as the pressure is the formula's value."""
    from scenes import barge_job, job_from_text

    from pice.physics.iso19906 import crushing_pressure
    from pice.platform.build import hulls_from_job

    def pressure(body_extra):
        job = job_from_text(barge_job(body_extra=body_extra) + "\n[crushing]\nstructure = \"iso19906\"\n")
        (hull,) = hulls_from_job(job, default_kn=1.0e8, reach=0.5)
        return hull.law.crushing_pressure

    assert pressure("") == pytest.approx(crushing_pressure(thickness=1.0, width=16.0), rel=1e-12)
    assert pressure("crushing_width = 4.0") == pytest.approx(crushing_pressure(thickness=1.0, width=4.0), rel=1e-12)
    assert pressure("crushing_width = 4.0") > pressure("")          # the size effect: narrower, higher
