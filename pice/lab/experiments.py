"""The three experiments of the virtual ice lab, each on a specimen of pice/lab/specimens.py, loaded
quasi-statically by pice/lab/loading.py. Every result is in SI units (Pa, N m, m, s).

* **Uniaxial compression** between frictionless platens: stress sigma = F / (b h) [Pa] (F the mean
  of the two platens' reactions, b = N sqrt(3)/2 d the rows' width, h the thickness); strain from an
  extensometer (the mean x of two cross-sections at 1/4 and 3/4 of the length), lateral strain from
  the top and bottom rows of the middle half. E [Pa] and nu are the least-squares slopes of stress
  and lateral strain against strain over the intact record (10-90 % of the stress at the first
  break, after the smooth start); sigma_c is the peak stress, once the stress has dropped to half
  of it (else "no peak" up to the displacement cap).
* **Three-point bending**: simply supported span L, line load F at midspan. Flexural rigidity per
  width EI/b [N m] two ways: (a) from the load-point stiffness k = dF/d(delta), EI = k L^3 / 48:
  the apparent value, which includes the transverse shear compliance of the bonds; (b) from the
  rotations of the elements (inclinometers on every cross-section): EI dpsi/dx = -M(x) holds for the
  section rotation psi whatever the shear strain, and M(x) is known from statics, so a fit of psi
  against the integral of M gives EI, the bending rigidity proper. sigma_f = 3 F L / (2 b h^2) with
  F the largest load before the first broken bond.
* **Cantilever** (the in-situ test): clamped root block, tip line load F, free length L from the
  clamp face. EI/b from the tip deflection, F L^3 / (3 EI) (the in-situ formula: includes shear and
  the clamp's compliance), and from the rotations as above (M = F (x_tip - x)); sigma_f =
  6 F L / (b h^2) at the first broken bond (at the root).
"""

from __future__ import annotations

import math

import numpy as np

from .loading import Program, load_specimen
from .specimens import cantilever, compression_block, three_point_beam

FIT_WINDOW = (0.1, 0.9)      # the slopes use the record between these fractions of the load at the first break
PROFILE_WINDOW = (0.2, 0.9)  # the rotation fits use the snapshots between these fractions of it
PEAK_DROP = 0.5              # compression: the peak is passed once the stress has dropped to this fraction of it
BLOCK_SLOWER, BLOCK_RAMP = 4.0, 6.0  # the block's axial period is short (9 ms for 10 m of 5 GPa ice) but its wave
                                     # and lateral modes ring after the start: 4x more periods, a 6-period start
SNAPSHOTS = 40               # positions and rotations recorded per reference loading time (tau)


def references(job, bond) -> dict:
    """Stiffness and strengths the loading rate is scaled on: E [Pa] (the job's, else the lattice's
    from the springs), sigma_f and sigma_c [Pa] (the job's, else from the bond strength)."""
    ice = job.ice
    h, nu = ice.thickness, ice.poissons_ratio
    E = ice.youngs_modulus
    if E is None:  # springs given directly: the triangular lattice of k_n, k_s (Griffiths & Mustoe 2001)
        E = 2.0 * math.sqrt(3.0) * bond.kn * (bond.kn + bond.ks) / (3.0 * bond.kn + bond.ks) / h
    sf = ice.flexural_strength
    if sf is None:
        sf = bond.normal_strength * (1.0 - nu) if math.isfinite(bond.normal_strength) else 1e-4 * E
    sc = ice.compressive_strength if ice.compressive_strength is not None else 5.0 * sf
    return {"E": E, "sigma_f": sf, "sigma_c": sc}


def bond_facts(bond) -> dict:
    """The bond's springs [N/m, N m/rad] and strengths [Pa] as the specimen's simulation has them
    (physics.bond.BondParams; an infinite strength is None)."""
    out = {}
    for k in ("kn", "ks", "kb", "kt", "normal_strength", "shear_strength", "friction", "compressive_strength",
              "shear_law", "calibration"):
        v = getattr(bond, k, None)
        out[k] = None if isinstance(v, float) and not math.isfinite(v) else v
    return out


def _slope(x: np.ndarray, y: np.ndarray) -> float:
    """Least-squares slope of y against x."""
    if len(x) < 3:
        return math.nan
    return float(np.polyfit(x, y, 1)[0])


def _window(force: np.ndarray, time: np.ndarray, *, after: float, upto: int, lo: float, hi: float) -> np.ndarray:
    """The intact, elastic part of the record for the initial slope: indices before ``upto`` (the
    first break), after time ``after`` [s] (the smooth start), with lo <= force / F(upto - 1) <= hi;
    if fewer than 5 qualify, every index after ``after`` before ``upto``."""
    f, t = force[:upto], time[:upto]
    top = f[-1] if f.size else 0.0
    i = np.arange(len(f))
    w = i[(t >= after) & (f >= lo * top) & (f <= hi * top)]
    return w if len(w) >= 5 else i[t >= after]


def _stop_at_first_break(cap: float):
    def stop(run, i):
        if run.first_break is not None:
            return "first break"
        if run.delta[i] >= cap:
            return "no break"
        return ""
    return stop


def _peak_before_break(force: np.ndarray, first_break) -> tuple[int, float]:
    """(index, value) of the largest force before the first broken bond (or over the record)."""
    upto = first_break if first_break is not None else len(force)
    k = int(np.argmax(force[:max(upto, 1)]))
    return k, float(force[k])


def _modes(modes: dict) -> dict:
    """Failure-mode counts by their names (kernels.bonds.FAILURE_MODES)."""
    from ..kernels.bonds import FAILURE_MODES

    return {FAILURE_MODES.get(m, str(m)): n for m, n in sorted(modes.items())}


def compression(job, *, d: float, length: float, width: float, periods: float, cap: float) -> dict:
    """Uniaxial compression between frictionless platens (module docstring). Returns the facts [SI]."""
    spec = compression_block(job, d=d, length=length, width=width)
    ref = references(job, spec.sim.bond)
    h, L, b, x0 = spec.thickness, spec.length, spec.width, spec.x0
    E = ref["E"]
    period = 2.0 * L / math.sqrt(E * h / spec.areal_mass)   # fixed-fixed bar
    delta_ref = ref["sigma_c"] * L / E
    program = Program.for_specimen(reference=delta_ref, period=period, periods=BLOCK_SLOWER * periods,
                                   ramp_periods=BLOCK_RAMP)
    xa, xb = spec.lines["platen_fixed"] + 0.25 * L, spec.lines["platen_fixed"] + 0.75 * L
    sec_a = np.nonzero(np.abs(x0[:, 0] - xa) <= 0.5 * d + 1e-6)[0]
    sec_b = np.nonzero(np.abs(x0[:, 0] - xb) <= 0.5 * d + 1e-6)[0]
    mid = np.abs(x0[:, 0] - 0.5 * (xa + xb)) <= 0.25 * L + 1e-6
    top = np.nonzero(mid & (x0[:, 1] > x0[:, 1].max() - 1e-6))[0]
    bottom = np.nonzero(mid & (x0[:, 1] < x0[:, 1].min() + 1e-6))[0]
    gauges = {"gauge": lambda p: float(p.x[sec_b, 0].mean() - p.x[sec_a, 0].mean()),
              "lateral": lambda p: float(p.x[top, 1].mean() - p.x[bottom, 1].mean())}
    g0 = float(x0[sec_b, 0].mean() - x0[sec_a, 0].mean())
    y0 = float(x0[top, 1].mean() - x0[bottom, 1].mean())

    peak = [0.0]

    def stop(run, i):
        f = run.forces["moving"][i]
        peak[0] = max(peak[0], f)
        if run.first_break is not None and f < PEAK_DROP * peak[0]:  # an intact lattice is elastic
            return "past the peak"
        if run.delta[i] >= cap * delta_ref:
            return "no peak" if run.first_break is not None else "no break"
        return ""

    run = load_specimen(spec, driven="moving", axis=0, sign=-1.0, program=program, sets=["fixed", "moving"],
                        stop=stop, gauges=gauges)
    t = run.array("time")
    sigma = 0.5 * (run.array("moving") - run.array("fixed")) / (b * h)
    strain = -(np.asarray(run.gauges["gauge"]) - g0) / g0
    lateral = (np.asarray(run.gauges["lateral"]) - y0) / y0
    k_peak = int(np.argmax(sigma))
    elastic = run.first_break if run.first_break is not None else len(t)
    w = _window(sigma, t, after=program.ramp, upto=elastic, lo=FIT_WINDOW[0], hi=FIT_WINDOW[1])
    E_meas = _slope(strain[w], sigma[w])
    nu_meas = _slope(strain[w], lateral[w])
    broke = run.first_break is not None
    return {"specimen": spec.describe(), "bond": bond_facts(spec.sim.bond),
            "loading": _loading(program, period, run, delta_ref),
            "youngs_modulus": E_meas, "poissons_ratio": nu_meas,
            "compressive_strength": float(sigma[k_peak]) if run.stopped == "past the peak" else None,
            "stress_at_first_break": float(sigma[max(run.first_break - 1, 0)]) if broke else None,
            "largest_stress": float(sigma.max()), "strain_at_peak": float(strain[k_peak]),
            "first_break_modes": _modes(run.first_modes), "failure_modes": _modes(run.modes),
            "broken_bonds": int(run.broken[-1]),
            "inertia": run.inertia(["fixed", "moving"], "moving", np.r_[w, max(elastic - 1, 0)])}


def _loading(program, period, run, delta_ref) -> dict:
    return {"speed": program.speed, "period": period, "ramp": program.ramp, "tau": program.tau,
            "reference_displacement": delta_ref, "steps": run.steps, "duration": run.time[-1] if run.time else 0.0,
            "stopped": run.stopped}


def _rotation_rigidity(spec, run, force, *, moment_integral, free, lo: float, hi: float, peak_index: int) -> tuple:
    """EI [N m^2] from the rotations of the elements (the cross-sections: inclinometers), over the
    snapshots whose load lies between lo and hi of the load at ``peak_index``.

    In a beam with shear, the section rotation psi obeys EI dpsi/dx = -M(x) (deflection downward)
    whatever the shear strain; M(x) = F m(x) is known from statics (the lines' positions), so
    psi(x) = a - (F / EI) G(x) with G = integral of m dx (``moment_integral``, [m^2]): a least-squares
    fit of psi against G over the ``free`` elements gives F / EI. Returns (EI, half-range of the
    snapshots' values)."""
    G = moment_integral(spec.x0[:, 0])[free]
    values = []
    for i, _x, rot in run.snapshots:
        if i > peak_index or not (lo * force[peak_index] <= force[i] <= hi * force[peak_index]):
            continue
        slope = np.polyfit(G, rot[free, 1], 1)[0]
        values.append(force[i] / abs(slope))
    if not values:
        return math.nan, math.nan
    return float(np.median(values)), 0.5 * float(max(values) - min(values))


def three_point(job, *, d: float, span: float, width: float, periods: float, cap: float) -> dict:
    """Three-point bending of a simply supported beam (module docstring). Returns the facts [SI]."""
    spec = three_point_beam(job, d=d, span=span, width=width)
    ref = references(job, spec.sim.bond)
    h, L, b = spec.thickness, spec.length, spec.width
    E = ref["E"]
    omega = (math.pi / L) ** 2 * math.sqrt(E * h ** 3 / 12.0 / spec.areal_mass)
    period = 2.0 * math.pi / omega
    delta_ref = ref["sigma_f"] * L ** 2 / (6.0 * E * h)
    program = Program.for_specimen(reference=delta_ref, period=period, periods=periods)
    run = load_specimen(spec, driven="load", axis=2, sign=-1.0, program=program, sets=["load", "supports"],
                        stop=_stop_at_first_break(cap * delta_ref), snapshot_every=program.tau / SNAPSHOTS)
    t, delta, force = run.array("time"), run.array("delta"), run.array("load")
    k_peak, f_peak = _peak_before_break(force, run.first_break)
    w = _window(force, t, after=program.ramp, upto=k_peak + 1, lo=FIT_WINDOW[0], hi=FIT_WINDOW[1])  # intact
    k = _slope(delta[w], force[w])
    xa, xl, xb = spec.lines["support_left"], spec.lines["load"], spec.lines["support_right"]

    def moment_integral(x):  # m(x) = (x - xa) / 2 left of the load, (xb - x) / 2 right of it [m]
        x = np.clip(x, xa, xb)
        return np.where(x <= xl, (x - xa) ** 2, (xl - xa) ** 2 + (xb - xl) ** 2 - (xb - x) ** 2) / 4.0

    EI, spread = _rotation_rigidity(spec, run, force, moment_integral=moment_integral,
                                    free=np.ones(len(spec.x0), bool), lo=PROFILE_WINDOW[0], hi=PROFILE_WINDOW[1],
                                    peak_index=k_peak)
    broke = run.first_break is not None
    return {"specimen": spec.describe(), "bond": bond_facts(spec.sim.bond),
            "loading": _loading(program, period, run, delta_ref),
            "rigidity_load_point": k * L ** 3 / 48.0 / b, "rigidity_bending": EI / b,
            "rigidity_bending_spread": spread / b,
            "flexural_strength": 1.5 * f_peak * L / (b * h ** 2) if broke else None,
            "largest_stress": 1.5 * f_peak * L / (b * h ** 2), "force_at_first_break": f_peak if broke else None,
            "deflection_at_first_break": float(delta[k_peak]) if broke else None,
            "first_break_modes": _modes(run.first_modes), "failure_modes": _modes(run.modes),
            "broken_bonds": int(run.broken[-1]),
            "inertia": run.inertia(["load", "supports"], "load", np.r_[w, k_peak])}


def cantilever_test(job, *, d: float, length: float, width: float, root: float, periods: float,
                    cap: float) -> dict:
    """The in-situ cantilever (module docstring). Returns the facts [SI]."""
    spec = cantilever(job, d=d, length=length, width=width, root=root)
    ref = references(job, spec.sim.bond)
    h, L, b = spec.thickness, spec.length, spec.width
    E = ref["E"]
    omega = (1.8751 / L) ** 2 * math.sqrt(E * h ** 3 / 12.0 / spec.areal_mass)
    period = 2.0 * math.pi / omega
    delta_ref = 2.0 * ref["sigma_f"] * L ** 2 / (3.0 * E * h)
    program = Program.for_specimen(reference=delta_ref, period=period, periods=periods)
    run = load_specimen(spec, driven="tip", axis=2, sign=-1.0, program=program, sets=["tip", "root"],
                        stop=_stop_at_first_break(cap * delta_ref), snapshot_every=program.tau / SNAPSHOTS)
    t, delta, force = run.array("time"), run.array("delta"), run.array("tip")
    k_peak, f_peak = _peak_before_break(force, run.first_break)
    w = _window(force, t, after=program.ramp, upto=k_peak + 1, lo=FIT_WINDOW[0], hi=FIT_WINDOW[1])  # intact
    k = _slope(delta[w], force[w])
    tip = spec.lines["tip"]

    def moment_integral(x):  # m(x) = tip - x [m]
        return tip * x - 0.5 * x * x

    free = np.ones(len(spec.x0), bool)
    free[spec.sets["root"]] = False
    EI, spread = _rotation_rigidity(spec, run, force, moment_integral=moment_integral, free=free,
                                    lo=PROFILE_WINDOW[0], hi=PROFILE_WINDOW[1], peak_index=k_peak)
    broke = run.first_break is not None
    return {"specimen": spec.describe(), "bond": bond_facts(spec.sim.bond),
            "loading": _loading(program, period, run, delta_ref),
            "rigidity_tip": k * L ** 3 / 3.0 / b, "rigidity_bending": EI / b, "rigidity_bending_spread": spread / b,
            "flexural_strength": 6.0 * f_peak * L / (b * h ** 2) if broke else None,
            "largest_stress": 6.0 * f_peak * L / (b * h ** 2), "force_at_first_break": f_peak if broke else None,
            "deflection_at_first_break": float(delta[k_peak]) if broke else None,
            "first_break_modes": _modes(run.first_modes), "failure_modes": _modes(run.modes),
            "broken_bonds": int(run.broken[-1]),
            "inertia": run.inertia(["tip", "root"], "tip", np.r_[w, k_peak])}
