"""Specimens of the virtual ice lab: jobs cut from the user's job, and the elements each test holds.

Every specimen is a piece of the user's sheet: the same [ice] (density, thickness, element size and
volume, E, nu, strengths), [bond], [contact] and [crushing], with no water, no push, no walls or
bodies and gravity 0, built by the real scene builder (``pice.scenes.level_ice``) and run by
``pice.simulation.Simulation`` on one rank.

Geometry. The single layer is a triangular lattice: rows along x spaced sqrt(3)/2 d apart, even rows
with centres at x = (k + 1/2) d, odd rows shifted by d/2. Lines across the sheet (platens,
supports, load and tip lines) are made of even-row elements only: those sit on one straight line
x = const, while a line taking one element from every row would be jagged by d/2, and two held
elements of neighbouring rows at different x clamp the beam's rotation through the shear springs
of the diagonal bond between them (it doubles a three-point beam's stiffness at d = 1 m). The odd
rows end d/2 inside each such line and are carried by their diagonal bonds.

Sizes are physical: a span of 20 m is 40, 20 or 10 element spacings at d = 0.5, 1 or 2 m. A width
is realised as a whole number of rows N, each standing for the strip sqrt(3)/2 d wide it carries,
so b = N sqrt(3)/2 d; the default 6 (sqrt(3)/2) h gives N = 12, 6, 3 rows and the same b = 5.196 m
at those three element sizes for h = 1 m.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

import numpy as np

ROW = math.sqrt(3.0) / 2.0  # row spacing / d
_EPS = 1e-6                 # [m] tolerance on lattice coordinates


@dataclass(frozen=True)
class Size:
    """A specimen dimension as the user gives it: ``value`` in metres ("m"), thicknesses ("h") or
    element spacings ("d")."""

    value: float
    unit: str = "m"

    def metres(self, *, thickness: float, element_size: float) -> float:
        """The dimension in metres for ice of ``thickness`` h [m] and element size d [m]."""
        return self.value * {"m": 1.0, "h": thickness, "d": element_size}[self.unit]

    def __str__(self) -> str:
        return f"{self.value:g}{self.unit if self.unit != 'm' else ' m'}"


def parse_size(text: str) -> Size:
    """``"20h"`` (20 thicknesses), ``"12d"`` (12 element spacings), ``"15"`` or ``"15m"`` (metres)."""
    m = re.fullmatch(r"\s*([0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?)\s*(m|h|d)?\s*", str(text))
    if m is None or float(m.group(1)) <= 0.0:
        raise ValueError(f"{text!r}: a positive length in metres (15 or 15m), thicknesses (20h) or "
                         "element spacings (12d)")
    return Size(float(m.group(1)), m.group(2) or "m")


def rows_for(width: float, d: float, minimum: int = 2) -> int:
    """Rows N whose strips (sqrt(3)/2 d each) make the width [m] closest to ``width``."""
    return max(minimum, int(round(width / (ROW * d))))


def specimen_job(job, *, element_size: float, columns: int, rows: int, name: str):
    """The job of a specimen: ``columns`` elements in the even rows (length columns d), ``rows``
    rows, the user's [ice], [bond], [contact] and [crushing], no water, gravity 0. Raises JobError (one line
    per problem) if the user's sheet cannot be built at this element size."""
    from ..job import parse_job

    d = element_size
    ice = job.ice.model_dump(exclude_none=True)
    ice.pop("push", None)
    ice.update(element_diameter=d, length=columns * d, width=d + (rows - 0.5) * ROW * d,
               origin=(0.0, 0.0), velocity=(0.0, 0.0))
    data = {"run": {"name": name, "duration": 1.0, "dt": "auto", "dt_safety": job.run.dt_safety,
                    "check_every": job.run.check_every},
            "gravity": 0.0, "ice": ice,
            "bond": job.bond.model_dump(exclude_none=True),
            "contact": job.contact.model_dump(exclude_none=True)}
    crushing = getattr(job, "crushing", None)  # the contacts' crushing law is the ice's too
    if crushing is not None:
        data["crushing"] = crushing.model_dump(exclude_none=True)
    return parse_job(data, source=f"{job.source or '<job>'} (lab, element size {d:g} m)")


@dataclass
class Specimen:
    """A specimen ready to load: its simulation, initial positions [m] and the held element sets.

    ``sets`` maps a name to local indices; ``lines`` holds the x [m] of its straight lines
    (supports, load, clamp face, tip, platens); ``width`` b [m] = rows sqrt(3)/2 d; ``areal_mass``
    [kg/m^2] is the specimen's mass per unit area of sheet.
    """

    name: str
    sim: object
    d: float
    thickness: float
    rows: int
    width: float
    length: float
    x0: np.ndarray
    sets: dict = field(default_factory=dict)
    lines: dict = field(default_factory=dict)
    areal_mass: float = 0.0
    held_rotation: tuple = ()  # sets whose rotation is held too (zeroed every step by the loading loop)

    @property
    def elements(self) -> int:
        return int(self.sim.p.nlocal)

    def describe(self) -> dict:
        """The specimen's facts for the report: sizes [m], element and row counts."""
        return {"length": self.length, "width": self.width, "thickness": self.thickness, "rows": self.rows,
                "elements": self.elements, "element_size": self.d, "dt": self.sim.dt,
                "lines": {k: float(v) for k, v in self.lines.items()}}


def _build(job, *, d: float, columns: int, rows: int, name: str) -> tuple:
    from ..parallel.comm import SerialComm
    from ..simulation import Simulation

    sjob = specimen_job(job, element_size=d, columns=columns, rows=rows, name=name)
    sim = Simulation(sjob, comm=SerialComm())
    p = sim.p
    if not np.array_equal(p.gid[:p.nlocal], np.arange(p.nlocal)):  # one rank keeps the builder's order
        raise RuntimeError("lab: the specimen's elements were reordered")
    x0 = p.x[:p.nlocal].copy()
    even = np.abs(np.mod(x0[:, 0] / d - 0.5 + 0.25, 1.0) - 0.25) < _EPS / d  # centres at (k + 1/2) d
    return sim, x0, even


def _line(x0, even, x: float) -> np.ndarray:
    """Even-row elements on the line x [m] (every layer of a multi-layer sheet)."""
    return np.nonzero(even & (np.abs(x0[:, 0] - x) < _EPS))[0]


def _specimen(name, sim, x0, *, d, h, rows, length) -> Specimen:
    p = sim.p
    area = length * rows * ROW * d
    return Specimen(name=name, sim=sim, d=d, thickness=h, rows=rows, width=rows * ROW * d, length=length,
                    x0=x0, areal_mass=float(p.mass[:p.nlocal].sum()) / area)


def compression_block(job, *, d: float, length: float, width: float) -> Specimen:
    """A block between two platens (even-row elements of the first and last column, held in x,
    free in y: frictionless). Every element is held in z (the platens' guides keep it plane).
    ``length`` [m] is the distance between the platens, rounded to whole spacings (>= 4)."""
    h = job.ice.thickness
    n = max(4, int(round(length / d)))
    rows = rows_for(width, d)
    sim, x0, even = _build(job, d=d, columns=n + 1, rows=rows, name="compression")
    s = _specimen("compression", sim, x0, d=d, h=h, rows=rows, length=n * d)
    s.lines = {"platen_fixed": 0.5 * d, "platen_moving": (n + 0.5) * d}
    s.sets = {"fixed": np.nonzero(x0[:, 0] < d + _EPS)[0], "moving": np.nonzero(x0[:, 0] > n * d - _EPS)[0]}
    p = sim.p
    p.fix_mask[:p.nlocal, 2] = True
    p.fix_velocity[:p.nlocal, 2] = 0.0
    for key in ("fixed", "moving"):
        p.fix_mask[s.sets[key], 0] = True
        p.fix_velocity[s.sets[key], 0] = 0.0
    return s


def three_point_beam(job, *, d: float, span: float, width: float) -> Specimen:
    """A beam of ``span`` [m] (rounded to an even number of spacings, >= 4) on two line supports
    (held in z, free to rotate and slide: simply supported) with the load line at midspan."""
    h = job.ice.thickness
    n = max(4, 2 * int(round(span / (2.0 * d))))
    rows = rows_for(width, d)
    sim, x0, even = _build(job, d=d, columns=n + 1, rows=rows, name="three_point")
    s = _specimen("three_point", sim, x0, d=d, h=h, rows=rows, length=n * d)
    s.lines = {"support_left": 0.5 * d, "load": (0.5 + n / 2) * d, "support_right": (n + 0.5) * d}
    s.sets = {"supports": np.concatenate([_line(x0, even, s.lines["support_left"]),
                                          _line(x0, even, s.lines["support_right"])]),
              "load": _line(x0, even, s.lines["load"])}
    p = sim.p
    for key in ("supports", "load"):
        p.fix_mask[s.sets[key], 2] = True
        p.fix_velocity[s.sets[key], 2] = 0.0
    return s


def cantilever(job, *, d: float, length: float, width: float, root: float) -> Specimen:
    """A cantilever: a root block of length ``root`` [m] (>= 2 columns) clamped (its elements held in
    x, y, z and in rotation) and a free part of ``length`` [m] from the clamp face to the tip line.

    The clamp face is the edge of the last held even-row element's cell (its centre + d/2); the
    first free bond of every even row sits on it and carries the face moment F L. The odd rows lie
    d/2 off the even ones, so their first free bond cannot sit on the face too: they are held up
    to the face (their last held centre on it) and their first free bond lies d/2 past it. The free
    length (face to tip) is (n - 1/2) d, the nearest to ``length`` (the longer on a tie).
    The rotation of the root elements is held by the loading loop (``held_rotation``), which zeroes
    their spin and torque every step: a clamp that only held positions would let the held elements
    turn against the small shear springs of their bonds (the tip formula then gives 0.73 EI at d = 1 m).
    """
    h = job.ice.thickness
    m = max(2, int(math.ceil(root / d - 1e-9)))                # held even-row columns
    n = max(2, int(math.floor(length / d + 1.0)))              # face -> tip = (n - 1/2) d
    rows = rows_for(width, d)
    face, tip = m * d, (m + n - 0.5) * d
    sim, x0, even = _build(job, d=d, columns=m + n, rows=rows, name="cantilever")
    s = _specimen("cantilever", sim, x0, d=d, h=h, rows=rows, length=tip - face)
    s.lines = {"clamp_face": face, "tip": tip}
    held_to = np.where(even, face - 0.5 * d, face)
    s.sets = {"root": np.nonzero(x0[:, 0] < held_to + _EPS)[0], "tip": _line(x0, even, tip)}
    s.held_rotation = ("root",)
    p = sim.p
    p.fix_mask[s.sets["root"], :] = True
    p.fix_velocity[s.sets["root"], :] = 0.0
    p.fix_mask[s.sets["tip"], 2] = True
    p.fix_velocity[s.sets["tip"], 2] = 0.0
    return s
