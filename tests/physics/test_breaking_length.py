"""Static breaking length (004_4e604f4929f28a45.txt, Section 5.4.2, Eqs. 5-18..5-21, Table 5-2).

Ice with effective E = 5 GPa, nu = 0.3, t = 1 m, density 925 kg/m^3 and flexural strength 0.5 MPa,
on water of 1025 kg/m^3, pushed slowly against a fixed 45-degree slope, first cracks in bending

    x_bl = sqrt(2) l arctan(sqrt(2) l / (sqrt(2) l - t tan(alpha))),  l = delta^(1/4),
    delta = E t^3 / (12 rho_w g (1 - nu^2))                       -> 16.74 m,

from the contact, here within 10 % with 1 m elements (jobs/breaking_length.toml).

What the DEM can be expected to give (docs/bond_calibration.md, section 5): the slope's force on a
sphere passes through its centre, so there is no eccentric end moment (the t tan(alpha) term) and
the ideal is the maximum of the moment of an end-loaded semi-infinite beam, pi / (4 beta) =
sqrt(2) l pi / 4 = 16.23 m. A three-row strip with free sides is a beam, not a plate: its EI per
unit width is 0.896 D (free anticlastic curving plus the lattice's edge rows) so l_strip = 0.973 l
and pi / (4 beta_strip) = 15.79 m from the front element's centre, plus the 0.35 m from that centre
to the contact point on the slope. The bending moment is flat at its maximum (within 0.1 % over
+-0.6 m), so the first bond to break is the x-bond with the largest moment among those 0.5 m apart.

Measured (one core): the first break is a tension/bending failure (mode 1) of an x-bond of the middle
row 16.35 m from the contact point (-2.3 % from 16.74 m; +1.3 % from this strip's ideal, 16.14 m), at t = 6.95 s
under a contact force of 34.9 kN vertical (the plate-calibrated bonds break at the flexural
strength on the strip's section, docs/bond_calibration.md); ~15 s wall time.

With crushing on (issue 11: "the static breaking-length check still holds"): the same job with
`[crushing]`, ISO 19906's pressure on the slope for the strip's 2.8 m width (1.27 MPa) and ice-ice
crushing at Table 5-2's compressive strength (0.6 MPa, which the job leaves out of ice.compressive_strength
for Eq. 7's sake), within the same 10 %. Measured: the same bond breaks first, at the same place
(16.35 m): the slope's contact stays elastic (plastic penetration 0: the first crack's normal force,
49 kN or 35 kN vertical, is below the cap p_G x chord x h at the overlap the wall's spring gives it,
57 kN at 0.5 mm on one element). With the slope at Table 5-2's 0.6 MPa instead, the contact yields
0.18 mm and the same bond breaks 0.01 s later; ~15 s more for the file.
"""

import math

import numpy as np
import pytest
from scenes import JOBS, tomllib  # the standard library's, or tomli on Python 3.10

from pice.job import load_job, parse_job
from pice.simulation import Simulation

JOB = JOBS / "breaking_length.toml"


def eq_5_18_breaking_length(*, E, nu, t, rho_w, g, alpha):
    """x_bl [m] of Eqs. 5-18..5-20 of 004 (Keijdener's static breaking length)."""
    delta = E * t ** 3 / (12.0 * rho_w * g * (1.0 - nu ** 2))    # Eq. 5-20 [m^4]
    l = delta ** 0.25                                            # Eq. 5-19 [m]
    s = math.sqrt(2.0) * l
    return s * math.atan(s / (s - t * math.tan(alpha))), l       # Eq. 5-18


def _with_crushing():
    """jobs/breaking_length.toml with [crushing]: ISO 19906 on the slope for the strip's width, ice on
    ice at Table 5-2's compressive strength."""
    data = tomllib.loads(JOB.read_text())
    data["crushing"] = {"structure": "iso19906", "ice": 0.6e6}
    data["walls"][0]["crushing_width"] = data["ice"]["width"]
    return parse_job(data, source=f"{JOB} with [crushing]")


@pytest.mark.parametrize("crushing", [False, True], ids=["elastic", "crushing"])
def test_first_crack_at_the_static_breaking_length(crushing):
    job = _with_crushing() if crushing else load_job(JOB)
    assert (job.crushing is not None) == crushing
    ice, water, g = job.ice, job.water, job.gravity
    (wall,) = job.walls
    normal = np.asarray(wall.normal, float) / np.linalg.norm(wall.normal)
    alpha = math.atan2(-normal[0], normal[2])                    # slope angle of the plane
    assert math.isclose(math.degrees(alpha), 45.0)
    x_bl, l = eq_5_18_breaking_length(E=ice.youngs_modulus, nu=ice.poissons_ratio, t=ice.thickness,
                                      rho_w=water.density, g=g, alpha=alpha)
    assert abs(x_bl - 16.74) < 0.01                              # Eq. 5-21
    assert ice.element_diameter <= 1.0 and ice.element_volume == "cell"
    assert job.bond.breakable and ice.push is not None

    sim = Simulation(job)
    p = sim.p
    n = p.nlocal
    front = np.nonzero(np.isclose(p.x[:n, 0], p.x[:n, 0].max()))[0]
    front_gid = p.gid[front].copy()
    n_rows = len(np.unique(np.round(p.x[:n, 1], 6)))           # rows of the strip, at t = 0

    # push until the first bond breaks (what run.stop_at_first_break does in `pice run`)
    chunk = 50
    while sim.c.broken == 0 and sim.c.time < job.run.duration:
        sim.advance(chunk)
    assert sim.c.broken > 0, f"no bond broke within {job.run.duration} s"

    def at(gid):
        (i,) = np.nonzero(p.gid[:n] == gid)[0]
        return p.x[i]

    step, time, ga, gb, mode = sim.c.events[0]
    assert mode == 1, f"first break in mode {mode}, expected 1 (tension/bending, Eq. 3)"
    mid = 0.5 * (at(ga) + at(gb))
    # contact point of the front element(s) on the plane: the centre moved back along the normal
    point = np.asarray(wall.point, float)
    contacts = []
    for gid in front_gid:
        c = at(gid)
        dist = float((c - point) @ normal)
        assert dist < float(p.radius[0]), "the front element must touch the slope"
        contacts.append(c - dist * normal)
    contact = np.mean(contacts, axis=0)
    measured = float(contact[0] - mid[0])

    # the DEM's own ideal: end-loaded strip, force through the sphere centre (module docstring)
    d = ice.element_diameter
    kb, kt = sim.bond.kb, sim.bond.kt
    EI = d * (n_rows * kb + (n_rows - 1) * 2.0 * kb * kt / (3.0 * kb + kt))
    k = water.density * g * n_rows * math.sqrt(3.0) / 2.0 * d   # cell elements: rho_w g x width
    ideal = math.pi / 4.0 * (4.0 * EI / k) ** 0.25 + (contact[0] - np.mean([at(q)[0] for q in front_gid]))

    v_force = -sim.wall_loads()[0][2]
    print(f"\nEq. 5-18: x_bl = {x_bl:.2f} m (l = {l:.2f} m); sphere-centred force: sqrt(2) l pi/4 = "
          f"{math.sqrt(2) * l * math.pi / 4:.2f} m; this strip: {ideal:.2f} m from the contact point")
    print(f"DEM: first break (mode {mode}) of bond {ga}-{gb} at t = {time:.2f} s, "
          f"{measured:.2f} m from the contact ({100 * (measured / x_bl - 1):+.1f} % vs Eq. 5-18), "
          f"contact force {v_force / 1e3:.1f} kN vertical")
    assert abs(measured / x_bl - 1.0) < 0.10
