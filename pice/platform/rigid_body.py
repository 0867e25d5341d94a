"""A floating rigid body (rank 0): 6 degrees of freedom, attitude as a unit quaternion (Eq. 11).

Equation of motion (Eq. 9 of Zhu & Ji 2022 without the radiation memory term):
    (M + M_add) u'' = F_ice + F_mooring + F_buoyancy + F_gravity + F_current - B |u'| u'
with a constant, diagonal added mass in the body frame (surge, sway, heave, roll, pitch, yaw),
quadratic damping per body-frame degree of freedom, buoyancy from the instantaneous submerged
volume of the hull mesh and its braces (platform.hull_buoyancy, Eqs. 12-14) acting at the combined
centre of buoyancy, and current drag 1/2 rho C_d A |u_c - v| (u_c - v) on the horizontal motion.
Motion is "free" or "prescribed" (a velocity history, e.g. a ship pushed at constant speed).

In waves (a platform.sea.SeaComponents given to ``hydro_loads`` with the time; docs/waves.md):
buoyancy and Froude-Krylov load together are the pressure of the undisturbed sea on the hull below
the wave surface, panel by panel, and on the braces (platform.hull_waves); Eq. 11's second term,
the diffraction load of a body small against the waves, is the added mass times the undisturbed
particle acceleration at the centre of buoyancy, R (A_diag (R^T a)); the current drag acts on the
current plus the particle velocity there, relative to the body (Eq. 12, as Morison's drag). No
radiation damping beyond ``damping``, no diffraction beyond A a, no second-order drift.

Time stepping is velocity Verlet: `kick` (half step of momentum and angular momentum), `drift`
(translation and the exact free rotation below), forces at the new pose, `kick`.

The rotation kernels (numba; pure functions of arrays and scalars, no MPI, no I/O) carry the
angular momentum L in the space frame; a step is a symplectic splitting (Dullweber, Leimkuhler &
McLachlan 1997): half a kick of L by the torque, then the free rotation over dt composed of exact
rotations about the principal axes (x: dt/2, y: dt/2, z: dt, y: dt/2, x: dt/2), then the second
half kick. Every sub-rotation is an exact flow of Eq. 11 with a constant body rate about one axis,
so |q| = 1 to round-off and, without torque, L is conserved exactly and the energy error is
bounded (second order, no drift). The attitude q maps body to space coordinates.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numba import njit

from ..kernels import JIT
from ..kernels.geometry import quat_mul, rotation_matrix
from . import hull_buoyancy, hull_waves
from .sea import wave_at


# -- rotation kernels (numba) ------------------------------------------------------------------
@njit(**JIT)
def _rotate_about_body_axis(q, L_body, axis, inertia_axis, h):
    """Exact free rotation for time h under the part L_axis^2 / (2 I_axis) of the kinetic energy.

    The body turns about its own ``axis`` at the constant rate L_axis / I_axis; in the body frame
    the angular momentum turns the opposite way. Returns the new (q, L_body).
    """
    angle = h * L_body[axis] / inertia_axis
    c, s = math.cos(0.5 * angle), math.sin(0.5 * angle)
    dq = np.zeros(4)
    dq[0] = c
    dq[1 + axis] = s
    q_new = quat_mul(q, dq)  # body-frame increment: q' = q (cos, sin e_axis)
    ca, sa = math.cos(angle), math.sin(angle)
    L_new = L_body.copy()
    j, k = (axis + 1) % 3, (axis + 2) % 3
    L_new[j] = ca * L_body[j] + sa * L_body[k]
    L_new[k] = -sa * L_body[j] + ca * L_body[k]
    return q_new, L_new


@njit(**JIT)
def free_rotation(q, L_space, principal_inertia, dt):
    """Advance the attitude by dt with the space-frame angular momentum L fixed (torque-free).

    principal_inertia: (3,) body-frame principal moments [kg m^2]. Returns the new unit quaternion.
    """
    R = rotation_matrix(q)
    L_body = R.T @ L_space
    h = 0.5 * dt
    q, L_body = _rotate_about_body_axis(q, L_body, 0, principal_inertia[0], h)
    q, L_body = _rotate_about_body_axis(q, L_body, 1, principal_inertia[1], h)
    q, L_body = _rotate_about_body_axis(q, L_body, 2, principal_inertia[2], dt)
    q, L_body = _rotate_about_body_axis(q, L_body, 1, principal_inertia[1], h)
    q, L_body = _rotate_about_body_axis(q, L_body, 0, principal_inertia[0], h)
    return q / math.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3])


@njit(**JIT)
def angular_velocity(q, L_space, principal_inertia):
    """Space-frame angular velocity [rad/s] w = R I_B^-1 R^T L."""
    R = rotation_matrix(q)
    return R @ ((R.T @ L_space) / principal_inertia)


@njit(**JIT)
def body_rates(q, L_space, principal_inertia):
    """Body-frame angular velocity w_B [rad/s] of Eq. 11."""
    return (rotation_matrix(q).T @ L_space) / principal_inertia


@njit(**JIT)
def rotational_energy(q, L_space, principal_inertia):
    """1/2 L_B . I_B^-1 L_B [J]."""
    Lb = rotation_matrix(q).T @ L_space
    return 0.5 * np.sum(Lb * Lb / principal_inertia)


@njit(**JIT)
def rigid_step(x, v, q, L, mass, principal_inertia, force, torque, dt):
    """One velocity-Verlet step of a rigid body for a constant force [N] and torque [N m] over the step.

    For forces that depend on the pose, call the two halves separately (kick, drift/rotate, kick)
    with the force evaluated in between; this helper is the building block and the torque-free test.
    Returns (x, v, q, L) [m, m/s, -, kg m^2/s].
    """
    v = v + 0.5 * dt * force / mass
    L = L + 0.5 * dt * torque
    x = x + dt * v
    q = free_rotation(q, L, principal_inertia, dt)
    v = v + 0.5 * dt * force / mass
    L = L + 0.5 * dt * torque
    return x, v, q, L


@njit(**JIT)
def still_water_loads(vertices, triangles, braces, brace_slices, x, v, q, L, mass, inertia, added_mass, damping,
                      current_drag, current, rho_w, g, level):
    """(force [N], moment about the CG [N m]) of ``RigidBody.hydro_loads`` in still water, in one call:
    buoyancy of the hull mesh and braces at their combined centre (platform.hull_buoyancy), gravity,
    quadratic damping of the body-frame velocities and current drag on the horizontal motion.
    inertia: the principal moments with the added inertia [kg m^2]; current (2,) [m/s]."""
    R = rotation_matrix(q)
    vol, cob = hull_buoyancy.submerged_volume(hull_buoyancy.transform(vertices, R, x), triangles, level)
    if braces.shape[0] > 0:
        mom = vol * cob if vol > 0.0 else np.zeros(3)
        vol, mom = hull_buoyancy._add_braces(vol, mom, braces, R, x, level, brace_slices)
        if vol > 0.0:
            cob = mom / vol
    f = np.zeros(3)
    m = np.zeros(3)
    if vol > 0.0:  # rho_w g V at the centre of buoyancy: arm x (0, 0, fz)
        fz = rho_w * g * vol
        f[2] = fz
        m[0] = (cob[1] - x[1]) * fz
        m[1] = -(cob[0] - x[0]) * fz
    f[2] += -mass * g
    vb = R.T @ v
    wb = R.T @ (R @ ((R.T @ L) / inertia))
    f = f - R @ (damping[:3] * np.abs(vb) * vb)
    m = m - R @ (damping[3:] * np.abs(wb) * wb)
    for k in range(2):
        rel = current[k] - v[k]
        f[k] += current_drag[k] * abs(rel) * rel
    return f, m


@njit(**JIT)
def kick_free(v, L, q, force, torque, mass, half_dt):
    """Half a step [s] of a free body's momentum: (v [m/s], L [kg m^2/s]) after the force [N], with
    the diagonal mass (3,) [kg] (the body's and the added mass) acting in the body frame, and the
    torque [N m]."""
    R = rotation_matrix(q)
    return v + half_dt * (R @ ((R.T @ force) / mass)), L + half_dt * torque


# -- attitude as angles ------------------------------------------------------------------------
def euler_angles(q) -> np.ndarray:
    """(roll, pitch, yaw) [rad] of a unit quaternion (w, x, y, z): the z-y'-x'' (yaw, then pitch, then
    roll) angles of ship motions."""
    w, x, y, z = (float(c) for c in q)
    roll = math.atan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y))
    pitch = math.asin(max(-1.0, min(1.0, 2.0 * (w * y - z * x))))
    yaw = math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
    return np.array([roll, pitch, yaw])


def heading_quaternion(deg: float) -> tuple[float, float, float, float]:
    """Unit quaternion (w, x, y, z) of a yaw of ``deg`` degrees about +z (a body's heading at t = 0)."""
    a = math.radians(deg)
    return (math.cos(a / 2), 0.0, 0.0, math.sin(a / 2))


# -- the body ----------------------------------------------------------------------------------
@dataclass
class RigidBody:
    """State and parameters of one body (SI units; body frame at the centre of gravity)."""

    name: str
    mass: float                      # [kg]
    inertia: np.ndarray              # (3,) principal moments about the CG [kg m^2]
    vertices: np.ndarray             # (nv, 3) hull mesh in the body frame [m]
    triangles: np.ndarray            # (nt, 3) outward-oriented triangles
    added_mass: np.ndarray = field(default_factory=lambda: np.zeros(6))   # diagonal, body frame [kg, kg m^2]
    damping: np.ndarray = field(default_factory=lambda: np.zeros(6))      # quadratic B [N s^2/m^2, N m s^2]
    current_drag: np.ndarray = field(default_factory=lambda: np.zeros(2))  # 1/2 rho C_d A along x, y [N s^2/m^2]
    prescribed: np.ndarray | None = None  # (k, 7) rows (t, vx, vy, vz, wx, wy, wz): velocity history
    # (k,) hull_buoyancy.BRACE_RECORD (p0 (3,), p1 (3,), radius) [m], body frame: cylindrical braces,
    # buoyancy only (Eqs. 13-14; no ice contact), e.g. platform.hulls.semi_submersible_braces(); they
    # must not overlap the mesh
    braces: np.ndarray = field(default_factory=lambda: np.zeros(0, hull_buoyancy.BRACE_RECORD))
    brace_slices: int = hull_buoyancy.BRACE_SLICES  # segments per brace along its axis (Eq. 13)
    # (vertices, triangles) of the hull's surface for the wave pressure (hull_waves.panel_mesh; body
    # frame [m]); None: the hull mesh itself. Unused in still water.
    panels: tuple | None = None
    x: np.ndarray = field(default_factory=lambda: np.zeros(3))    # CG position [m]
    v: np.ndarray = field(default_factory=lambda: np.zeros(3))    # CG velocity [m/s]
    q: np.ndarray = field(default_factory=lambda: np.array([1.0, 0.0, 0.0, 0.0]))
    L: np.ndarray = field(default_factory=lambda: np.zeros(3))    # angular momentum, space frame [kg m^2/s]
    force: np.ndarray = field(default_factory=lambda: np.zeros(3))
    torque: np.ndarray = field(default_factory=lambda: np.zeros(3))

    def __post_init__(self) -> None:
        b = self.braces
        if not isinstance(b, np.ndarray) or b.dtype != hull_buoyancy.BRACE_RECORD or b.ndim != 1:
            raise ValueError(f"body {self.name!r}: braces must be a (k,) array of platform.hull_buoyancy.BRACE_RECORD "
                             f"(p0, p1, radius), got {getattr(b, 'dtype', type(b).__name__)} of shape {np.shape(b)}")
        if np.any(b["radius"] <= 0.0) or np.any(np.linalg.norm(b["p1"] - b["p0"], axis=1) <= 0.0):
            raise ValueError(f"body {self.name!r}: every brace needs a radius > 0 m and distinct ends p0, p1")
        if int(self.brace_slices) < 1:
            raise ValueError(f"body {self.name!r}: brace_slices = {self.brace_slices}: must be >= 1")

    @property
    def free(self) -> bool:
        return self.prescribed is None

    @property
    def effective_inertia(self) -> np.ndarray:
        return self.inertia + self.added_mass[3:]

    @property
    def omega(self) -> np.ndarray:
        """Angular velocity, space frame [rad/s]."""
        return angular_velocity(self.q, self.L, self.effective_inertia)

    def kinetic_energy(self) -> float:
        """Kinetic energy [J] with the inertia the equation of motion carries (body and added mass):
        1/2 v_B . (m + m_a) v_B, the diagonal added mass acting in the body frame, plus the
        rotational 1/2 L_B . (I + I_a)^-1 L_B (``rotational_energy``); with no added mass it is
        1/2 m |v|^2 + 1/2 w . I w."""
        vb = rotation_matrix(self.q).T @ self.v
        translational = 0.5 * float(np.sum((self.mass + self.added_mass[:3]) * vb * vb))
        return translational + float(rotational_energy(self.q, self.L, self.effective_inertia))

    def pose_vector(self) -> np.ndarray:
        """(13,) x, q, v, omega: what rank 0 broadcasts to every rank each step."""
        return np.concatenate([self.x, self.q, self.v, self.omega])

    def hull_in_space(self) -> np.ndarray:
        """(nv, 3) hull vertices at this pose, space frame [m]."""
        return hull_buoyancy.hull_in_space(self.vertices, position=self.x, attitude=self.q)

    # -- loads ---------------------------------------------------------------------------------
    def submerged(self, level: float) -> tuple[float, np.ndarray]:
        """(submerged volume [m^3], centre of buoyancy (3,) [m], space frame) of hull mesh and braces
        at this pose (platform.hull_buoyancy.submerged)."""
        return hull_buoyancy.submerged(self.vertices, self.triangles, self.braces, int(self.brace_slices),
                                       position=self.x, attitude=self.q, level=level)

    def hydrostatics(self, *, rho_w: float, g: float, level: float) -> tuple[np.ndarray, np.ndarray, float]:
        """(force [N], moment about the CG [N m], submerged volume [m^3]) of buoyancy at this pose:
        hull mesh and braces together, acting at their combined centre of buoyancy."""
        return hull_buoyancy.buoyancy(self.vertices, self.triangles, self.braces, int(self.brace_slices),
                                      position=self.x, attitude=self.q, rho_w=rho_w, g=g, level=level)

    @property
    def wave_panels(self) -> tuple[np.ndarray, np.ndarray]:
        """(vertices, triangles) the wave pressure is integrated over (``panels``, else the hull)."""
        return self.panels if self.panels is not None else (self.vertices, self.triangles)

    def wave_flow(self, sea, t: float, *, level: float) -> tuple[np.ndarray, np.ndarray]:
        """(particle velocity (3,) [m/s], acceleration (3,) [m/s^2]) of the undisturbed ``sea``
        (SeaComponents) at time t [s] at the centre of buoyancy of the hull cut at the surface over
        the CG, level + eta; zeros when the hull is dry."""
        eta = wave_at(sea, self.x[0], self.x[1], 0.0, t)[0]
        vol, cob = self.submerged(level + eta)
        if vol <= 0.0:
            return np.zeros(3), np.zeros(3)
        w = wave_at(sea, cob[0], cob[1], cob[2] - level, t)
        return np.array(w[1:4]), np.array(w[4:7])

    def hydro_loads(self, *, rho_w: float, g: float, level: float, current=(0.0, 0.0), sea=None, t: float = 0.0,
                    waves=None):
        """Gravity, buoyancy, quadratic damping and current drag: (force [N], moment [N m]); with a
        ``sea`` (SeaComponents) at time t [s], the wave loads of the module docstring. sea None:
        still water, exactly as without waves. waves: the sea at the panel corners and brace slices
        at time t (hull_waves.wave_loads; the platform interpolates it in time,
        platform.wave_intervals), None: summed at t. The flow at the centre of buoyancy
        (``wave_flow``, two point sums) is summed at t."""
        if sea is None:  # one kernel call
            return still_water_loads(self.vertices, self.triangles, self.braces, int(self.brace_slices), self.x,
                                     self.v, self.q, self.L, float(self.mass), self.effective_inertia,
                                     self.added_mass, self.damping, self.current_drag,
                                     np.asarray(current, float), rho_w, g, level)
        f_b, m_b = hull_waves.wave_loads(self, sea, t, rho_w=rho_w, g=g, level=level, waves=waves)
        f = f_b + np.array([0.0, 0.0, -self.mass * g])
        m = m_b
        R = rotation_matrix(self.q)
        vb = R.T @ self.v
        wb = R.T @ self.omega
        f = f - R @ (self.damping[:3] * np.abs(vb) * vb)
        m = m - R @ (self.damping[3:] * np.abs(wb) * wb)
        u, a = self.wave_flow(sea, t, level=level)
        rel = np.asarray(current, float) - self.v[:2] + u[:2]
        f = f + R @ (self.added_mass[:3] * (R.T @ a))  # Eq. 11: A a, the small body's diffraction
        f[:2] += self.current_drag * np.abs(rel) * rel
        return f, m

    # -- time stepping -------------------------------------------------------------------------
    def prescribed_velocity(self, t: float) -> tuple[np.ndarray, np.ndarray]:
        """Linear interpolation of the velocity history at time t [s] (held after its last row)."""
        h = self.prescribed
        vel = np.array([np.interp(t, h[:, 0], h[:, k]) for k in range(1, 7)])
        return vel[:3], vel[3:]

    def kick(self, half_dt: float, t: float) -> None:
        """Half-step update of v and L from self.force/self.torque (or the prescribed history)."""
        if not self.free:
            v, w = self.prescribed_velocity(t)
            self.v = v
            R = rotation_matrix(self.q)
            self.L = R @ (self.effective_inertia * (R.T @ w))
            return
        self.v, self.L = kick_free(self.v, self.L, self.q, self.force, self.torque, self.mass + self.added_mass[:3],
                                   half_dt)

    def drift(self, dt: float) -> None:
        """x += v dt and the exact torque-free rotation over dt (free_rotation)."""
        self.x = self.x + dt * self.v
        self.q = free_rotation(self.q, self.L, self.effective_inertia, dt)
