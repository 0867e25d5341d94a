"""TOML job -> validated, frozen job description.

Every problem is reported as one line naming the file, the key, the value and what is
expected, e.g. ``jobs/x.toml: ice.thickness = -1.0: must be > 0 m``. Validation happens before
anything is allocated or written.
"""

from __future__ import annotations

import math
import pathlib
from typing import Annotated, Any, Literal, Optional, Union, get_args, get_origin

from pydantic import BaseModel, Field, StrictBool, ValidationError, model_validator

from .errors import JobError
from .job_platform import BodySpec, MooringSpec, check_platform
from .job_types import Vec2, Vec3, _Bound, _count, _q, _Real, _Section, _vec

try:  # Python >= 3.11
    import tomllib
except ModuleNotFoundError:  # pragma: no cover
    import tomli as tomllib


class RunSpec(_Section):
    """[run]: duration, time step and output schedule."""

    name: str = "run"
    duration: _q("s") = 1.0
    dt: Union[Literal["auto"], _q("s")] = "auto"
    dt_safety: _q("", gt=0.0, le=1.0) = 0.5
    allow_unstable_dt: StrictBool = False
    output: str = ""
    series_every: _count(1) = 100
    snapshots: _count(0) = 5
    check_every: _count(1) = 10
    stop_at_first_break: StrictBool = False
    checkpoint_every: _q("s", gt=None, ge=0.0) = 0.0  # simulated seconds between checkpoints; 0 = off
    checkpoint: str = ""  # checkpoint file (default: beside the run file, <run>.ckpt.h5)


class WaterSpec(_Section):
    """[water]: still water with a uniform current."""

    density: _q("kg/m^3") = 1025.0
    level: _q("m", gt=None) = 0.0
    current: _vec(Vec2, "m/s") = (0.0, 0.0)
    drag_coefficient: _q("", gt=None, ge=0.0) = 1.0
    heave_damping_ratio: _q("", gt=None, ge=0.0, lt=1.0) = 0.0
    depth: Optional[_q("m")] = None  # still-water depth to the flat seabed (mooring lines need it)


class PushSpec(_Section):
    """[ice.push]: the rear edge of the sheet driven at a constant speed along +x: rigidly (its
    velocity prescribed), or through springs of ``stiffness`` per element to anchors moving at
    ``speed`` (a spring boundary standing for the far-field ice)."""

    speed: _q("m/s", gt=None) = 0.05
    rows: _count(1) = 1
    stiffness: Optional[_q("N/m")] = None
    damping_ratio: _q("", gt=None, ge=0.0, le=1.0) = 1.0


class IceSpec(_Section):
    """[ice]: a bonded level-ice sheet in hexagonal close packing."""

    density: _q("kg/m^3") = 920.0
    thickness: _q("m") = 1.0
    element_diameter: _q("m") = 1.0
    length: _q("m") = 20.0
    width: _q("m") = 10.0
    origin: _vec(Vec2, "m") = (0.0, 0.0)
    velocity: _vec(Vec2, "m/s") = (0.0, 0.0)
    element_volume: Literal["sphere", "cell"] = "sphere"
    youngs_modulus: Optional[_q("Pa")] = None
    poissons_ratio: _q("", gt=None, ge=0.0, lt=0.5) = 0.3
    flexural_strength: Optional[_q("Pa")] = None
    compressive_strength: Optional[_q("Pa")] = None
    push: Optional[PushSpec] = None


class BondSpec(_Section):
    """[bond]: parallel bond (Eqs. 1-5 of Zhu & Ji 2022). Stiffness in N/m, or from ice.youngs_modulus."""

    normal_stiffness: Optional[_q("N/m")] = None
    shear_stiffness: Optional[_q("N/m")] = None
    radius_ratio: _q("", le=1.0) = 1.0
    normal_strength: Optional[_q("Pa")] = None
    shear_strength: Optional[_q("Pa")] = None
    friction: Optional[_q("", gt=None, ge=0.0)] = None
    damping_ratio: _q("", gt=None, ge=0.0, le=1.0) = 0.0
    breakable: StrictBool = True


class ContactSpec(_Section):
    """[contact]: linear spring-dashpot normal force, tangential spring with Coulomb friction."""

    normal_stiffness: Optional[_q("N/m")] = None
    stiffness_ratio: _q("", le=1.0) = 0.5
    restitution: _q("", le=1.0) = 0.3
    friction: _q("", gt=None, ge=0.0) = 0.15


class WallSpec(_Section):
    """[[walls]]: a fixed rigid plane, triangle or triangle mesh file (meshio-readable)."""

    name: str = ""
    type: Literal["plane", "triangle", "mesh"]
    point: Optional[_vec(Vec3, "m")] = None
    normal: Optional[Vec3] = None
    vertices: Optional[_vec(tuple[Vec3, Vec3, Vec3], "m")] = None
    file: Optional[str] = None
    friction: _q("", gt=None, ge=0.0) = 0.1
    normal_stiffness: Optional[_q("N/m")] = None

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


class Region(_Section):
    """An axis-aligned box selecting elements by their initial centre [m]; open sides default to infinity."""

    xmin: _Bound = -math.inf
    xmax: _Bound = math.inf
    ymin: _Bound = -math.inf
    ymax: _Bound = math.inf
    zmin: _Bound = -math.inf
    zmax: _Bound = math.inf


class LoadSpec(_Section):
    """[[loads]]: a constant total force [N] shared evenly by the elements in a region."""

    force: _vec(Vec3, "N")
    region: Region


class FixSpec(_Section):
    """[[fixes]]: prescribed velocity components [m/s] for the elements in a region ("free" leaves one free)."""

    velocity: _vec(tuple[Union[_Real, Literal["free"]], Union[_Real, Literal["free"]], Union[_Real, Literal["free"]]],
                   "m/s")
    region: Region


class ParallelSpec(_Section):
    """[parallel]: decomposition and load balance (ignored on one rank)."""

    skin: _q("m") = 0.3
    balance_every: Annotated[int, Field(ge=0)] = 500
    imbalance_threshold: _q("", gt=1.0) = 1.05
    domain: Optional[tuple[Vec2, Vec2]] = None


class Job(_Section):
    """A validated scene. Sections that are absent switch their physics off."""

    run: RunSpec = RunSpec()
    gravity: _q("m/s^2", gt=None, ge=0.0) = 9.81
    water: Optional[WaterSpec] = None
    ice: IceSpec
    bond: BondSpec = BondSpec()
    contact: ContactSpec = ContactSpec()
    walls: tuple[WallSpec, ...] = ()
    loads: tuple[LoadSpec, ...] = ()
    fixes: tuple[FixSpec, ...] = ()
    bodies: tuple[BodySpec, ...] = ()
    moorings: tuple[MooringSpec, ...] = ()
    parallel: ParallelSpec = ParallelSpec()
    source: str = Field(default="", exclude=True)
    text: str = Field(default="", exclude=True)

    @model_validator(mode="after")
    def _consistent(self):
        """Rules between keys; every broken rule is reported (one line each)."""
        ice, bond, run = self.ice, self.bond, self.run
        problems: list[_Located] = []

        def bad(loc, value, msg):
            problems.append(_Located(loc, value, msg))

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
        if run.dt != "auto" and run.dt >= run.duration:
            bad(("run", "dt"), run.dt, f"must be < run.duration = {run.duration} s")
        check_platform(self, bad)
        if problems:
            raise _Located.group(problems)
        return self


EQ7_SLOPE, EQ7_OFFSET = 0.23, 0.5  # Eq. 7 of Zhu & Ji (2022): mu = 0.23 sc/sf - 0.5 (as in physics/bond.py)


class _Located(ValueError):
    """A cross-field error that knows which key it is about; ``problems`` lists all of them."""

    def __init__(self, loc, value, msg):
        self.loc, self.value, self.msg = loc, value, msg
        self.problems = [self]
        super().__init__(msg)

    @classmethod
    def group(cls, problems: list["_Located"]) -> "_Located":
        first = problems[0]
        first.problems = list(problems)
        return first


_TYPE_WORDS = {
    "float_parsing": "must be a number", "float_type": "must be a number",
    "int_parsing": "must be a whole number", "int_type": "must be a whole number",
    "int_from_float": "must be a whole number",
    "bool_parsing": "must be true or false", "bool_type": "must be true or false",
    "string_type": "must be a string", "tuple_type": "must be a list",
    "model_type": "must be a table", "finite_number": "must be a finite number",
}


def _field_unit(loc) -> str:
    """Unit of the field at ``loc`` (walks the model classes), '' if unknown."""
    model: Any = Job
    field = None
    for part in loc:
        if isinstance(part, int) or model is None:
            continue
        fields = getattr(model, "model_fields", {})
        if part not in fields:
            return ""
        field = fields[part]
        ann = field.annotation
        model = _inner_model(ann)
    if field is None:
        return ""
    if isinstance(field.json_schema_extra, dict):
        return field.json_schema_extra.get("unit", "")
    for meta in field.metadata:
        extra = getattr(meta, "json_schema_extra", None)
        if extra:
            return extra.get("unit", "")
    ann = field.annotation
    for arg in getattr(ann, "__args__", ()):
        for meta in getattr(arg, "__metadata__", ()):
            extra = getattr(meta, "json_schema_extra", None)
            if extra:
                return extra.get("unit", "")
    return ""


def _inner_model(ann):
    if isinstance(ann, type) and issubclass(ann, BaseModel):
        return ann
    for arg in getattr(ann, "__args__", ()):
        m = _inner_model(arg)
        if m is not None:
            return m
    return None


def _tuple_length(loc) -> int | None:
    """Fixed length of the tuple field at ``loc`` (e.g. 3 for a Vec3), None if not a fixed tuple."""
    ann: Any = Job
    for part in loc:
        ann = _strip(ann)
        if isinstance(part, int):
            args = get_args(ann) if get_origin(ann) is tuple else ()
            if not args:
                return None
            ann = args[0] if args[-1] is Ellipsis else args[min(part, len(args) - 1)]
        else:
            model = _inner_model(ann)
            if model is None or part not in model.model_fields:
                return None
            ann = model.model_fields[part].annotation
    ann = _strip(ann)
    args = get_args(ann) if get_origin(ann) is tuple else ()
    return len(args) if args and args[-1] is not Ellipsis else None


def _is_table(loc) -> bool:
    """True if the key at ``loc`` is a section (a pydantic model), not a value."""
    model: Any = Job
    for part in loc:
        if isinstance(part, int):
            continue
        f = getattr(model, "model_fields", {}).get(part) if model is not None else None
        if f is None:
            return False
        model = _inner_model(f.annotation)
    return model is not None and get_origin(_strip(f.annotation)) is not tuple


def _strip(ann):
    """Annotated[X, ...] -> X and Optional[X] -> X."""
    while True:
        if get_origin(ann) is Annotated:
            ann = get_args(ann)[0]
            continue
        args = [a for a in get_args(ann) if a is not type(None)]
        if get_origin(ann) is Union and len(args) == 1:
            ann = args[0]
            continue
        return ann


def _allowed_keys(loc) -> list[str]:
    model: Any = Job
    for part in loc[:-1]:
        if isinstance(part, int):
            continue
        f = getattr(model, "model_fields", {}).get(part)
        model = _inner_model(f.annotation) if f else None
        if model is None:
            return []
    return [k for k in model.model_fields if k not in ("source", "text")]


def _key(loc) -> str:
    """('walls', 0, 'normal') -> 'walls[0].normal'."""
    out = ""
    for p in loc:
        out += f"[{p}]" if isinstance(p, int) else (f".{p}" if out else str(p))
    return out


def _format(err: dict) -> tuple[str, Any, str]:
    loc = tuple(p for p in err["loc"] if not (isinstance(p, str) and ("[" in p or p.startswith("function-"))))
    # pydantic inserts union-branch names like 'float' or "literal['auto']": drop them
    loc = tuple(p for p in loc if p not in ("float", "str", "int", "bool", "constrained-float"))
    typ, ctx = err["type"], err.get("ctx", {})
    unit = _field_unit(loc)
    u = f" {unit}" if unit else ""
    value = err.get("input")
    if typ == "extra_forbidden":
        allowed = ", ".join(_allowed_keys(loc))
        return _key(loc), value, f"unknown key; expected one of: {allowed}"
    if typ == "missing" and loc and isinstance(loc[-1], int):  # a list one entry short of a fixed length
        n = _tuple_length(loc[:-1])
        got = f", not {len(value)}" if isinstance(value, (list, tuple)) else ""
        return _key(loc[:-1]), value, f"must have {n} entries{got}" if n else "too few entries"
    if typ == "missing":
        table = _key(tuple(p for p in loc if not isinstance(p, int)))
        return _key(loc), None, (f"missing: the [{table}] table is required" if _is_table(loc)
                                 else "missing: this key is required")
    if typ == "model_type" and isinstance(value, list):
        table = _key(tuple(p for p in loc if not isinstance(p, int)))
        return _key(loc), value, f"must be a table: write [{table}], not [[{table}]]"
    if typ in ("greater_than", "greater_than_equal", "less_than", "less_than_equal"):
        op = {"greater_than": ">", "greater_than_equal": ">=", "less_than": "<", "less_than_equal": "<="}[typ]
        bound = list(ctx.values())[0]
        bound = f"{bound:g}" if isinstance(bound, float) else bound
        return _key(loc), value, f"must be {op} {bound}{u}"
    if typ == "literal_error":
        expected = str(ctx.get("expected"))
        return _key(loc), value, f"must be {'one of ' if ' or ' in expected else ''}{expected}"
    if typ in ("too_short", "too_long"):
        n = ctx.get("min_length") if typ == "too_short" else ctx.get("max_length")
        got = f", not {ctx['actual_length']}" if ctx.get("actual_length") is not None else ""
        return _key(loc), value, f"must have {'at least' if typ == 'too_short' else 'at most'} {n} entries{got}"
    if typ == "value_error":
        msg = str(ctx.get("error", err["msg"]))
        if ": " in msg:
            key, _, msg = msg.partition(": ")
            loc = loc + (key,)
            value = value.get(key) if isinstance(value, dict) else value
        return _key(loc), value, msg
    words = _TYPE_WORDS.get(typ, err["msg"])
    return _key(loc), value, f"{words}{' (' + unit + ')' if unit else ''}"


def _show(value, top: bool = True) -> str:
    """A value as it reads in TOML (true, 1.0, [1.0, 2.0], 'text'), on one short line."""
    if value is None:
        return "(absent)"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, dict):
        if not top or len(value) > 6:
            return "{...}"
        return "{" + ", ".join(f"{k} = {_show(v, False)}" for k, v in value.items()) + "}"
    if isinstance(value, (list, tuple)):
        if len(value) > 6:
            return f"[{len(value)} entries]"
        return "[" + ", ".join(_show(v, False) for v in value) + "]"
    text = repr(value) if isinstance(value, str) else str(value)
    return text if len(text) <= 80 else text[:77] + "..."


def parse_job(data: dict, source: str = "<job>", text: str = "", base_dir: pathlib.Path | None = None) -> Job:
    """Validate a job given as a dict; raise JobError with one line per problem."""
    try:
        job = Job.model_validate({**data, "source": source, "text": text})
    except _Located as exc:  # raised inside a model validator of the top-level model
        raise JobError([f"{source}: {_key(c.loc)} = {_show(c.value)}: {c.msg}" for c in exc.problems]) from None
    except ValidationError as exc:
        problems: dict[str, tuple[Any, list[str]]] = {}
        for err in exc.errors(include_url=False):
            cause = err.get("ctx", {}).get("error")
            if isinstance(cause, _Located):
                for c in cause.problems:
                    problems.setdefault(_key(c.loc), (c.value, []))[1].append(c.msg)
                continue
            key, value, msg = _format(err)
            # a union (e.g. dt = "auto" or a number) fails once per branch: join them
            problems.setdefault(key, (value, []))[1].append(msg)
        lines = []
        for key, (value, msgs) in problems.items():
            msg = msgs[0] if len(msgs) == 1 else " or ".join(m.replace("must be ", "", 1) if i else m
                                                            for i, m in enumerate(msgs))
            lines.append(f"{source}: {key} = {_show(value)}: {msg}")
        raise JobError(lines) from None
    base = base_dir or pathlib.Path(".")
    for k, wall in enumerate(job.walls):
        if wall.type == "mesh" and not (base / wall.file).is_file():
            raise JobError(f"{source}: walls[{k}].file = {wall.file!r}: file not found "
                           f"(paths are relative to the job file's folder {str(base)!r})")
    for k, body in enumerate(job.bodies):
        if body.hull.type == "mesh" and not (base / body.hull.file).is_file():
            raise JobError(f"{source}: bodies[{k}].hull.file = {body.hull.file!r}: file not found "
                           f"(paths are relative to the job file's folder {str(base)!r})")
    return job


def load_job(path: str | pathlib.Path) -> Job:
    """Read and validate a TOML job file; raise JobError naming the file on any problem."""
    path = pathlib.Path(path)
    if not path.is_file():
        what = "is a directory" if path.is_dir() else "file not found"
        raise JobError(f"{path}: {what}: give the path of a TOML job file (see jobs/)")
    try:
        text = path.read_text(encoding="utf-8", errors="replace")
    except OSError as exc:
        raise JobError(f"{path}: cannot read the job file ({exc.strerror or exc})") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise JobError(f"{path}: not valid TOML: {exc}") from None
    return parse_job(data, source=str(path), text=text, base_dir=path.parent)
