"""TOML job -> validated, frozen job description.

Every problem is reported as one line naming the file, the key, the value and what is
expected, e.g. ``jobs/x.toml: ice.thickness = -1.0: must be > 0 m``. Validation happens before
anything is allocated or written.
"""

from __future__ import annotations

import math
import pathlib
from typing import Annotated, Any, Literal, Optional, Union

from pydantic import BaseModel, ConfigDict, Field, ValidationError, model_validator

from .errors import JobError

try:  # Python >= 3.11
    import tomllib
except ModuleNotFoundError:  # pragma: no cover
    import tomli as tomllib


def _q(unit: str, gt: float | None = 0.0, ge: float | None = None, le: float | None = None, lt: float | None = None):
    """A float quantity with a unit (shown in error messages) and bounds."""
    kw = {k: v for k, v in dict(gt=gt, ge=ge, le=le, lt=lt).items() if v is not None}
    return Annotated[float, Field(json_schema_extra={"unit": unit}, allow_inf_nan=False, **kw)]


Vec2 = tuple[float, float]
Vec3 = tuple[float, float, float]


class _Section(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True, strict=False)


class RunSpec(_Section):
    """[run]: duration, time step and output schedule."""

    name: str = "run"
    duration: _q("s") = 1.0
    dt: Union[Literal["auto"], _q("s")] = "auto"
    dt_safety: _q("", gt=0.0, le=1.0) = 0.5
    allow_unstable_dt: bool = False
    output: str = ""
    series_every: Annotated[int, Field(ge=1)] = 100
    snapshots: Annotated[int, Field(ge=0)] = 5
    check_every: Annotated[int, Field(ge=1)] = 10
    stop_at_first_break: bool = False


class WaterSpec(_Section):
    """[water]: still water with a uniform current."""

    density: _q("kg/m^3") = 1025.0
    level: _q("m", gt=None) = 0.0
    current: Vec2 = (0.0, 0.0)
    drag_coefficient: _q("", gt=None, ge=0.0) = 1.0
    heave_damping_ratio: _q("", gt=None, ge=0.0, lt=1.0) = 0.0


class PushSpec(_Section):
    """[ice.push]: the rear edge of the sheet driven at a constant speed along +x."""

    speed: _q("m/s", gt=None) = 0.05
    rows: Annotated[int, Field(ge=1)] = 1


class IceSpec(_Section):
    """[ice]: a bonded level-ice sheet in hexagonal close packing."""

    density: _q("kg/m^3") = 920.0
    thickness: _q("m") = 1.0
    element_diameter: _q("m") = 1.0
    length: _q("m") = 20.0
    width: _q("m") = 10.0
    origin: Vec2 = (0.0, 0.0)
    velocity: Vec2 = (0.0, 0.0)
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
    breakable: bool = True


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
    point: Optional[Vec3] = None
    normal: Optional[Vec3] = None
    vertices: Optional[tuple[Vec3, Vec3, Vec3]] = None
    file: Optional[str] = None
    friction: _q("", gt=None, ge=0.0) = 0.1
    normal_stiffness: Optional[_q("N/m")] = None

    @model_validator(mode="after")
    def _geometry(self):
        need = {"plane": ("point", "normal"), "triangle": ("vertices",), "mesh": ("file",)}[self.type]
        for key in need:
            if getattr(self, key) is None:
                raise ValueError(f"{key}: a {self.type} wall needs '{key}'")
        if self.type == "plane" and math.hypot(*self.normal) == 0.0:
            raise ValueError("normal: must be a non-zero vector")
        return self


class Region(_Section):
    """An axis-aligned box selecting elements by their initial centre [m]; open sides default to infinity."""

    xmin: float = -math.inf
    xmax: float = math.inf
    ymin: float = -math.inf
    ymax: float = math.inf
    zmin: float = -math.inf
    zmax: float = math.inf


class LoadSpec(_Section):
    """[[loads]]: a constant total force [N] shared evenly by the elements in a region."""

    force: Vec3
    region: Region


class FixSpec(_Section):
    """[[fixes]]: prescribed velocity components [m/s] for the elements in a region ("free" leaves one free)."""

    velocity: tuple[Union[float, Literal["free"]], Union[float, Literal["free"]], Union[float, Literal["free"]]]
    region: Region


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
    source: str = Field(default="", exclude=True)
    text: str = Field(default="", exclude=True)

    @model_validator(mode="after")
    def _consistent(self):
        ice, bond = self.ice, self.bond
        if ice.thickness < ice.element_diameter * (1 - 1e-9):
            raise _Located(("ice", "thickness"), ice.thickness,
                           f"must be >= ice.element_diameter = {ice.element_diameter} m (one layer of elements)")
        for key in ("length", "width"):
            if getattr(ice, key) < ice.element_diameter:
                raise _Located(("ice", key), getattr(ice, key),
                               f"must be >= ice.element_diameter = {ice.element_diameter} m")
        has_k = bond.normal_stiffness is not None
        if has_k and ice.youngs_modulus is not None:
            raise _Located(("bond", "normal_stiffness"), bond.normal_stiffness,
                           "give either bond.normal_stiffness or ice.youngs_modulus, not both")
        if not has_k and ice.youngs_modulus is None:
            raise _Located(("bond", "normal_stiffness"), None,
                           "missing: give bond.normal_stiffness [N/m] or ice.youngs_modulus [Pa]")
        if bond.breakable and bond.normal_strength is None and ice.flexural_strength is None:
            raise _Located(("bond", "normal_strength"), None,
                           "missing: give bond.normal_strength [Pa] or ice.flexural_strength [Pa] "
                           "(or set bond.breakable = false)")
        if bond.friction is None and ice.compressive_strength is None and ice.flexural_strength is not None \
                and bond.normal_strength is None and bond.breakable:
            raise _Located(("ice", "compressive_strength"), None,
                           "missing: Eq. 7 needs ice.compressive_strength [Pa] for the bond friction "
                           "(or give bond.friction)")
        if self.run.dt != "auto" and self.run.dt >= self.run.duration:
            raise _Located(("run", "dt"), self.run.dt, f"must be < run.duration = {self.run.duration} s")
        return self


class _Located(ValueError):
    """A cross-field error that knows which key it is about."""

    def __init__(self, loc, value, msg):
        self.loc, self.value, self.msg = loc, value, msg
        super().__init__(msg)


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
    if typ == "missing":
        return _key(loc), None, "missing: this key is required"
    if typ in ("greater_than", "greater_than_equal", "less_than", "less_than_equal"):
        op = {"greater_than": ">", "greater_than_equal": ">=", "less_than": "<", "less_than_equal": "<="}[typ]
        bound = list(ctx.values())[0]
        bound = f"{bound:g}" if isinstance(bound, float) else bound
        return _key(loc), value, f"must be {op} {bound}{u}"
    if typ == "literal_error":
        return _key(loc), value, f"must be one of {ctx.get('expected')}"
    if typ in ("too_short", "too_long"):
        return _key(loc), value, f"must have {ctx.get('min_length', ctx.get('max_length'))} entries"
    if typ == "value_error":
        msg = str(ctx.get("error", err["msg"]))
        if ": " in msg:
            key, _, msg = msg.partition(": ")
            loc = loc + (key,)
            value = value.get(key) if isinstance(value, dict) else value
        return _key(loc), value, msg
    words = _TYPE_WORDS.get(typ, err["msg"])
    return _key(loc), value, f"{words}{' (' + unit + ')' if unit else ''}"


def _show(value) -> str:
    if value is None:
        return "(absent)"
    if isinstance(value, dict):
        return "{...}"
    return repr(value) if isinstance(value, str) else str(value)


def parse_job(data: dict, source: str = "<job>", text: str = "", base_dir: pathlib.Path | None = None) -> Job:
    """Validate a job given as a dict; raise JobError with one line per problem."""
    try:
        job = Job.model_validate({**data, "source": source, "text": text})
    except _Located as exc:  # raised inside a model validator of the top-level model
        raise JobError(f"{source}: {'.'.join(exc.loc)} = {_show(exc.value)}: {exc.msg}") from None
    except ValidationError as exc:
        problems: dict[str, tuple[Any, list[str]]] = {}
        for err in exc.errors(include_url=False):
            cause = err.get("ctx", {}).get("error")
            if isinstance(cause, _Located):
                key, value, msg = ".".join(cause.loc), cause.value, cause.msg
            else:
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
    return job


def load_job(path: str | pathlib.Path) -> Job:
    """Read and validate a TOML job file; raise JobError naming the file on any problem."""
    path = pathlib.Path(path)
    if not path.is_file():
        raise JobError(f"{path}: file not found: give the path of a TOML job file (see jobs/)")
    text = path.read_text(encoding="utf-8", errors="replace")
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise JobError(f"{path}: not valid TOML: {exc}") from None
    return parse_job(data, source=str(path), text=text, base_dir=path.parent)
