"""[[bodies]] and [[moorings]]: the floating structures of a job and their mooring lines.

A body is a 6-degree-of-freedom rigid hull (pice/platform/rigid_body.py) owned by rank 0; its hull is
built from parameters or read from a mesh file. A [[moorings]] entry is a spread of lines attached to
one body, either DEM lines (pice/platform/mooring_lines.py) or the quasi-static elastic catenary
(pice/platform/quasi_static.py), each anchor placed by the layout solve for the given pretension.
These are the schema only; pice/platform/ builds and steps them.
"""

from __future__ import annotations

import math
from typing import Literal, Optional, Union

from pydantic import Field, StrictBool, model_validator

from .types import Real, Section, Vec2, Vec3, count, quantity, vector

Vec6 = tuple[Real, Real, Real, Real, Real, Real]
Row7 = tuple[Real, Real, Real, Real, Real, Real, Real]
Moment = quantity("kg m^2")  # a principal moment of inertia, > 0


class HullSpec(Section):
    """[bodies.hull]: the hull surface in the body frame (origin at the centre of gravity).

    "buoy" is the double cone of Cai (2018, seed 004; platform.hulls.buoy_design_profile), keel
    cylinder, lower cone at ``alpha`` up to the widest section of diameter ``d_max``, upper cone to the
    top, placed with its shell's centre at the body origin (the centre of gravity of a thin shell).

    "ship" is the parametric hull of seed 002's Table 1 (platform.ship): a raked wedge bow, a parallel
    midbody and a wedge stern, three convex pieces; the body origin on the centreline at the design
    waterline, half-way along the waterline length; ``half``: its y >= 0 half."""

    type: Literal["semi_submersible", "box", "mesh", "revolved", "buoy", "ship"]
    size: Optional[vector(Vec3, "m")] = None        # box: length, width, height
    centre: vector(Vec3, "m") = (0.0, 0.0, 0.0)     # box: centre in the body frame
    file: Optional[str] = None                      # mesh: meshio-readable closed triangle mesh
    profile: Optional[tuple[vector(Vec2, "m"), ...]] = None  # revolved: (z, r) rings [m], keel up, body frame
    segments: count(3) = 48                         # revolved, buoy: sides of each ring
    d_max: Optional[quantity("m")] = None           # buoy: the widest diameter
    alpha: Optional[quantity("deg", lt=90.0)] = None  # buoy: downward-sloping hull angle, from the horizontal
    height: Optional[quantity("m")] = None          # buoy: keel to top
    keel: Optional[quantity("m", gt=None, ge=0.0)] = None   # buoy: the keel cylinder's height (default height/6)
    widest: Optional[quantity("m")] = None          # buoy: the widest section above the keel (default 5 height/6)
    length: Optional[quantity("m")] = None          # ship: waterline length (platform/ship.py)
    midbody: Optional[quantity("m")] = None         # ship: parallel midbody on the waterline
    breadth: Optional[quantity("m")] = None         # ship: breadth B
    draft: Optional[quantity("m")] = None           # ship: draft T, keel to the body origin's waterline
    waterline_angle: Optional[quantity("deg", lt=90.0)] = None  # ship: the bow's half-angle on the waterline
    stem_angle: Optional[quantity("deg", lt=90.0)] = None       # ship: the stem's rake from the horizontal
    depth: Optional[quantity("m")] = None           # ship: keel to deck (default draft + 5.5 m)
    half: StrictBool = False                        # ship: the y >= 0 half only (a symmetry wall at y = 0)

    @model_validator(mode="after")
    def _geometry(self):
        if self.type == "box" and self.size is None:
            raise ValueError("size: missing: a box hull needs size = [length, width, height] (m)")
        if self.type == "box" and min(self.size) <= 0.0:
            raise ValueError("size: must be three lengths > 0 m")
        if self.type == "revolved":
            prof = self.profile or []
            if len(prof) < 2 or any(b[0] <= a[0] for a, b in zip(prof, prof[1:])) or any(r <= 0.0 for _, r in prof):
                raise ValueError(f"profile = {prof}: a revolved hull needs at least two [z, r] rings (m, body "
                                 "frame), z increasing from the keel up, every radius r > 0")
        if self.type == "mesh" and self.file is None:
            raise ValueError("file: missing: a mesh hull needs file = \"path/to/hull.stl\" (relative to the "
                             "job file's folder; body frame, origin at the centre of gravity)")
        self._buoy()
        self._ship()
        return self

    def _ship(self) -> None:
        """The keys of a "ship" hull (seed 002's Table 1): given, and the bow, stem and stern fitting."""
        keys = ("length", "midbody", "breadth", "draft", "waterline_angle", "stem_angle", "depth")
        if self.type != "ship":
            for key in keys + ("half",):
                if getattr(self, key) not in (None, False):
                    raise ValueError(f"{key}: only for type = \"ship\"; drop it (this hull is {self.type!r})")
            return
        for key, what in (("length", "the waterline length [m]"), ("midbody", "the parallel midbody [m]"),
                          ("breadth", "the breadth [m]"), ("draft", "the draft [m]"),
                          ("waterline_angle", "the bow's waterline half-angle [deg]"),
                          ("stem_angle", "the stem angle [deg] from the horizontal")):
            if getattr(self, key) is None:
                raise ValueError(f"{key}: missing: a ship hull needs {what}")
        if self.midbody >= self.length:
            raise ValueError(f"midbody: must be < length = {self.length:g} m (the bow and stern lie outside it)")
        bow = 0.5 * self.breadth / math.tan(math.radians(self.waterline_angle))
        if self.length - self.midbody - bow <= 0.0:
            widest = math.degrees(math.atan2(0.5 * self.breadth, self.length - self.midbody))
            raise ValueError(f"waterline_angle: the bow at {self.waterline_angle:g} deg is {bow:.4g} m long on the "
                             f"waterline (B / (2 tan alpha)), more than the {self.length - self.midbody:.4g} m that "
                             f"length and midbody leave for bow and stern; raise it above {widest:.4g} deg or "
                             "shorten the midbody")
        rake = self.draft / math.tan(math.radians(self.stem_angle))
        if rake >= self.midbody:
            raise ValueError(f"stem_angle: the stem at {self.stem_angle:g} deg rakes {rake:.4g} m over the draft "
                             f"(T / tan phi), more than the {self.midbody:g} m midbody whose fore end rakes with it; "
                             f"raise it above {math.degrees(math.atan2(self.draft, self.midbody)):.4g} deg")
        if self.depth is not None and self.depth <= self.draft:
            raise ValueError(f"depth: must be > draft = {self.draft:g} m (keel to deck)")

    @property
    def ship_dimensions(self) -> dict:
        """A "ship" hull's keywords for platform.ship.ship_pieces (depth None: its default freeboard)."""
        return dict(length=self.length, midbody=self.midbody, breadth=self.breadth, draft=self.draft,
                    waterline_angle=self.waterline_angle, stem_angle=self.stem_angle, depth=self.depth,
                    half=self.half)

    def _buoy(self) -> None:
        """The keys of a "buoy" hull: d_max, alpha and height given, the cones fitting the height."""
        keys = ("d_max", "alpha", "height", "keel", "widest")
        if self.type != "buoy":
            for key in keys:
                if getattr(self, key) is not None:
                    raise ValueError(f"{key}: only for type = \"buoy\"; drop it (this hull is {self.type!r})")
            return
        if self.profile is not None:
            raise ValueError("profile: a buoy hull's rings come from d_max, alpha and height; drop profile "
                             "(or use type = \"revolved\")")
        for key, what in (("d_max", "the widest diameter [m]"), ("alpha", "the downward-sloping hull angle [deg], "
                                                                          "from the horizontal"),
                          ("height", "keel to top [m]")):
            if getattr(self, key) is None:
                raise ValueError(f"{key}: missing: a buoy hull needs {what}")
        keel, widest = self.buoy_keel, self.buoy_widest
        if widest >= self.height:
            raise ValueError(f"widest: must be < height = {self.height:g} m (the upper cone lies above it)")
        if keel >= widest:
            raise ValueError(f"keel: the keel cylinder ({keel:g} m high) must end below the widest section at "
                             f"{widest:g} m; lower keel or raise widest")
        drop = (widest - keel) / math.tan(math.radians(self.alpha))
        if drop >= 0.5 * self.d_max:
            raise ValueError(f"d_max: the lower cone at alpha = {self.alpha:g} deg closes before the keel (its diameter "
                             f"shrinks by {2 * drop:.4g} m over its {widest - keel:g} m height); widen the buoy (d_max > {2 * drop:.4g} m) "
                             f"or steepen the cone (alpha > "
                             f"{math.degrees(math.atan2(widest - keel, 0.5 * self.d_max)):.4g} deg)")

    @property
    def buoy_keel(self) -> float:
        """A buoy's keel cylinder [m]: given, or height/6 (seed 004 Eq. 4-16)."""
        return self.keel if self.keel is not None else self.height / 6.0

    @property
    def buoy_widest(self) -> float:
        """A buoy's widest section above its keel [m]: given, or 5 height/6 (seed 004 Eq. 4-22)."""
        return self.widest if self.widest is not None else 5.0 * self.height / 6.0


class BodySpec(Section):
    """[[bodies]]: a rigid floating body (6 DOF, attitude as a unit quaternion)."""

    name: str
    hull: HullSpec
    mass: Union[Literal["balance", "shell"], quantity("kg")]    # "balance": the mass that floats at `position`;
                                                                 # "shell": a steel shell (platform/shell.py)
    inertia: Optional[vector(tuple[Moment, Moment, Moment], "kg m^2")] = None  # roll, pitch, yaw about the CG
                                                                 # (default with mass = "shell": the shell's)
    shell_thickness: Optional[quantity("m")] = None              # mass = "shell": t of m = rho_s t S
    shell_density: quantity("kg/m^3") = 7850.0                   # mass = "shell": rho_s (steel, seed 004 Eq. 4-19)
    position: Union[Literal["afloat"], vector(Vec3, "m")]        # centre of gravity at t = 0; "afloat": at x = y =
                                                                 # 0, as high as it floats with its lines' pull
    heading: quantity("deg", gt=None) = 0.0                      # yaw at t = 0
    added_mass: vector(Vec6, "kg, kg m^2") = (0.0,) * 6          # diagonal, body frame
    damping: vector(Vec6, "N s^2/m^2, N m s^2") = (0.0,) * 6     # quadratic B of F = -B |u| u, body frame
    current_drag: vector(Vec2, "N s^2/m^2") = (0.0, 0.0)         # 1/2 rho C_d A along x and y
    motion: Literal["free", "prescribed"] = "free"
    velocity: tuple[Row7, ...] = ()                              # prescribed: rows (t, vx, vy, vz, wx, wy, wz)
    friction: quantity("", gt=None, ge=0.0) = 0.15               # ice-hull Coulomb friction
    normal_stiffness: Optional[quantity("N/m")] = None           # ice-hull contact spring (default: contact's)
    crushing_width: Optional[quantity("m")] = None               # w of ISO 19906 crushing (default: hull's y-extent)

    @model_validator(mode="after")
    def _mass(self):
        if self.mass == "shell" and self.shell_thickness is None:
            raise ValueError("shell_thickness: missing: mass = \"shell\" needs the shell's thickness t [m] of "
                             "m = shell_density t S (seed 004 Eq. 4-21: 0.0619 m of steel)")
        if self.mass != "shell" and self.shell_thickness is not None:
            raise ValueError("shell_thickness: only with mass = \"shell\"; drop it or set mass = \"shell\"")
        if self.mass != "shell" and self.inertia is None:
            raise ValueError("inertia: missing: give [roll, pitch, yaw] moments (kg m^2) about the centre of "
                             "gravity, or mass = \"shell\" (a thin shell's)")
        if self.position == "afloat" and self.mass == "balance":
            raise ValueError("position: \"afloat\" floats the body at its mass, and mass = \"balance\" is the mass "
                             "that floats at a given position: give the mass (kg or \"shell\") or the position")
        if self.mass == "shell" and self.hull.type == "ship":
            raise ValueError("mass: \"shell\" is not for a ship hull (its pieces share inner faces that a shell over "
                             "its triangles would count); give the mass in kg")
        if self.position == "afloat" and self.hull.type == "mesh":
            raise ValueError("position: \"afloat\" needs a hull built from parameters (box, revolved, buoy, "
                             "semi_submersible); for a mesh hull give [x, y, z] (m)")
        return self

    @model_validator(mode="after")
    def _motion(self):
        if self.motion == "prescribed" and not self.velocity:
            raise ValueError("velocity: missing: prescribed motion needs velocity = [[t, vx, vy, vz, wx, wy, wz], "
                             "...] (s, m/s, rad/s)")
        if self.motion == "free" and self.velocity:
            raise ValueError("velocity: given for a free body: set motion = \"prescribed\" or drop velocity")
        times = [row[0] for row in self.velocity]
        if any(b <= a for a, b in zip(times, times[1:])):
            raise ValueError("velocity: the times (first column, s) must increase from row to row")
        return self


class SegmentSpec(Section):
    """[[moorings.segments]]: one homogeneous part of every line of the entry, anchor first."""

    length: quantity("m")
    ea: quantity("N")
    diameter: quantity("m")
    wet_weight: quantity("N/m")
    dry_mass: Optional[quantity("kg/m")] = None  # default: steel, from the wet weight
    drag_normal: quantity("", gt=None, ge=0.0) = 1.2
    drag_tangential: quantity("", gt=None, ge=0.0) = 0.008
    added_mass: quantity("", gt=None, ge=0.0) = 1.0


class MooringSpec(Section):
    """[[moorings]]: a spread of lines from fairleads on one body to anchors placed by the layout solve.

    The fairleads are points in space at t = 0 (``fairleads``), or, with ``fairlead_inset``, on the
    body's keel: one per heading, on the lowest ring of a hull of revolution, ``fairlead_inset`` m in
    from its edge towards the axis, wherever the body floats (seed 004's d_m,f, Table 4-3). The
    anchors lie ``anchor_depth`` m below the fairleads, or on the seabed with "seabed"."""

    body: str
    model: Literal["dem", "quasi_static"] = "dem"
    fairleads: Optional[tuple[vector(Vec3, "m"), ...]] = Field(default=None, min_length=1)  # space frame, t = 0
    fairlead_inset: Optional[quantity("m", gt=None, ge=0.0)] = None  # or: on the keel's edge, this far in
    headings: tuple[Real, ...] = Field(min_length=1)                # outward heading of each fairlead [deg]
    lines_per_fairlead: count(1) = 1
    spread: quantity("deg", gt=None, ge=0.0) = 5.0                  # between the lines of one fairlead
    anchor_depth: Union[Literal["seabed"], quantity("m")]           # anchor below its fairlead, or on the seabed
    pretension: quantity("N")                                       # fairlead tension at rest
    segments: tuple[SegmentSpec, ...] = Field(min_length=1)
    element_length: quantity("m") = 10.0                            # DEM: longest element
    bond_damping: quantity("", gt=None, ge=0.0, le=1.0) = 0.3       # DEM: axial dashpot, fraction of critical
    seabed_stiffness: quantity("N/m^2") = 1.0e5                     # DEM: per metre of line
    seabed_friction: quantity("", gt=None, ge=0.0) = 0.5
    relax: StrictBool = True                                        # DEM: settle the lines before t = 0

    @model_validator(mode="after")
    def _layout(self):
        if (self.fairleads is None) == (self.fairlead_inset is None):
            raise ValueError("fairleads: give either fairleads = [[x, y, z], ...] (m, in space at t = 0) or "
                             "fairlead_inset (m: on the keel's edge, one per heading), not both or neither")
        if self.fairleads is not None and len(self.headings) != len(self.fairleads):
            raise ValueError(f"headings: must have one heading per fairlead ({len(self.fairleads)}), "
                             f"not {len(self.headings)}")
        total = sum(s.length for s in self.segments)
        if self.anchor_depth != "seabed" and total <= self.anchor_depth:
            raise ValueError(f"anchor_depth: must be < the line's length {total:g} m (the line cannot reach)")
        if self.model == "dem" and self.element_length > max(s.length for s in self.segments):
            raise ValueError(f"element_length: must be <= the longest segment "
                             f"({max(s.length for s in self.segments):g} m)")
        return self

    @property
    def n_lines(self) -> int:
        return len(self.headings) * self.lines_per_fairlead


def check_platform(job, bad) -> None:
    """Rules between [[bodies]], [[moorings]] and [water]; ``bad(loc, value, msg)`` records one."""
    names = [b.name for b in job.bodies]
    for k, b in enumerate(job.bodies):
        if names.index(b.name) != k:
            bad(("bodies", k, "name"), b.name, "must be unique among [[bodies]]")
        if job.water is None:
            bad(("bodies", k), b.name, "a floating body needs a [water] table")
        if b.mass == "balance" and job.gravity == 0.0:
            bad(("bodies", k, "mass"), b.mass, "\"balance\" needs gravity > 0; give the mass in kg")
    for k, m in enumerate(job.moorings):
        if m.body not in names:
            bad(("moorings", k, "body"), m.body, f"must name one of the [[bodies]]: {', '.join(names) or '(none)'}")
        if job.water is None or job.water.depth is None:
            bad(("moorings", k), m.body, "mooring lines need water.depth [m] (the seabed) in [water]")
        elif m.fairleads and m.anchor_depth != "seabed" and any(
                f[2] - m.anchor_depth < job.water.level - job.water.depth - 1e-6 for f in m.fairleads):
            bad(("moorings", k, "anchor_depth"), m.anchor_depth,
                f"puts an anchor below the seabed at {job.water.level - job.water.depth:g} m (water.depth = "
                f"{job.water.depth:g} m)")
        if job.gravity == 0.0:
            bad(("moorings", k), m.body, "mooring lines need gravity > 0 (their catenary)")
        if m.fairlead_inset is not None and m.body in names and job.bodies[names.index(m.body)].hull.type not in (
                "revolved", "buoy"):
            bad(("moorings", k, "fairlead_inset"), m.fairlead_inset, "puts the fairleads on the keel of a hull of "
                "revolution (hull.type \"revolved\" or \"buoy\"); give fairleads = [[x, y, z], ...] (m) instead")
        if job.water is not None:
            for j, f in enumerate(m.fairleads or ()):
                if f[2] > job.water.level:
                    bad(("moorings", k, "fairleads", j), list(f),
                        f"is above the water (z > water.level = {job.water.level:g} m): a line weighs its "
                        "wet_weight everywhere, which holds under water only (its weight in air is not "
                        "modelled); put the fairlead at or below the water level")
        _check_line_stiffness(m, k, bad)


def _check_line_stiffness(m: MooringSpec, k: int, bad) -> None:
    """The stiffness of a line's segments against its own weight and its pretension (linear elastic
    line, T = EA x strain): a segment softer than a tenth of the line's wet weight W [N] would be
    stretched more than ten-fold by that weight alone (no line model holds there); at a tension
    equal to the smallest EA [N] the line is stretched to twice its length (real lines break far
    below that), which bounds the pretension."""
    weight = sum(s.wet_weight * s.length for s in m.segments)
    soft = [j for j, s in enumerate(m.segments) if s.ea < 0.1 * weight]
    for j in soft:
        bad(("moorings", k, "segments", j, "ea"), m.segments[j].ea,
            f"must be >= {0.1 * weight:.4g} N, a tenth of the line's wet weight ({weight:.4g} N): softer, its own "
            "weight would stretch it more than ten-fold (T/EA > 10); check the unit (N, e.g. 1.0e8 for a chain)")
    j = min(range(len(m.segments)), key=lambda i: m.segments[i].ea)
    if not soft and m.pretension >= m.segments[j].ea:
        bad(("moorings", k, "pretension"), m.pretension,
            f"must be < {m.segments[j].ea:g} N, the axial stiffness moorings[{k}].segments[{j}].ea: at a tension "
            "equal to EA the linear-elastic line is stretched to twice its length (real lines break far below)")

