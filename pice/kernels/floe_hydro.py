"""Water on rigid floes (numba, arrays in and out): gravity, buoyancy of the submerged part of each
floe's polyhedron, heave/roll/pitch damping, current drag, and the waves' Froude-Krylov, diffraction
and drag loads (issue 14).

With waves, a floe's buoyancy is that of its part below the surface at its centre, level + eta_c, so
that a floe riding a wave higher than its freeboard keeps floating (cut at the still level, a 2 m
wave would sink a 2.6 m floe of 0.27 m freeboard in its troughs). A floe is small against the waves
(seed 003's premise for its Eq. 11: under 1/5 of the wavelength; a 40 m floe in a 20 s sea of 52 m
depth is 1/11): the undisturbed dynamic pressure less rho g eta_c varies linearly across it, and its
integral over the wetted surface closed by the cut is the volume integral of its gradient, the
Froude-Krylov force rho V a_c, with a_c the waves' acceleration at the floe's centre of mass, where
Eq. 11 evaluates it; Eq. 11's diffraction term adds A a_c with the floe's added mass A. The drag
takes the waves' particle velocity there too, and the surface is cut at the elevation there: one
sum over the sea's components per floe and step. Their moments, and the pitch the wave's
slope (k a, 0.01 for the seed's sea) would give, are left out.

Per floe of mass m, centre x, velocity v, angular velocity w, water-plane area A_wp [m^2]:

- gravity -m g at x; buoyancy rho_w g V up at the centre of buoyancy, where V is the part of the
  polyhedron below the water level (kernels/polyhedra.clip);
- for a floe in the surface, linear damping of heave, roll and pitch at ``damping_ratio`` of critical
  for the hydrostatic stiffnesses, rho_w g A_wp in heave and rho_w g A_wp r^2 in roll and pitch with
  r^2 = I / m (standing for the radiation damping the seed takes from WAMIT; an assumption, like the
  level ice's heave damping ratio);
- skin drag of the current on the bottom, rho_w C_w A_wp |u| u, and form drag on the wetted side,
  1/2 rho_w C_d d b |u| u, b the floe's width across u, with u the current relative to the floe's
  horizontal velocity (seed 003 Eq. 12 for the form drag; the skin drag as the level ice). d is the
  side's wetted height: the draft, level - z_min, for a floe in the surface; its own height z_max -
  z_min for a floe wholly under it (a keel's block: the water above it does not widen its wake);
- a floe wholly under the surface has no water plane, so no hydrostatic stiffness and none of the
  damping above; it moves through the water vertically against the form drag on its faces,
  1/2 rho_w C_d A_wp |w| w, A_wp its plan area and w its vertical velocity relative to the water's
  (the waves' vertical particle velocity at its centre of mass; none in still water). A floe in the
  surface moves with the surface (its buoyancy is cut at eta): its heave damping stands for the
  radiation damping, which acts on the body's own velocity.
"""

import math

import numpy as np
from numba import njit

from . import JIT
from .polyhedron_contact import part_inside
from .waves import sea_point

SEA_COLUMNS = 7  # the sea at a floe (``floe_sea``): eta, u_x, u_y, a_x, a_y, a_z, u_z


@njit(**JIT)
def floe_sea(lo, hi, stride, x, amp, omega, k, direction, phase, depth, g, rho_w, t, out):
    """The undisturbed sea at the centres of mass x of floes lo, lo + stride, ... below hi at time t [s] into out
    (n, SEA_COLUMNS): the elevation eta [m], the particle velocity u_x, u_y [m/s], the acceleration
    a_x, a_y, a_z [m/s^2] and the vertical particle velocity u_z [m/s] (one sum over the components
    per floe: kernels/waves.sea_point)."""
    for i in range(lo, hi, stride):
        eta, u0, u1, u2, a0, a1, a2, _ = sea_point(amp, omega, k, direction, phase, depth, g, rho_w,
                                                   x[i, 0], x[i, 1], x[i, 2], t)
        out[i, 0], out[i, 1], out[i, 2], out[i, 3], out[i, 4], out[i, 5] = eta, u0, u1, a0, a1, a2
        out[i, 6] = u2


@njit(**JIT)
def floe_water(lo, hi, stride, x, v, omega, rot, mass, inertia, area, volume, pts, counts, level, rho_w, g, current, skin,
               form, damping_ratio, wave, added, force, torque):
    """Add the water's forces [N] and torques about each centre [N m] to the floes lo, lo + stride, ... below hi; returns the
    total submerged volume [m^3]. omega (n, 3) [rad/s] and the torques in space; rot (n, 3, 3) each
    floe's attitude (body to space, its principal axes); pts, counts: world polyhedra; area:
    water-plane areas [m^2]; volume (n,) each floe's volume [m^3] (a floe wholly under the surface,
    a keel's block, floats on it about its centre, with no clipping); inertia (n, 3) principal
    moments [kg m^2]; current (2,) [m/s]; skin
    C_w, form C_d [-]; ``wave`` (n, SEA_COLUMNS): the sea at each floe's centre of mass (``floe_sea``:
    eta, u_x, u_y, a_x, a_y, a_z, u_z; an empty array: still water), whose acceleration drives the
    Froude-Krylov force and whose particle velocity adds to the current in the drag, and for a floe
    wholly under the surface to the vertical drag (module docstring). With
    waves, ``added`` (n, 3) [kg]: each floe's added mass along x, y, z, times the waves'
    acceleration (seed 003 Eq. 11's diffraction force on a small body).
    """
    total = 0.0
    buf = np.empty((2, pts.shape[2] + 2, 3))
    for i in range(lo, hi, stride):
        # with waves the floe floats on the surface where it is: its buoyancy is cut at level + eta there
        # (module docstring)
        eta = uw0 = uw1 = aw0 = aw1 = aw2 = uw2 = 0.0
        waves = wave.shape[0] > 0
        if waves:  # the undisturbed sea at the floe's centre of mass (seed 003 Eq. 11)
            eta, uw0, uw1, aw0, aw1, aw2 = wave[i, 0], wave[i, 1], wave[i, 2], wave[i, 3], wave[i, 4], wave[i, 5]
            uw2 = wave[i, 6]
        flow0, flow1 = current[0] + uw0, current[1] + uw1
        u0, u1 = flow0 - v[i, 0], flow1 - v[i, 1]
        speed = math.sqrt(u0 * u0 + u1 * u1)
        across0, across1 = (-u1 / speed, u0 / speed) if speed > 0.0 else (0.0, 0.0)  # across the flow
        # the submerged part: volume, centre of buoyancy, its extent across the flow and its lowest point;
        # the whole floe when every vertex is under the surface, else clipped at it
        # (kernels/polyhedron_contact.part_inside)
        wide_lo, wide_hi, zmin, zmax = math.inf, -math.inf, math.inf, -math.inf
        for f in range(counts.shape[1]):
            for j in range(counts[i, f]):
                across = pts[i, f, j, 0] * across0 + pts[i, f, j, 1] * across1
                wide_lo, wide_hi = min(wide_lo, across), max(wide_hi, across)
                zmin, zmax = min(zmin, pts[i, f, j, 2]), max(zmax, pts[i, f, j, 2])
        force[i, 2] -= mass[i] * g
        submerged = zmax <= level + eta
        top = zmax if submerged else level  # the wetted side's top edge (module docstring)
        if submerged:
            vol, cb0, cb1 = volume[i], x[i, 0], x[i, 1]
        else:
            vol, cob, _, wide_lo, wide_hi, zmin = part_inside(pts[i], counts[i], 0.0, 0.0, 1.0, level + eta, buf,
                                                              across0, across1)
            cb0, cb1 = cob[0], cob[1]
        if vol <= 0.0:
            continue
        total += vol
        fb = rho_w * g * vol
        force[i, 2] += fb
        torque[i, 0] += (cb1 - x[i, 1]) * fb
        torque[i, 1] -= (cb0 - x[i, 0]) * fb
        if submerged:  # no water plane, so no hydrostatic stiffness to damp: form drag across the faces
            wz = v[i, 2] - uw2  # through the water (still water: uw2 = 0)
            force[i, 2] -= 0.5 * rho_w * form * area[i] * abs(wz) * wz
        else:  # heave, roll and pitch damping of a floe in the surface
            k_heave = rho_w * g * area[i]
            force[i, 2] -= damping_ratio * 2.0 * math.sqrt(k_heave * mass[i]) * v[i, 2]
            R = rot[i]
            for a in range(2):  # about the principal axes: roll and pitch are the first two (scalars: no BLAS)
                wb = R[0, a] * omega[i, 0] + R[1, a] * omega[i, 1] + R[2, a] * omega[i, 2]
                k_tilt = k_heave * inertia[i, a] / mass[i]
                tb = -damping_ratio * 2.0 * math.sqrt(k_tilt * inertia[i, a]) * wb
                for e in range(3):
                    torque[i, e] += R[e, a] * tb
        if waves:
            # Froude-Krylov rho V a and the diffraction term A a (seed 003 Eq. 11, a small body)
            force[i, 0] += (rho_w * vol + added[i, 0]) * aw0
            force[i, 1] += (rho_w * vol + added[i, 1]) * aw1
            force[i, 2] += (rho_w * vol + added[i, 2]) * aw2
        # drag of the current (and the waves' particle velocity): skin on the bottom, form on the side
        if speed == 0.0:
            continue
        drag = rho_w * (skin * area[i] + 0.5 * form * (top - zmin) * (wide_hi - wide_lo)) * speed
        force[i, 0] += drag * u0
        force[i, 1] += drag * u1
    return total
