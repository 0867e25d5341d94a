"""Rank 0's platform: fairleads carried by the hull, the mooring pull on the body, rest equilibrium."""

import math

import numpy as np

from pice.kernels.geometry import rotation_matrix
from pice.platform.hulls import semi_submersible, semi_submersible_braces
from pice.platform.layout import spread_mooring, zhu_ji_fairleads
from pice.platform.mooring_lines import build_lines
from pice.platform.platform import Attachment, Platform
from pice.platform.rigid_body import RigidBody

CG = np.array([0.0, 0.0, -14.0 + 8.9])  # Table 3: CG 8.9 m above the keel, draft 14 m


def moored_semi():
    v, t = semi_submersible()
    fl, headings = zhu_ji_fairleads()
    lines, _, _ = spread_mooring(fairleads_body=fl, bundle_headings_deg=headings)
    ml = build_lines(lines, element_length=20.0, water_density=1025.0, water_level=0.0, seabed_z=-400.0,
                     bond_damping=0.3)
    ml.relax(tol=1.0)
    pull_down = -ml.reactions(ml.fairleads)[:, 2].sum()
    # Table 3's displacement at 14 m carries the hull and the lines' vertical pull at pretension
    body = RigidBody("semi", 35000.5e3 - pull_down / 9.81, np.array([3.0e10, 5.0e10, 6.0e10]), v, t,
                     braces=semi_submersible_braces(),
                     damping=np.array([2e6, 2e6, 2e7, 1e12, 1e12, 1e12]))
    body.x = CG.copy()
    att = [Attachment(k, 0, lines[k][1] - CG) for k in range(len(lines))]
    return Platform([body], ml, att, rho_w=1025.0, g=9.81, level=0.0), body


def test_fairleads_follow_the_hull_pose():
    """Fairleads are body-fixed points: x_f = x_cg + R(q) p_B, v_f = v_cg + omega x (R p_B)."""
    p, b = moored_semi()
    a = math.radians(10.0)
    b.q = np.array([math.cos(a / 2), 0.0, 0.0, math.sin(a / 2)])
    b.x = CG + np.array([3.0, -2.0, 0.5])
    b.v = np.array([0.2, 0.0, 0.0])
    b.L = rotation_matrix(b.q) @ (b.effective_inertia * np.array([0.0, 0.0, 0.01]))
    x, v = p.fairlead_positions()
    for att in p.attachments:
        arm = rotation_matrix(b.q) @ att.point
        assert np.allclose(x[att.line], b.x + arm)
        assert np.allclose(v[att.line], b.v + np.cross([0.0, 0.0, 0.01], arm), atol=1e-12)


def test_moored_platform_at_rest_stays_put():
    """With the weight of the hull and the lines' pretension balanced by the buoyancy at 14 m draft,
    the coupled platform (hull + 12 DEM lines) stays within 2 cm and 0.01 degree of its start over
    60 s; the lines' horizontal pulls cancel (the spread is symmetric) and each keeps its
    pretension within 1 % (221.7 kN, Zhu & Ji 2022, section 4.1)."""
    p, b = moored_semi()
    dt = 0.05
    p.loads()
    for _ in range(int(60.0 / dt)):
        p.kick(0.5 * dt)
        p.drift(dt)
        p.loads()
        p.kick(0.5 * dt)
    assert np.linalg.norm(b.x - CG) < 0.02
    assert 2 * math.degrees(math.acos(min(1.0, abs(b.q[0])))) < 0.01
    np.testing.assert_allclose(p.fairlead_tensions(), 221.7e3, rtol=0.01)
