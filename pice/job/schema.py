"""The job schema: one frozen pydantic model per TOML table, and ``Job``, the whole scene.

A table that is absent switches its physics off. Bounds and units sit on the fields (pice.job.types);
rules between keys are checked in ``Job`` (and, for bodies and moorings, in pice.job.platform),
each broken rule reported as its own line (pice.job.messages).
"""

from __future__ import annotations

import math
from typing import Annotated, Literal, Optional, Union

from pydantic import Field, StrictBool, model_validator

from .floes import FloesSpec, WavesSpec
from .keel import KeelSpec
from .messages import Located
from .platform import BodySpec, MooringSpec, check_platform
from .types import Bound, Real, Section, Vec2, Vec3, count, quantity, vector

EQ7_SLOPE, EQ7_OFFSET = 0.23, 0.5  # Eq. 7 of Zhu & Ji (2022): mu = 0.23 sc/sf - 0.5 (as in physics/bond.py)


class RunSpec(Section):
    """[run]: duration, time step and output schedule."""

    name: str = "run"
    duration: quantity("s") = 1.0
    dt: Union[Literal["auto"], quantity("s")] = "auto"
    dt_safety: quantity("", gt=0.0, le=1.0) = 0.5
    allow_unstable_dt: StrictBool = False
    output: str = ""
    series_every: count(1) = 100
    snapshots: count(0) = 5
    check_every: count(1) = 10
    stop_at_first_break: StrictBool = False
    checkpoint_every: quantity("s", gt=None, ge=0.0) = 0.0  # simulated seconds between checkpoints; 0 = off
    checkpoint: str = ""  # checkpoint file (default: beside the run file, <run>.ckpt.h5)


class WaterSpec(Section):
    """[water]: still water with a uniform current.

    The water drags the ice by ``ice_drag``: "skin" (the default: ice-ocean skin friction per unit
    area of the sheet, tau = rho_w C_w |u_rel| u_rel with C_w = ``skin_drag_coefficient``, 0.0055 by
    default, a common value of the 0.003-0.006 measured under sea ice; docs/crushing.md) or
    "morison" (form drag on every element, Eq. 8 of Zhu & Ji 2022, with ``drag_coefficient``:
    right for floes, rubble and lines, not for a sheet, where it grows with the sheet's size).
    """

    density: quantity("kg/m^3") = 1025.0
    level: quantity("m", gt=None) = 0.0
    current: vector(Vec2, "m/s") = (0.0, 0.0)
    ice_drag: Literal["skin", "morison"] = "skin"
    skin_drag_coefficient: quantity("", gt=None, ge=0.0) = 0.0055
    drag_coefficient: quantity("", gt=None, ge=0.0) = 1.0
    heave_damping_ratio: quantity("", gt=None, ge=0.0, lt=1.0) = 0.0
    depth: Optional[quantity("m")] = None  # still-water depth to the flat seabed (mooring lines need it)


class PushSpec(Section):
    """[ice.push]: the rear edge of the sheet driven at a constant speed along +x: rigidly (its
    velocity prescribed), or through springs of ``stiffness`` per element to anchors moving at
    ``speed`` (a spring boundary standing for the far-field ice). With ``far_field_length`` the
    anchors are the ice of that length behind the sheet (its width and thickness), a free mass that
    starts at ``speed`` and is slowed by its push on the sheet: a finite ice field, as seed 004's
    level ice of 5050 m in all (Table 6-3); without it the far field is unbounded."""

    speed: quantity("m/s", gt=None) = 0.05
    rows: count(1) = 1
    stiffness: Optional[quantity("N/m")] = None
    side_stiffness: Optional[quantity("N/m")] = None  # with stiffness: the side edges held in y by springs
    damping_ratio: quantity("", gt=None, ge=0.0, le=1.0) = 1.0
    far_field_length: Optional[quantity("m")] = None  # with stiffness: the far field a free mass of this length

    @model_validator(mode="after")
    def _far_field(self):
        if self.far_field_length is not None and self.stiffness is None:
            raise ValueError("far_field_length: the far field moves the anchors of the spring boundary: give "
                             "stiffness as well, or drop far_field_length")
        return self


class IceSpec(Section):
    """[ice]: a bonded level-ice sheet in hexagonal close packing."""

    density: quantity("kg/m^3") = 920.0
    thickness: quantity("m") = 1.0
    element_diameter: quantity("m") = 1.0
    length: quantity("m") = 20.0
    width: quantity("m") = 10.0
    origin: vector(Vec2, "m") = (0.0, 0.0)
    velocity: vector(Vec2, "m/s") = (0.0, 0.0)
    element_volume: Literal["sphere", "cell"] = "sphere"
    youngs_modulus: Optional[quantity("Pa")] = None
    poissons_ratio: quantity("", gt=None, ge=0.0, lt=0.5) = 0.3
    flexural_strength: Optional[quantity("Pa")] = None
    compressive_strength: Optional[quantity("Pa")] = None
    push: Optional[PushSpec] = None


class BondSpec(Section):
    """[bond]: parallel bond (Eqs. 1-5 of Zhu & Ji 2022). Stiffness in N/m, or from ice.youngs_modulus."""

    normal_stiffness: Optional[quantity("N/m")] = None
    shear_stiffness: Optional[quantity("N/m")] = None
    radius_ratio: quantity("", le=1.0) = 1.0
    normal_strength: Optional[quantity("Pa")] = None
    shear_strength: Optional[quantity("Pa")] = None
    friction: Optional[quantity("", gt=None, ge=0.0)] = None
    shear_strength_law: Literal["mohr_coulomb", "zhu_ji_2022_eq5"] = "mohr_coulomb"  # Eq. 5 as printed: option
    compressive_strength: Optional[quantity("Pa")] = None  # the bond's compressive cap (none by default)
    damping_ratio: quantity("", gt=None, ge=0.0, le=1.0) = 0.0
    breakable: StrictBool = True


class ContactSpec(Section):
    """[contact]: linear spring-dashpot normal force, tangential spring with Coulomb friction."""

    normal_stiffness: Optional[quantity("N/m")] = None
    stiffness_ratio: Optional[quantity("", le=1.0)] = None  # k_t / k_n; default G / E = 1 / (2 (1 + nu))
    restitution: quantity("", le=1.0) = 0.3
    friction: quantity("", gt=None, ge=0.0) = 0.15


class WallSpec(Section):
    """[[walls]]: a fixed rigid plane, triangle or triangle mesh file (meshio-readable)."""

    name: str = ""
    type: Literal["plane", "triangle", "mesh"]
    point: Optional[vector(Vec3, "m")] = None
    normal: Optional[Vec3] = None
    vertices: Optional[vector(tuple[Vec3, Vec3, Vec3], "m")] = None
    file: Optional[str] = None
    friction: quantity("", gt=None, ge=0.0) = 0.1
    normal_stiffness: Optional[quantity("N/m")] = None
    crushing_width: Optional[quantity("m")] = None  # the structure's width w for ISO 19906 crushing

    @model_validator(mode="after")
    def _geometry(self):
        need = {"plane": ("point", "normal"), "triangle": ("vertices",), "mesh": ("file",)}[self.type]
        for key in need:
            if getattr(self, key) is None:
                raise ValueError(f"{key}: missing: a {self.type} wall needs {key} = {_WALL_KEY_HINTS[key]}")
        if self.type == "plane" and math.hypot(*self.normal) == 0.0:
            raise ValueError("normal: must be a non-zero vector [nx, ny, nz] (any length; it is normalised)")
        if self.type == "triangle":
            a, b, c = (tuple(map(float, v)) for v in self.vertices)
            ab = [b[i] - a[i] for i in range(3)]
            ac = [c[i] - a[i] for i in range(3)]
            cross = (ab[1] * ac[2] - ab[2] * ac[1], ab[2] * ac[0] - ab[0] * ac[2], ab[0] * ac[1] - ab[1] * ac[0])
            longest2 = max(sum(x * x for x in e) for e in (ab, ac, [c[i] - b[i] for i in range(3)]))
            if math.hypot(*cross) <= 1e-12 * longest2:
                raise ValueError("vertices: degenerate triangle (zero area): the three vertices [m] must not "
                                 "coincide or lie on one line")
        return self


_WALL_KEY_HINTS = {"point": "[x, y, z] (a point on the plane, m)",
                   "normal": "[nx, ny, nz] (pointing towards the ice)",
                   "vertices": "[[x, y, z], [x, y, z], [x, y, z]] (m)",
                   "file": "\"path/to/mesh.stl\" (relative to the job file's folder)"}


class Region(Section):
    """An axis-aligned box selecting elements by their initial centre [m]; open sides default to infinity."""

    xmin: Bound = -math.inf
    xmax: Bound = math.inf
    ymin: Bound = -math.inf
    ymax: Bound = math.inf
    zmin: Bound = -math.inf
    zmax: Bound = math.inf


class LoadSpec(Section):
    """[[loads]]: a constant total force [N] shared evenly by the elements in a region."""

    force: vector(Vec3, "N")
    region: Region


FixComponent = Union[Real, Literal["free"]]  # a prescribed velocity component [m/s], or "free"


class FixSpec(Section):
    """[[fixes]]: prescribed velocity components [m/s] for the elements in a region ("free" leaves one free)."""

    velocity: vector(tuple[FixComponent, FixComponent, FixComponent], "m/s")
    region: Region


class CrushingSpec(Section):
    """[crushing]: elastic-perfectly-plastic contacts (seeds 003 and 004): the normal force is capped at
    a crushing pressure times the contact area, and the ice yields beyond it. Absent: elastic contacts.

    ``structure``: the pressure of ice crushing on walls and hulls: "iso19906" (the global pressure
    p_G = C_R (h/h1)^n (w/h)^m of ISO 19906 A.8.2.4.3 for each structure's width w: walls[].crushing_width)
    or a constant [Pa]. ``ice``: the pressure of ice crushing on ice [Pa]; default ice.compressive_strength.
    docs/crushing.md gives the defaults and why.
    """

    structure: Union[Literal["iso19906"], quantity("Pa")] = "iso19906"
    iso_cr: quantity("Pa") = 1.5e6
    ice: Optional[quantity("Pa")] = None


class ParallelSpec(Section):
    """[parallel]: decomposition and load balance (ignored on one rank)."""

    skin: quantity("m") = 0.3
    balance_every: Annotated[int, Field(ge=0)] = 500
    imbalance_threshold: quantity("", gt=1.0) = 1.05
    # what the cuts even out (parallel/domain.py): the elements per rank, or each rank's measured
    # busy time (its wall time outside waits on other ranks) since the last check; "time" follows
    # the work a rank really does (rank 0's platform, a slower core) but makes the cuts, and so the
    # round-off, depend on timing: a run is then not repeatable bit for bit; "work" weighs each element
    # by its modelled work (its ice and hull contacts cost more than its bonds: physics/work.py), from
    # the state alone, so that a run stays repeatable bit for bit
    balance_by: Literal["elements", "time", "work"] = "elements"
    domain: Optional[tuple[Vec2, Vec2]] = None


class Job(Section):
    """A validated scene. Sections that are absent switch their physics off."""

    run: RunSpec = RunSpec()
    gravity: quantity("m/s^2", gt=None, ge=0.0) = 9.81
    water: Optional[WaterSpec] = None
    ice: Optional[IceSpec] = None      # a bonded level-ice sheet
    floes: Optional[FloesSpec] = None  # a field of rigid floes
    waves: Optional[WavesSpec] = None
    keel: Optional[KeelSpec] = None    # a ridge keel of rubble blocks under a cover
    bond: BondSpec = BondSpec()
    contact: ContactSpec = ContactSpec()
    walls: tuple[WallSpec, ...] = ()
    loads: tuple[LoadSpec, ...] = ()
    fixes: tuple[FixSpec, ...] = ()
    bodies: tuple[BodySpec, ...] = ()
    moorings: tuple[MooringSpec, ...] = ()
    crushing: Optional[CrushingSpec] = None
    parallel: ParallelSpec = ParallelSpec()
    source: str = Field(default="", exclude=True)  # the job file's path, as error lines name it
    text: str = Field(default="", exclude=True)    # the job file's text, as the run file keeps it

    @property
    def half_model(self) -> bool:
        """A half model: a body's hull is a ship's y >= 0 half, and a keel's wall at y0 = 0 is the
        symmetry plane through its centreline (frictionless: physics/keel.keel_walls)."""
        return any(b.hull.type == "ship" and b.hull.half for b in self.bodies)

    @model_validator(mode="after")
    def _consistent(self):
        """Rules between keys; every broken rule is reported (one line each)."""
        ice, run = self.ice, self.run
        problems: list[Located] = []

        def bad(loc, value, msg):
            problems.append(Located(loc, value, msg))

        if ice is not None:
            self._ice_rules(bad)
        elif self.floes is None and self.keel is None and not self.bodies:
            bad(("ice",), None, "missing: a scene needs ice: give [ice] (a level-ice sheet) or [floes] (broken ice), "
                "or at least one [[bodies]] entry")
        if ice is None and self.walls:
            bad(("walls",), None, "[[walls]] hold level-ice elements and the job has no [ice]; drop [[walls]] (a floe "
                "field is confined by floes.sides = \"confined\")")
        if ice is not None and self.waves is not None and self.floes is None and not self.bodies:
            bad(("waves",), None, "nothing in this scene feels waves: the level-ice elements do not (waves act on "
                "rigid floes, hulls and mooring lines); drop [waves]")
        if self.floes is not None and self.floes.breakable:
            self._breakable_floe_rules(bad)
        if (self.floes is not None or self.waves is not None) and self.water is None:
            bad(("water",), None, "missing: [floes] and [waves] need [water] (the floes float in it, the waves "
                "travel on it)")
        if self.keel is not None:
            if self.water is None:
                bad(("water",), None, "missing: a [keel]'s blocks rise against its cover by their buoyancy: give "
                    "[water]")
            if self.gravity == 0.0:
                bad(("gravity",), 0.0, "a [keel]'s blocks rise against its cover by their buoyancy: give gravity > 0")
            if self.floes is not None:
                bad(("floes", "area"), list(self.floes.area), "a [keel] scene's rigid pieces are its blocks: drop "
                    "[floes]")
            if self.waves is not None:
                bad(("waves", "spectrum"), self.waves.spectrum, "a [keel] lies under its cover in still water: drop "
                    "[waves]")
            if self.keel.end_after_peak is not None and not self.bodies:
                bad(("keel", "end_after_peak"), self.keel.end_after_peak, "ends a ship's run once its resistance "
                    "is past the peak, and the job has no [[bodies]]: give the ship, or drop end_after_peak")
            if self.keel.y0 != 0.0 and self.half_model:
                bad(("keel", "y0"), self.keel.y0, "a half ship's model (hull.half = true) has its symmetry plane at "
                    "the centreline y = 0, where the keel's wall at y0 stands: give y0 = 0")
        if run.dt != "auto" and run.dt >= run.duration:
            bad(("run", "dt"), run.dt, f"must be < run.duration = {run.duration} s")
        if self.crushing is not None:
            if self.crushing.structure == "iso19906":
                for k, wall in enumerate(self.walls):
                    if wall.crushing_width is None:
                        bad(("walls", k, "crushing_width"), None,
                            "missing: crushing.structure = \"iso19906\" needs each wall's width w [m] for the "
                            "pressure-area relation (or give crushing.structure a pressure [Pa])")
            if self.crushing.ice is None and ice is not None and ice.compressive_strength is None:
                bad(("crushing", "ice"), None, "missing: the ice-ice crushing pressure [Pa]; give crushing.ice "
                    "or ice.compressive_strength")
        check_platform(self, bad)
        if problems:
            raise Located.group(problems)
        return self

    def _breakable_floe_rules(self, bad) -> None:
        """Breakable floes are the floe field built of [ice] elements (scenes/bonded_floes.py)."""
        ice, floes = self.ice, self.floes
        if ice is None:
            bad(("ice",), None, "missing: breakable floes (floes.breakable = true) are built of [ice] elements: "
                "give [ice] (thickness, element_diameter, youngs_modulus, flexural_strength)")
            return
        for key in sorted({"length", "width", "origin", "velocity", "push"} & ice.model_fields_set):
            bad(("ice", key), getattr(ice, key), "the floe field places breakable floes (floes.area, floes.size, "
                f"floes.velocity): drop ice.{key}")
        if self.waves is not None:
            bad(("waves",), None, "breakable floes are level-ice elements, which do not feel waves: drop [waves], "
                "or make the floes rigid (drop floes.breakable)")
        if floes.sides == "confined":
            x0, y0, x1, y1 = floes.area
            bad(("floes", "sides"), floes.sides, "breakable floes are held at the sides by [[walls]]: drop "
                f"floes.sides and give two planes, point = [0, {y0:g}, 0] normal = [0, 1, 0] and "
                f"point = [0, {y1:g}, 0] normal = [0, -1, 0]")

    def _ice_rules(self, bad) -> None:
        """Rules between [ice], [bond], [water] and [crushing] keys of a level-ice sheet."""
        ice, bond = self.ice, self.bond
        # the HCP sheet needs at least one element across each dimension (scenes/level_ice.py)
        if ice.thickness < ice.element_diameter * (1 - 1e-9) and ice.element_volume != "cell":
            bad(("ice", "thickness"), ice.thickness,
                f"must be >= ice.element_diameter = {ice.element_diameter} m (one layer of elements), or set "
                "ice.element_volume = \"cell\" (elements stand for plate cells of the thickness)")
        for key in ("length", "width"):
            if getattr(ice, key) < ice.element_diameter:
                bad(("ice", key), getattr(ice, key), f"must be >= ice.element_diameter = {ice.element_diameter} m "
                    "(one element across)")
        # bond stiffness: given directly or calibrated from E (physics/bond.py)
        has_k = bond.normal_stiffness is not None
        if has_k and ice.youngs_modulus is not None:
            bad(("bond", "normal_stiffness"), bond.normal_stiffness,
                f"give either bond.normal_stiffness [N/m] or ice.youngs_modulus [Pa] (= {ice.youngs_modulus}), "
                "not both")
        if not has_k and ice.youngs_modulus is None:
            bad(("bond", "normal_stiffness"), None,
                "missing: give bond.normal_stiffness [N/m] or ice.youngs_modulus [Pa]")
        # bond strength: given directly or from the flexural strength by Eq. 6 of Zhu & Ji (2022)
        if bond.breakable and bond.normal_strength is None and ice.flexural_strength is None:
            bad(("bond", "normal_strength"), None,
                "missing: give bond.normal_strength [Pa] or ice.flexural_strength [Pa] "
                "(or set bond.breakable = false)")
        # bond friction mu = 0.23 sc/sf - 0.5 (Eq. 7 of Zhu & Ji 2022) unless bond.friction is given
        if bond.friction is None and ice.compressive_strength is None and ice.flexural_strength is not None \
                and bond.normal_strength is None and bond.breakable:
            bad(("ice", "compressive_strength"), None,
                "missing: Eq. 7 needs ice.compressive_strength [Pa] for the bond friction (or give bond.friction)")
        if bond.breakable and bond.friction is None and ice.compressive_strength is not None \
                and ice.flexural_strength is not None:
            mu = EQ7_SLOPE * ice.compressive_strength / ice.flexural_strength - EQ7_OFFSET
            if mu < 0:
                bad(("ice", "compressive_strength"), ice.compressive_strength,
                    f"must be >= {EQ7_OFFSET / EQ7_SLOPE:.4g} x ice.flexural_strength = "
                    f"{EQ7_OFFSET / EQ7_SLOPE * ice.flexural_strength:.4g} Pa, else Eq. 7 gives a negative bond "
                    f"friction (0.23 sc/sf - 0.5 = {mu:.3g}); or give bond.friction")
        # a floating sheet (scenes/level_ice.py floats it at its rest height)
        if self.water is not None and self.gravity > 0 and ice.density >= self.water.density:
            bad(("ice", "density"), ice.density,
                f"must be < water.density = {self.water.density} kg/m^3, else the ice sinks")
