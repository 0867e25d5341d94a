"""The moored Kulluk (jobs/kulluk_2017_mooring.toml): its surge restoring curve and surge natural period.

Scene: the job as shipped (seed 003, Tables 1-2: 12 wire lines 30 degrees apart, fairleads on the
keel 18 m from the centre, 39.5 m above the anchors, 917 m long, 274.68 N/m wet, EA 4.1874805e8 N; the
300 kN pretension is the job's assumption), built as a run builds it (pice.platform.build:
the layout solve places the anchors, a "balance" mass floats the hull at its 12.5 m draft), in
its "quasi_static" and "dem" mooring models. The platform is stepped on its own (Platform.kick,
drift, loads), without the Simulation.

Reference: an elastic catenary with seabed contact written here from the textbook equations
(Irvine, Cable Structures, 1981, Eqs. 2.26-2.27 with the grounded part straight on a frictionless
seabed; Faltinsen, Sea Loads on Ships and Offshore Structures, 1990, Sec. 8.2), solved for the
horizontal and vertical fairlead tensions (H, V) together by a Levenberg-Marquardt root solve; it
shares no code with pice.platform.catenary, nor with tests/reference_catenary.py (nested bracketed
solves), which it also matches. The 12 lines' forces are summed for the body translated in surge
(the restoring curve) and, for the period, also pitched: the lines pull at the keel, 12.5 m below
the CG, so the hull pitches as it surges (quasi-statically: its pitch period is ~8.5 s, its surge
period ~64 s), which softens the surge stiffness by 0.8 %: K_eff = K11 - K15 K51 / K55 with the
hydrostatic pitch stiffness rho g (I_wp + V z_B) of the 24-sided hull (CG on the waterline) added to
the lines' K55. docs/kulluk.md, "The structure and its mooring", has the numbers.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import reference_catenary as rc
import scenes
from scenes import tomllib
from scipy.optimize import root

from pice.job import parse_job
from pice.platform.build import build_platform, hulls_from_job

JOB = scenes.JOBS / "kulluk_2017_mooring.toml"
LENGTH, WET, EA = 917.0, 28.0 * 9.81, 456.65e3 * 917.0  # [m], [N/m], [N] (Table 2)
HEIGHT, FAIRLEAD_R, KEEL = 39.5, 18.0, -12.5             # fairlead above the anchor, its radius, its z [m]
PRETENSION = 300.0e3                                     # [N] (the job's assumption)
RHO, G = 1025.0, 9.81


# -- the reference: one elastic catenary line with seabed contact --------------------------------
def line_spans(H: float, V: float) -> tuple[float, float]:
    """(x, z) [m] of the fairlead from the anchor for fairlead tensions H, V [N]: while V <= w L the
    line touches down where its vertical tension vanishes (suspended length V / w) and lies straight
    on the seabed from there to the anchor, stretched by H / EA; beyond, it hangs whole and pulls
    the anchor up with V - w L."""
    w, L = WET, LENGTH
    if V <= w * L:
        s = V / w
        x = (L - s) * (1.0 + H / EA) + H / w * math.asinh(V / H) + H * s / EA
        z = H / w * (math.hypot(1.0, V / H) - 1.0) + V * s / (2.0 * EA)
    else:
        va = V - w * L
        x = H / w * (math.asinh(V / H) - math.asinh(va / H)) + H * L / EA
        z = H / w * (math.hypot(1.0, V / H) - math.hypot(1.0, va / H)) + (V * V - va * va) / (2.0 * w * EA)
    return x, z


def line_tensions(X: float, Z: float, guess=(2.9e5, 8.0e4)) -> tuple[float, float]:
    """(H, V) [N] of the line whose fairlead is X [m] out and Z [m] above its anchor, to 1e-9 m; the
    root solve starts from ``guess`` (H, V) [N], then, if it stalls at the touchdown's kink, from a
    few others."""
    scale = WET * LENGTH

    def residual(u):
        x, z = line_spans(scale * u[0], scale * u[1])
        return [x - X, z - Z]

    for h0, v0 in (guess, (1.0e5, 6.0e4), (1.0e6, 2.0e5), (1.0e7, 1.0e6), (3.0e4, 3.0e4)):
        sol = root(residual, [h0 / scale, v0 / scale], method="lm", options=dict(xtol=1e-15, ftol=1e-15))
        H, V = scale * sol.x
        if H > 0.0 and V > 0.0:
            x, z = line_spans(H, V)
            if abs(x - X) < 1e-9 * X and abs(z - Z) < 1e-9 * Z:
                return H, V
    raise AssertionError(f"no catenary through ({X}, {Z}) m: {sol.message}")


class Spread:
    """The 12 reference lines: fairleads on the keel at 18 m radius, headings 0, 30, ..., 330 deg,
    anchors ``radius`` [m] out from their fairleads (where a line pulls with the pretension)."""

    def __init__(self):
        heading = np.radians(np.arange(12) * 30.0)
        out = np.column_stack([np.cos(heading), np.sin(heading), np.zeros(12)])
        self.radius = float(self._anchor_radius())
        self.fairleads = FAIRLEAD_R * out + [0.0, 0.0, KEEL]  # body frame, CG at the origin
        self.anchors = self.fairleads + self.radius * out - [0.0, 0.0, HEIGHT]
        self.guess = [(PRETENSION, 8.0e4)] * 12

    @staticmethod
    def _anchor_radius() -> float:
        from scipy.optimize import brentq
        return brentq(lambda X: math.hypot(*line_tensions(X, HEIGHT)) - PRETENSION, 0.99 * LENGTH, LENGTH,
                      xtol=1e-10)

    def wrench(self, *, surge: float = 0.0, pitch: float = 0.0):
        """(forces (12, 3) [N] of the lines on their fairleads, their moment about the CG (3,) [N m],
        fairlead tensions (12,) [N]) for the body translated by ``surge`` [m] and pitched by
        ``pitch`` [rad] about +y."""
        c, s = math.cos(pitch), math.sin(pitch)
        rot = np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])
        forces, moment, tension = np.zeros((12, 3)), np.zeros(3), np.zeros(12)
        for k in range(12):
            r = rot @ self.fairleads[k]
            d = r + [surge, 0.0, 0.0] - self.anchors[k]
            X = math.hypot(d[0], d[1])
            H, V = self.guess[k] = line_tensions(X, d[2], self.guess[k])
            forces[k] = [-H * d[0] / X, -H * d[1] / X, -V]
            moment += np.cross(r, forces[k])
            tension[k] = math.hypot(H, V)
        return forces, moment, tension

    def restoring(self, surge: float) -> float:
        """-F_x [N] at ``surge`` [m] of pure translation."""
        return -float(self.wrench(surge=surge)[0][:, 0].sum())


def hull_pitch_stiffness() -> float:
    """rho g (I_wp + V z_B) [N m/rad]: the hydrostatic pitch stiffness of the job's 24-sided hull (vertices
    on the circles of Table 1's radii) floating at 12.5 m with its CG on the waterline."""
    phi = 2.0 * math.pi * np.arange(24) / 24
    x0, y0 = 35.0 * np.cos(phi), 35.0 * np.sin(phi)
    x1, y1 = np.roll(x0, -1), np.roll(y0, -1)
    cross = x0 * y1 - x1 * y0
    i_wp = float((cross * (x0 * x0 + x0 * x1 + x1 * x1)).sum()) / 12.0  # [m^4] about the y axis
    polygon = float(cross.sum()) / 2.0 / (math.pi * 35.0 ** 2)          # polygon / circle area
    volume = moment = 0.0
    for (za, ra), (zb, rb) in (((-12.5, 31.0), (-6.553, 31.0)), ((-6.553, 31.0), (0.0, 35.0))):
        z = np.linspace(za, zb, 2001)
        zc, dz = 0.5 * (z[1:] + z[:-1]), np.diff(z)
        area = polygon * math.pi * np.interp(zc, [za, zb], [ra, rb]) ** 2
        volume += float((area * dz).sum())
        moment += float((area * zc * dz).sum())
    return RHO * G * (i_wp + moment)


# -- the job's platform --------------------------------------------------------------------------
def platform(model: str):
    """The job's Platform (rank 0's bodies and lines, as set-up builds them) with mooring ``model``."""
    data = tomllib.loads(JOB.read_text())
    data["moorings"][0]["model"] = model
    job = parse_job(data, source=str(JOB))
    return build_platform(job, hulls_from_job(job, default_kn=1.0e8, reach=0.5))


def move(pf, surge: float, *, speed: float = 1.0) -> None:
    """Translate the body to ``surge`` [m] (at rest), its fairleads carried at ``speed`` [m/s] (DEM
    lines, then settled to 20 N a node) or moved at once (quasi-static lines); loads evaluated."""
    body, lines = pf.bodies[0], pf.groups[0].lines
    start = body.x[0]
    body.x = np.array([surge, body.x[1], body.x[2]])
    target, _ = pf.fairlead_positions()
    if hasattr(lines, "relax"):
        dt = 0.5 * lines.stable_step()
        n = max(1, int(math.ceil(abs(surge - start) / speed / dt)))
        lines.advance(abs(surge - start) / speed / n, n, target, np.tile([math.copysign(speed, surge - start), 0, 0],
                                                                          (len(target), 1)))
        lines.relax(tol=20.0)
        assert lines.settled
    else:
        lines.advance(0.0, 1, target)
    pf.loads()


# -- the checks ----------------------------------------------------------------------------------
def test_quasi_static_layout_and_restoring_curve_match_the_reference():
    """model = "quasi_static": the anchors the layout solve places for 300 kN (914.05 m out from their
    fairleads) and the restoring force and largest fairlead tension at 0-10 m of surge equal the
    reference's within 1e-6 (both solve the same continuous equations to round-off; measured
    ~1e-13), which itself matches tests/reference_catenary.py within 1e-8. Also pinned, for the
    docs: 626 m of each line on the seabed at rest, K = dF/dx = 722 kN/m at rest, 10.65 MN and a
    3.69 MN line (72 % of the 5.1 MN breaking load) at 10 m."""
    ref = Spread()
    assert ref.radius == pytest.approx(914.05, abs=0.01)
    assert ref.radius == pytest.approx(rc.anchor_radius([rc.Piece(LENGTH, WET, EA)], HEIGHT, PRETENSION), rel=1e-9)
    _, V = line_tensions(ref.radius, HEIGHT)
    assert LENGTH - V / WET == pytest.approx(626.0, abs=0.5)  # grounded [m]
    pf = platform("quasi_static")
    qs = pf.groups[0].lines
    rel = qs.anchors_x - qs.fairlead_x
    np.testing.assert_allclose(np.hypot(rel[:, 0], rel[:, 1]), ref.radius, rtol=1e-9)
    np.testing.assert_allclose(rel[:, 2], -HEIGHT, atol=1e-9)
    spread = rc.spread(np.arange(12) * 30.0, radius=ref.radius, Z=HEIGHT)
    for surge in (0.0, 1.0, 2.0, 3.0, 5.0, 7.0, 10.0):
        move(pf, surge)
        forces, _, tension = ref.wrench(surge=surge)
        pulls = np.abs(forces[:, 0]).sum()  # the lines' summed horizontal pulls in x [N]
        assert -pf.mooring_force[0, 0] == pytest.approx(-forces[:, 0].sum(), abs=1e-6 * pulls)
        np.testing.assert_allclose(qs.fairlead_tensions(), tension, rtol=1e-6)  # lines in the same order
        assert ref.restoring(surge) == pytest.approx(rc.restoring([rc.Piece(LENGTH, WET, EA)], spread, surge)[0],
                                                     abs=1e-8 * pulls)
    assert (ref.restoring(0.01) - ref.restoring(-0.01)) / 0.02 == pytest.approx(722.2e3, rel=1e-3)
    assert ref.restoring(10.0) == pytest.approx(10.647e6, rel=1e-3)
    assert ref.wrench(surge=10.0)[2].max() == pytest.approx(3.694e6, rel=1e-3)


def test_dem_restoring_curve_matches_the_reference():
    """model = "dem" (the job's 20 m elements, settled at rest as a run starts them): the hull moved
    at 1 m/s to 2, 5 and 10 m of surge and the lines settled (20 N a node): the restoring force is
    the reference's within 0.5 % of the lines' summed horizontal pulls and the largest fairlead
    tension within 0.3 % (measured: 0.09-0.31 % and 0.00-0.23 %). The DEM lines' own bias is
    ~0.2 %: their grounded part lies with its axis D/2 + w/k_bed = 47 mm above the seabed, where
    the anchor and the reference's line are, and this mooring is so nearly taut (914.05 m of span
    for 917 m of line, 39.5 m high) that these 47 mm lower the pretension by 0.22 % (measured at
    rest; the reference gives -0.26 % for a fairlead 47 mm lower); 40, 20, 10 and 5 m elements give
    288.5, 288.5, 288.3 and 288.4 kN of H at rest (the continuous line: 289.2 kN)."""
    ref = Spread()
    pf = platform("dem")
    dem = pf.groups[0].lines
    assert dem.settled
    np.testing.assert_allclose(dem.fairlead_tensions(), PRETENSION, rtol=3e-3)
    for surge in (2.0, 5.0, 10.0):
        move(pf, surge)
        forces, _, tension = ref.wrench(surge=surge)
        pulls = np.abs(forces[:, 0]).sum()
        assert -pf.mooring_force[0, 0] == pytest.approx(-forces[:, 0].sum(), abs=5e-3 * pulls)
        assert dem.fairlead_tensions().max() == pytest.approx(tension.max(), rel=3e-3)


def reference_period(mass: float, amplitude: float) -> tuple[float, float]:
    """(linearised surge period 2 pi sqrt(M / K11) with pure translation [s], the period of the
    reference at ``amplitude`` [m] with the hull pitching as it surges [s]): K_eff = K11 - K15 K51 /
    K55 from the lines' stiffness (central differences, 1 mm and 1 mrad) and the hull's
    hydrostatic pitch stiffness; the hardening of the curve at the amplitude from the energy
    integral of the odd polynomial fitted to the pure-surge curve (0-1.2 m, residual ~0.01 N),
    T(a) / T(0) = (4 / T(0)) int_0^a dx / sqrt(2 (U(a) - U(x)) / M)."""
    ref, h = Spread(), 1.0e-3
    (fp, mp, _), (fm, mm, _) = ref.wrench(surge=h), ref.wrench(surge=-h)
    k11, k51 = -(fp[:, 0].sum() - fm[:, 0].sum()) / (2 * h), -(mp[1] - mm[1]) / (2 * h)
    (fp, mp, _), (fm, mm, _) = ref.wrench(pitch=h), ref.wrench(pitch=-h)
    k15 = -(fp[:, 0].sum() - fm[:, 0].sum()) / (2 * h)
    k55 = -(mp[1] - mm[1]) / (2 * h) + hull_pitch_stiffness()
    k_eff = k11 - k15 * k51 / k55
    x = np.linspace(0.0, 1.2, 13)
    basis = np.column_stack([x, x ** 3, x ** 5, x ** 7])
    c = np.linalg.lstsq(basis, [ref.restoring(v) for v in x], rcond=None)[0]

    def energy(v):
        return c[0] * v ** 2 / 2 + c[1] * v ** 4 / 4 + c[2] * v ** 6 / 6 + c[3] * v ** 8 / 8

    t, wq = np.polynomial.legendre.leggauss(200)
    theta, wq = (t + 1) * math.pi / 4, wq * math.pi / 4  # x = a sin(theta), theta in (0, pi/2)
    xa = amplitude * np.sin(theta)
    period_a = 4.0 * float(np.sum(wq * amplitude * np.cos(theta) / np.sqrt(2.0 * (energy(amplitude) - energy(xa)))))
    hardening = period_a / (2.0 * math.pi / math.sqrt(c[0]))
    return 2.0 * math.pi * math.sqrt(mass / k11), 2.0 * math.pi * math.sqrt(mass / k_eff) * hardening


@pytest.mark.parametrize("model,tol", [("quasi_static", 3e-3), ("dem", 2e-2)])
def test_surge_free_decay_period(model, tol):
    """The hull released from 1 m of surge (lines at rest there), body steps of 0.1 s (its heave and
    pitch periods are ~9.6 s and ~8.5 s): the period between the first two down-crossings of the
    equilibrium is the reference's at that amplitude (64.20 s: 64.64 s linearised with the pitch
    coupling, 0.69 % shorter for the curve's hardening at 1 m) within ``tol``, and the linearised
    pure-surge 2 pi sqrt((M + A11) / K) = 64.39 s within tol + 0.5 %.
    quasi_static, 0.3 %: the body's quadratic damping lengthens the period by < 0.01 %, the
    amplitude's decay to 0.97 m in the cycle shortens the hardening by 0.03 %, the 0.1 s step's
    phase error is ~1e-5; measured 64.23 s (+0.05 %).
    dem, 2 %: the lines' own mass (12 x 31 t, ~0.5 % of M + A11) and added mass lengthen the
    period by ~0.3 %, their seabed friction (mu = 0.5 on the 626 m grounded, regularised below
    1 cm/s) stiffens the slow oscillation, their drag and dashpots damp it (the amplitude falls to
    0.74 m in one cycle); measured 63.81 s (-0.6 %; 64.60 s, +0.6 %, without seabed friction)."""
    pf = platform(model)
    body = pf.bodies[0]
    move(pf, 1.0)
    mass = body.mass + body.added_mass[0]
    dt, times, surge = 0.1, [0.0], [body.x[0]]
    for _ in range(850):  # 85 s: a quarter period to the first down-crossing, then one period
        pf.kick(0.5 * dt)
        pf.drift(dt)
        pf.loads()
        pf.kick(0.5 * dt)
        times.append(pf.time)
        surge.append(body.x[0])
    t, x = np.array(times), np.array(surge)
    k = np.nonzero((x[:-1] > 0.0) & (x[1:] <= 0.0))[0]
    crossings = t[k] + (t[k + 1] - t[k]) * x[k] / (x[k] - x[k + 1])
    assert len(crossings) >= 2
    measured = crossings[1] - crossings[0]
    linear, at_amplitude = reference_period(mass, 1.0)
    assert linear == pytest.approx(64.39, abs=0.01)
    assert at_amplitude == pytest.approx(64.20, abs=0.02)
    assert measured == pytest.approx(at_amplitude, rel=tol)
    assert measured == pytest.approx(linear, rel=tol + 5e-3)
