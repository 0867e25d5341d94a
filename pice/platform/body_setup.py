"""A body's mass, inertia and starting height from its hull (set-up, every rank; pure numpy).

* ``body_profile``: the rings of a hull of revolution in its body frame; a "buoy" hull (seed 004,
  hulls.buoy_design_profile) is placed with its shell's centre at the body origin.
* ``mass_and_inertia``: mass = "shell" is rho_s t S of a steel shell over the hull (shell.py), and
  an inertia left out is the shell's about its centre, which must be the body origin.
* ``afloat_position``: position = "afloat" is x = y = 0 and the height where the body's weight
  equals its buoyancy plus the vertical pull of its lines at their layout.
"""

from __future__ import annotations

import numpy as np

from ..errors import JobError
from .hull_buoyancy import submerged
from .hulls import buoy_design_profile
from .shell import mesh_shell, revolved_shell

CENTRE_TOLERANCE = 1e-4  # a shell's centre off the body origin by more than this fraction of the hull's size is refused


def body_profile(spec) -> np.ndarray | None:
    """(k, 2) (z, r) rings [m] in the body frame of a hull of revolution (``spec``: a HullSpec): a
    "revolved" hull's profile as given; a "buoy" hull's design profile raised or lowered so that its
    shell's centre (shell.revolved_shell) is the body origin. None for any other hull."""
    if spec.type == "revolved":
        return np.asarray(spec.profile, float)
    if spec.type != "buoy":
        return None
    prof = buoy_design_profile(d_max=spec.d_max, alpha_deg=spec.alpha, height=spec.height, keel=spec.buoy_keel,
                               widest=spec.buoy_widest)
    prof[:, 0] -= revolved_shell(prof, areal_density=1.0)[1][2]
    return prof


def mass_and_inertia(job, k: int, vertices: np.ndarray, triangles: np.ndarray):
    """(mass [kg] or "balance", principal inertia (3,) [kg m^2]) of bodies[k] whose hull is the mesh
    (body frame [m]). mass = "shell": shell_density x shell_thickness over the hull's surface (its true
    circles for a hull of revolution, else its triangles), and without an inertia given the shell's
    about its centre. JobError when that centre is not the body origin (the centre of gravity), or
    when the shell's principal axes are not the body's axes."""
    spec = job.bodies[k]
    if spec.mass != "shell":
        return spec.mass if spec.mass == "balance" else float(spec.mass), np.asarray(spec.inertia, float)
    where = f"{job.source}: bodies[{k}]"
    sigma = spec.shell_density * spec.shell_thickness  # [kg/m^2]
    prof = body_profile(spec.hull)
    if prof is not None:
        mass, centre, inertia = revolved_shell(prof, areal_density=sigma)
    else:
        mass, centre, tensor = mesh_shell(vertices, triangles, areal_density=sigma)
        inertia = np.diag(tensor).copy()
        off = np.abs(tensor - np.diag(inertia)).max()
        if spec.inertia is None and off > 1e-6 * inertia.sum():
            raise JobError(f"{where}.inertia = (absent): the shell's inertia has products of inertia up to "
                           f"{off:.4g} kg m^2 (its principal axes are not the body axes); give "
                           "inertia = [roll, pitch, yaw] (kg m^2)")
    size = float(np.ptp(vertices, axis=0).max())
    if np.linalg.norm(centre) > CENTRE_TOLERANCE * size:
        fix = ("shift the profile's z by {:.6g} m".format(-centre[2]) if prof is not None
               else "shift the hull by ({:.6g}, {:.6g}, {:.6g}) m".format(*(-centre)))
        raise JobError(f"{where}.mass = \"shell\": the shell's centre of gravity lies at ({centre[0]:.4g}, "
                       f"{centre[1]:.4g}, {centre[2]:.4g}) m in the body frame, not at its origin; {fix}, or use "
                       "hull.type = \"buoy\", which centres itself")
    if spec.inertia is not None:
        inertia = np.asarray(spec.inertia, float)
    return float(mass), inertia


def afloat_position(job, k: int, vertices: np.ndarray, triangles: np.ndarray, braces: np.ndarray,
                    attitude, *, mass: float, pull_z: float) -> np.ndarray:
    """(3,) position [m] of bodies[k] at x = y = 0 and the height z where rho_w V(z) + pull_z / g = mass:
    its buoyancy (hull and braces, platform.hull_buoyancy, at ``attitude``) carries its ``mass`` [kg]
    and the lines' vertical pull ``pull_z`` [N] (< 0: down). JobError when the whole hull under water
    cannot carry them (it sinks), or when the lines alone lift it."""
    from scipy.optimize import brentq

    w, g = job.water, job.gravity
    where = f"{job.source}: bodies[{k}].position = \"afloat\""
    if mass == "balance":  # refused by the schema
        raise JobError(f"{where}: needs a mass (kg or \"shell\")")

    def excess(z):  # [kg]
        vol = submerged(vertices, triangles, braces, position=np.array([0.0, 0.0, z]), attitude=np.asarray(attitude),
                        level=w.level)[0]
        return w.density * vol + pull_z / g - mass

    z_dry, z_wet = w.level - vertices[:, 2].min(), w.level - vertices[:, 2].max()
    if excess(z_wet) < 0.0:
        full = w.density * submerged(vertices, triangles, braces, position=np.array([0.0, 0.0, z_wet]),
                                     attitude=np.asarray(attitude), level=w.level)[0]
        lines = f" and the lines' pull of {-pull_z / g:.4g} kg" if pull_z else ""
        raise JobError(f"{where}: the hull cannot float: wholly under water it displaces {full:.6g} kg of water, "
                       f"less than its mass {mass:.6g} kg{lines}; lighten it "
                       "(shell_thickness) or enlarge the hull")
    if excess(z_dry) >= 0.0:
        raise JobError(f"{where}: the lines' pull {pull_z:.4g} N lifts the body ({mass:.6g} kg) out of the water; "
                       "check the mooring's pretension and fairleads")
    z = float(brentq(excess, z_wet, z_dry, xtol=1e-10))
    return np.array([0.0, 0.0, z])
