"""The virtual ice lab (``pice lab JOB``): specimens cut from a job's sheet, tested as an ice lab would.

For each element size (the job's, or several given) it builds three specimens from the job's [ice],
[bond], [contact] and [crushing] (pice/lab/specimens.py), loads them quasi-statically with the real solver on
one rank (pice/lab/loading.py) and measures (pice/lab/experiments.py):

* uniaxial compression between platens: E [Pa], nu, compressive strength sigma_c [Pa];
* three-point bending: flexural rigidity per width EI/b [N m] and flexural strength sigma_f [Pa];
* a cantilever (the in-situ test): EI/b and sigma_f at the root.

``run_lab`` returns everything as a JSON-ready dict; pice/lab/report.py prints it beside the
intended values (ice.youngs_modulus, ice.flexural_strength, ice.compressive_strength) and Zhu &
Ji's Eqs. 6-7. docs/lab.md describes the experiments.
"""

from __future__ import annotations

import logging
from dataclasses import asdict, dataclass

from .specimens import Size, specimen_job

TESTS = ("compression", "three_point", "cantilever")
log = logging.getLogger("pice")


@dataclass(frozen=True)
class LabSizes:
    """Specimen sizes (pice.lab.specimens.Size: metres, thicknesses h or element spacings d)."""

    block_length: Size = Size(10.0, "h")       # compression: platen to platen
    block_width: Size = Size(5.2, "h")
    beam_span: Size = Size(20.0, "h")          # three-point: support to support
    beam_width: Size = Size(5.2, "h")          # also the cantilever's width
    cantilever_length: Size = Size(10.0, "h")  # clamp face to tip line
    clamp_length: Size = Size(2.0, "h")        # the cantilever's clamped root block


QUICK_SIZES = LabSizes(block_length=Size(6.0, "h"), beam_span=Size(10.0, "h"), cantilever_length=Size(6.0, "h"))
PERIODS, QUICK_PERIODS = 5.0, 3.0  # fundamental periods of loading to the intended strength
CAP = 50.0                         # no break up to CAP x the displacement of the intended strength: stop


def run_lab(job, *, element_sizes=None, sizes: LabSizes | None = None, periods: float | None = None,
            tests=TESTS, quick: bool = False, cap: float = CAP) -> dict:
    """Run the lab on ``job`` at each element size [m] (default: the job's ice.element_diameter).

    ``periods``: loading time to the intended strength in fundamental periods of the specimen
    (default 5; 3 with ``quick``); ``quick``: smaller specimens (QUICK_SIZES) unless ``sizes`` is
    given. Raises JobError when the job's sheet cannot be built at an element size. Returns a
    JSON-ready dict (pice/lab/report.py prints it).
    """
    from . import experiments

    sizes = sizes or (QUICK_SIZES if quick else LabSizes())
    periods = periods or (QUICK_PERIODS if quick else PERIODS)
    ice = job.ice
    h = ice.thickness
    out = {"job": job.source, "thickness": h, "poissons_ratio": ice.poissons_ratio, "periods": periods,
           "quick": quick, "sizes": {k: str(v) for k, v in asdict(sizes).items()},
           "intended": intended(job), "element_sizes": []}
    element_sizes = list(element_sizes or [ice.element_diameter])
    for d in element_sizes:  # every element size must make a sheet before anything runs
        specimen_job(job, element_size=d, columns=4, rows=2, name="check")
    for d in element_sizes:
        def m(size: Size) -> float:
            return size.metres(thickness=h, element_size=d)

        entry = {"element_size": d}
        for test in tests:
            log.info("lab: d = %g m: %s", d, test.replace("_", "-"))
            if test == "compression":
                r = experiments.compression(job, d=d, length=m(sizes.block_length), width=m(sizes.block_width),
                                            periods=periods, cap=cap)
            elif test == "three_point":
                r = experiments.three_point(job, d=d, span=m(sizes.beam_span), width=m(sizes.beam_width),
                                            periods=periods, cap=cap)
            elif test == "cantilever":
                r = experiments.cantilever_test(job, d=d, length=m(sizes.cantilever_length),
                                                width=m(sizes.beam_width), root=m(sizes.clamp_length),
                                                periods=periods, cap=cap)
            else:
                raise ValueError(f"unknown lab test {test!r}: one of {', '.join(TESTS)}")
            bond = r.pop("bond")
            entry.setdefault("bond", bond)
            entry[test] = r
        entry["zhu_ji"] = zhu_ji(job, d, entry.get("bond"))
        out["element_sizes"].append(entry)
    return out


def intended(job) -> dict:
    """The properties the job asks for [Pa, N m]: E, nu, sigma_f, sigma_c, and the flexural rigidity
    per width of a free-sided beam, E h^3 / 12, and of a plate, D = E h^3 / (12 (1 - nu^2))."""
    ice = job.ice
    E, nu, h = ice.youngs_modulus, ice.poissons_ratio, ice.thickness
    return {"youngs_modulus": E, "poissons_ratio": nu, "flexural_strength": ice.flexural_strength,
            "compressive_strength": ice.compressive_strength,
            "beam_rigidity": E * h ** 3 / 12.0 if E is not None else None,
            "plate_rigidity": E * h ** 3 / (12.0 * (1.0 - nu * nu)) if E is not None else None}


def _eqs():
    try:  # the calibration's home may move between pice/physics/bond.py and bond_calibration.py
        from ..physics.bond_calibration import eq6_bond_strength, eq7_bond_friction
    except ImportError:
        from ..physics.bond import eq6_bond_strength, eq7_bond_friction
    return eq6_bond_strength, eq7_bond_friction


def zhu_ji(job, d: float, bond: dict | None) -> dict:
    """Zhu & Ji (2022) Eqs. 6-7 for this sheet at element size d [m], beside the bond's own values:
    Eq. 6 bond strength [Pa] from sigma_f and h/d, Eq. 7 friction from sigma_c / sigma_f."""
    eq6, eq7 = _eqs()
    ice = job.ice
    out = {"thickness_over_size": ice.thickness / d, "eq6_bond_strength": None, "eq7_friction": None,
           "bond_normal_strength": bond and bond["normal_strength"], "bond_friction": bond and bond["friction"]}
    if ice.flexural_strength is not None:
        out["eq6_bond_strength"] = eq6(flexural_strength=ice.flexural_strength, thickness=ice.thickness,
                                       element_diameter=d)
        if ice.compressive_strength is not None:
            out["eq7_friction"] = eq7(compressive_strength=ice.compressive_strength,
                                      flexural_strength=ice.flexural_strength)
    return out


__all__ = ["LabSizes", "QUICK_SIZES", "TESTS", "Size", "run_lab", "intended", "zhu_ji"]
