"""A floating rigid body (rank 0): 6 degrees of freedom, attitude as a unit quaternion (Eq. 11).

Equation of motion (Eq. 9 of Zhu & Ji 2022 without the radiation memory term):
    (M + M_add) u'' = F_ice + F_mooring + F_buoyancy + F_gravity + F_current - B |u'| u'
with a constant, diagonal added mass in the body frame (surge, sway, heave, roll, pitch, yaw),
quadratic damping per body-frame degree of freedom, buoyancy from the instantaneous submerged
volume of the hull mesh (Eq. 12, kernels.hull) plus that of its cylindrical braces cut by the
water plane (Eqs. 13-14), acting at the combined centre of buoyancy, and current
drag 1/2 rho C_d A |u_c - v| (u_c - v) on the horizontal motion. Motion is "free" or
"prescribed" (a velocity history, e.g. a ship pushed at constant speed).

Time stepping is velocity Verlet: `kick` (half step of momentum and angular momentum), `drift`
(translation and the exact free rotation of kernels.rigid_body), forces at the new pose, `kick`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..kernels.hull import brace_submerged, submerged_volume, transform
from ..kernels.geometry import rotation_matrix
from ..kernels.rigid_body import angular_velocity, free_rotation


def euler_angles(q) -> np.ndarray:
    """(roll, pitch, yaw) [rad] of a unit quaternion (w, x, y, z): the z-y'-x'' (yaw, then pitch, then
    roll) angles of ship motions."""
    w, x, y, z = (float(c) for c in q)
    roll = math.atan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y))
    pitch = math.asin(max(-1.0, min(1.0, 2.0 * (w * y - z * x))))
    yaw = math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
    return np.array([roll, pitch, yaw])


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
    # (k, 7) rows (p0 (3), p1 (3), radius) [m], body frame: cylindrical braces, buoyancy only (Eqs. 13-14;
    # no ice contact), e.g. scenes.hulls.semi_submersible_braces(); they must not overlap the mesh
    braces: np.ndarray = field(default_factory=lambda: np.zeros((0, 7)))
    brace_slices: int = 64           # segments per brace along its axis (Eq. 13)
    x: np.ndarray = field(default_factory=lambda: np.zeros(3))    # CG position [m]
    v: np.ndarray = field(default_factory=lambda: np.zeros(3))    # CG velocity [m/s]
    q: np.ndarray = field(default_factory=lambda: np.array([1.0, 0.0, 0.0, 0.0]))
    L: np.ndarray = field(default_factory=lambda: np.zeros(3))    # angular momentum, space frame [kg m^2/s]
    force: np.ndarray = field(default_factory=lambda: np.zeros(3))
    torque: np.ndarray = field(default_factory=lambda: np.zeros(3))

    def __post_init__(self) -> None:
        b = np.asarray(self.braces, float)
        if b.size == 0:
            b = np.zeros((0, 7))
        if b.ndim != 2 or b.shape[1] != 7:
            raise ValueError(f"body {self.name!r}: braces must be (k, 7) rows (p0, p1, radius), got shape {b.shape}")
        if np.any(b[:, 6] <= 0.0) or np.any(np.linalg.norm(b[:, 3:6] - b[:, :3], axis=1) <= 0.0):
            raise ValueError(f"body {self.name!r}: every brace needs a radius > 0 m and distinct ends p0, p1")
        if int(self.brace_slices) < 1:
            raise ValueError(f"body {self.name!r}: brace_slices = {self.brace_slices}: must be >= 1")
        self.braces = b

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

    def pose_vector(self) -> np.ndarray:
        """(13,) x, q, v, omega: what rank 0 broadcasts to every rank each step."""
        return np.concatenate([self.x, self.q, self.v, self.omega])

    def hull_in_space(self) -> np.ndarray:
        return transform(self.vertices, rotation_matrix(self.q), self.x)

    # -- loads ---------------------------------------------------------------------------------
    def submerged(self, level: float) -> tuple[float, np.ndarray]:
        """(submerged volume [m^3], centre of buoyancy (3,) [m], space frame) at this pose: the clipped
        hull mesh (Eq. 12) plus the braces sliced along their axes (Eqs. 13-14). NaN centre when dry."""
        vol, cob = submerged_volume(self.hull_in_space(), self.triangles, level)
        if len(self.braces) == 0:
            return vol, cob
        R = rotation_matrix(self.q)
        mom = vol * cob if vol > 0.0 else np.zeros(3)
        for row in self.braces:
            vb, cb = brace_submerged(R @ row[:3] + self.x, R @ row[3:6] + self.x, row[6], level,
                                     int(self.brace_slices))
            if vb > 0.0:
                vol += vb
                mom = mom + vb * cb
        if vol <= 0.0:
            return 0.0, np.full(3, np.nan)
        return vol, mom / vol

    def hydrostatics(self, *, rho_w: float, g: float, level: float) -> tuple[np.ndarray, np.ndarray, float]:
        """(force [N], moment about the CG [N m], submerged volume [m^3]) of buoyancy at this pose:
        hull mesh and braces together, acting at their combined centre of buoyancy."""
        vol, cob = self.submerged(level)
        if vol <= 0.0:
            return np.zeros(3), np.zeros(3), 0.0
        f = np.array([0.0, 0.0, rho_w * g * vol])
        return f, np.cross(cob - self.x, f), vol

    def hydro_loads(self, *, rho_w: float, g: float, level: float, current=(0.0, 0.0)):
        """Gravity, buoyancy, quadratic damping and current drag: (force [N], moment [N m])."""
        f_b, m_b, _ = self.hydrostatics(rho_w=rho_w, g=g, level=level)
        f = f_b + np.array([0.0, 0.0, -self.mass * g])
        m = m_b
        R = rotation_matrix(self.q)
        vb = R.T @ self.v
        wb = R.T @ self.omega
        f = f - R @ (self.damping[:3] * np.abs(vb) * vb)
        m = m - R @ (self.damping[3:] * np.abs(wb) * wb)
        rel = np.asarray(current, float) - self.v[:2]
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
        R = rotation_matrix(self.q)
        m_eff = self.mass + self.added_mass[:3]
        self.v = self.v + half_dt * (R @ ((R.T @ self.force) / m_eff))
        self.L = self.L + half_dt * self.torque

    def drift(self, dt: float) -> None:
        """x += v dt and the exact torque-free rotation over dt (kernels.rigid_body)."""
        self.x = self.x + dt * self.v
        self.q = free_rotation(self.q, self.L, self.effective_inertia, dt)
