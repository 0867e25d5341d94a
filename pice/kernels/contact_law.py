"""The contact law shared by every contact in pice: ice-ice, ice-wall and ice-hull.

One element touches another surface at one point. With

    n   the unit normal pointing from the other surface towards the element,
    delta > 0  the overlap [m],
    u   the velocity of the element's contact point relative to the other surface's [m/s],
    u_n = u . n  (negative while approaching),

the normal force on the element is F_n = max(k_n delta - c_n u_n, 0) along n, a linear spring and
dashpot that never pulls, with c_n = 2 zeta sqrt(m_eff k_n). With crushing (seed 003 Eqs. 1-2,
seed 004 Eqs. 3-32..3-35) the contact is elastic-perfectly-plastic: the force is capped at the
crushing pressure times the contact area, F_n <= p_c A_c, and beyond the cap the overlap grows
plastically: the plastic penetration delta_p is kept in the contact's history and the spring acts
on delta - delta_p only (``plastic_normal_force``). The contact area of one layer of elements is the
chord of the overlap in plan times the contact height (``chord_area``). The tangential force is an incremental
spring with history h: h is first turned into the current tangent plane, then
h <- h - k_t (u - u_n n) dt, and capped at the Coulomb limit mu F_n. The force on the element is
F_n n + h; the other surface receives the opposite.

These are inline numba functions of plain floats (no arrays), called by the kernels in
``contacts.py`` (ice-ice), ``walls.py`` and ``pice/platform/hull_contact.py``.
"""

import math

from numba import njit

from . import JIT


@njit(**JIT, inline="always")
def normal_force(kn, zeta, m_eff, delta, un):
    """Normal force magnitude [N] of the spring-dashpot: k_n delta - 2 zeta sqrt(m_eff k_n) u_n, >= 0.

    kn [N/m], zeta [-], m_eff [kg], delta [m] (> 0 in contact), un [m/s] (< 0 approaching).
    """
    fn = kn * delta - 2.0 * zeta * math.sqrt(m_eff * kn) * un
    return fn if fn > 0.0 else 0.0


@njit(**JIT, inline="always")
def plastic_normal_force(kn, zeta, m_eff, delta, dp, un, cap):
    """Elastic-perfectly-plastic normal force: (F_n [N], plastic penetration delta_p [m]).

    The spring acts on the elastic overlap delta - dp; when k_n (delta - dp) exceeds ``cap`` [N]
    (p_c A_c) the excess becomes plastic (dp grows) and the elastic force stays at the cap. The
    dashpot acts while in elastic contact; the total is kept within [0, cap]. With cap = inf and
    dp = 0 this is ``normal_force`` exactly.
    """
    de = delta - dp
    if de <= 0.0:
        return 0.0, dp
    fe = kn * de
    if fe > cap:
        dp = delta - cap / kn
        fe = cap
    fn = fe - 2.0 * zeta * math.sqrt(m_eff * kn) * un
    if fn < 0.0:
        fn = 0.0
    if fn > cap:
        fn = cap
    return fn, dp


@njit(**JIT, inline="always")
def crushing_cap(pressure, half_chord2, height):
    """The plastic limit p_c A_c [N] of one contact: the crushing pressure [Pa] (inf: no crushing) times
    the overlap's chord in plan, 2 sqrt(half_chord2) [m], times the contact height [m]."""
    if pressure == math.inf:
        return math.inf
    return pressure * 2.0 * math.sqrt(half_chord2) * height if half_chord2 > 0.0 else 0.0


@njit(**JIT, inline="always")
def contact_height(radius, cell_area, half_height):
    """Height [m] of an element's contact face: its prism for a "cell" element, its diameter for a sphere."""
    return 2.0 * half_height if cell_area > 0.0 else 2.0 * radius


@njit(**JIT, inline="always")
def tangential_force(h0, h1, h2, n0, n1, n2, u0, u1, u2, un, kt, dt, cap):
    """Tangential spring with a Coulomb limit: the new history (h0, h1, h2) [N] and its magnitude.

    h: the previous tangential force on the element [N]; n: unit normal; u: contact-point velocity
    of the element relative to the other surface [m/s], un = u . n; kt [N/m]; dt [s];
    cap = mu F_n [N], the Coulomb limit.
    """
    dn = h0 * n0 + h1 * n1 + h2 * n2
    t0 = h0 - dn * n0 - kt * (u0 - un * n0) * dt
    t1 = h1 - dn * n1 - kt * (u1 - un * n1) * dt
    t2 = h2 - dn * n2 - kt * (u2 - un * n2) * dt
    tm = math.sqrt(t0 * t0 + t1 * t1 + t2 * t2)
    if tm > cap:
        s = cap / tm if tm > 0.0 else 0.0
        t0 *= s
        t1 *= s
        t2 *= s
        tm = cap
    return t0, t1, t2, tm


@njit(**JIT, inline="always")
def contact_energy(kn, kt, delta, tm):
    """Elastic energy [J] stored in one contact: 1/2 k_n delta^2 + 1/2 |h|^2 / k_t (delta: the elastic
    overlap, delta - delta_p with crushing)."""
    e = 0.5 * kn * delta * delta
    if kt > 0.0:
        e += 0.5 * tm * tm / kt
    return e
