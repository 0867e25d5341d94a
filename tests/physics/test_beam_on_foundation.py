"""A floating strip with a vertical point load at a free edge settles to the semi-infinite beam
solution, Eqs. 5-1..5-8 of 004_4e604f4929f28a45.txt (Section 5.1):

    w(x) = P exp(-beta x) cos(beta x) / (2 beta^3 EI) = (2 P beta / k) exp(-beta x) cos(beta x),
    beta = (k / (4 EI))^(1/4).

The reference is built here from the bond springs and the geometry, not from pice's calibration
(docs/bond_calibration.md, sections 2 and 3):

* EI of an N-row single-layer hexagonal strip bending along x. Per metre of strip, each of the N rows
  has one x-bond per d, bent by kappa d: bending spring k_b -> N k_b d. Each of the N - 1 gaps has
  two diagonal bonds per d at +-60 deg, whose relative rotation kappa d cos(phi) splits into bending
  kappa d cos^2(phi) (spring k_b) and twist kappa d cos(phi) sin(phi) (spring k_t); letting each gap
  relax its anticlastic rotation gives 2 k_b k_t / (3 k_b + k_t) d per gap:
      EI = d [N k_b + (N - 1) 2 k_b k_t / (3 k_b + k_t)]   ( = k_b d (1.5 N - 0.5) when k_t = k_b).
  The job has nu = 0, i.e. k_t = k_b: no anticlastic coupling, and the formula is exact.
* Foundation: a sphere of radius r floating at draft h has the waterplane A = pi h (2 r - h); with
  N / d elements per metre, k = (N / d) rho_w g A.

Waterplane nonlinearity: dA/dh / A = 2 (r - h) / (h (2 r - h)) = -3.8 /m at h = 0.80 m, so a 2.1 mm
deflection changes the local buoyancy stiffness by ~0.4 % at the load (secant: half of 0.8 %), and
w(0) by ~0.2 % (a +-500 N pair of runs gives -1.83 % / -2.24 % against -2.02 % at 50 N).

Discrete edge: each loaded element's waterplane acts around its centre, half of it ahead of the
load (x < 0), where the continuous beam of Eq. 5-7 has nothing. That is an extra spring
K_e = n_loaded * rho_w g A / 2 at the load point, in parallel with the beam's end stiffness
k / (2 beta): w(0) = P / (k / (2 beta) + K_e), a relative (2/3) beta d / (1 + (2/3) beta d) below
Eq. 5-7 for this strip (the third row starts half an element further in). The job's 1/beta = 32 m
makes that 2.1 %, inside the 3 % the issue asks for; the test checks this finer prediction as well.

Measured (this job, one core): w(0) 1.8 % below Eq. 5-7 (0.2 % above the edge-corrected value),
first zero 0.03 m from pi / (2 beta) = 50 m; ~12 s.
"""

import math

import numpy as np
from scenes import JOBS

from pice.job import load_job
from pice.scenes.level_ice import rest_elevation
from pice.simulation import Simulation

JOB = JOBS / "beam_on_foundation.toml"


def _lattice(x):
    """Rows (sorted y values) and element spacing d of a single-layer strip from its centres."""
    ys = np.unique(np.round(x[:, 1], 9))
    row0 = np.sort(x[np.isclose(x[:, 1], ys[0]), 0])
    d = float(np.median(np.diff(row0)))
    return ys, d


def test_strip_settles_to_semi_infinite_beam():
    job = load_job(JOB)
    sim = Simulation(job)
    p = sim.p
    n = p.nlocal
    water, g = job.water, job.gravity

    # the sheet starts exactly at rest: every centre at the Archimedes height of one element
    r = float(p.radius[0])
    z_rest = rest_elevation(mass=float(p.mass[0]), radius=r, cell_area=0.0, half_height=r,
                            rho_w=water.density, level=water.level)
    x0 = p.x[:n].copy()
    assert np.allclose(x0[:, 2], z_rest, atol=1e-9)
    gid0 = p.gid[:n].copy()

    # --- reference from the bond springs and the geometry -------------------------------------
    ys, d = _lattice(x0)
    n_rows = len(ys)
    assert n_rows == 3
    kb, kt = sim.bond.kb, sim.bond.kt
    assert math.isclose(kt, kb, rel_tol=1e-12), "nu = 0 must give k_t = k_b (no anticlastic coupling)"
    EI = d * (n_rows * kb + (n_rows - 1) * 2.0 * kb * kt / (3.0 * kb + kt))
    assert math.isclose(EI, kb * d * (1.5 * n_rows - 0.5), rel_tol=1e-12)
    h = water.level - (z_rest - r)                      # rest draft of a sphere
    a_wp = math.pi * h * (2.0 * r - h)                  # its waterplane area
    k = n_rows / d * water.density * g * a_wp           # foundation modulus per metre of strip [N/m^2]
    beta = (k / (4.0 * EI)) ** 0.25

    loaded = p.ext_force[:n, 2] != 0.0
    P = -float(p.ext_force[:n, 2].sum())                # downward load [N]
    x_load = float(x0[loaded, 0].mean())
    assert P > 0 and np.allclose(x0[loaded, 0], x_load)
    length = x0[:, 0].max() - x_load
    assert beta * length >= 4.9, "the strip must be long enough to be semi-infinite"

    # --- settle ---------------------------------------------------------------------------------
    sim.advance(sim.total_steps)
    # settled: no element's deflection changes by more than 1e-4 of w(0) per second
    assert np.abs(p.v[:n, 2]).max() < 1e-4 * (2.0 * P * beta / k)
    order = np.argsort(p.gid[:n])
    assert np.array_equal(p.gid[:n][order], gid0[np.argsort(gid0)])
    z = p.x[:n][order, 2]
    xs = x0[np.argsort(gid0)]
    w = z_rest - z                                      # deflection, downward positive [m]

    # Eq. 5-7 at the load: w(0) = P / (2 beta^3 EI) = 2 P beta / k
    w0_eq57 = P / (2.0 * beta ** 3 * EI)
    w0 = float(w[loaded[np.argsort(gid0)]].mean())
    err = w0 / w0_eq57 - 1.0
    print(f"\n1/beta = {1 / beta:.2f} m, EI = {EI:.4g} N m^2, k = {k:.5g} N/m^2, P = {P:g} N")
    print(f"w(0): DEM {w0 * 1e3:.4f} mm, Eq. 5-7 {w0_eq57 * 1e3:.4f} mm, error {100 * err:+.2f} %")
    assert abs(err) < 0.03

    # finer: the discrete edge's extra half-waterplane per loaded element (module docstring)
    k_edge = np.count_nonzero(loaded) * 0.5 * water.density * g * a_wp
    w0_edge = P / (k / (2.0 * beta) + k_edge)
    print(f"      edge-corrected {w0_edge * 1e3:.4f} mm, DEM vs that {100 * (w0 / w0_edge - 1):+.2f} %")
    assert abs(w0 / w0_edge - 1.0) < 0.01

    # first zero of the deflection along the loaded row: beta x = pi / 2
    row = np.isclose(xs[:, 1], xs[loaded[np.argsort(gid0)]][0, 1])
    xr = xs[row, 0] - x_load
    wr = w[row]
    o = np.argsort(xr)
    xr, wr = xr[o], wr[o]
    i = int(np.nonzero((wr[:-1] > 0) & (wr[1:] <= 0))[0][0])
    x_zero = xr[i] + wr[i] * (xr[i + 1] - xr[i]) / (wr[i] - wr[i + 1])
    x_zero_eq57 = math.pi / (2.0 * beta)
    print(f"first zero: DEM {x_zero:.3f} m, Eq. 5-7 {x_zero_eq57:.3f} m (element {d:g} m)")
    assert abs(x_zero - x_zero_eq57) < d

    # and the whole shape near the load follows Eq. 5-7 scaled to the measured w(0)
    near = xr < 2.0 * x_zero_eq57
    shape = w0 * np.exp(-beta * xr[near]) * np.cos(beta * xr[near])
    assert np.abs(wr[near] - shape).max() < 0.01 * w0
