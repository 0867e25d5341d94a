"""Validation errors -> one line per problem: ``FILE: key = value: what is expected``.

pydantic reports a failed field as a location tuple, an error type and a context; this module turns
each into the job's dotted key (``walls[0].normal``), the offending value as it reads in TOML, and
a sentence with the field's unit and bounds. Rules between keys raise ``Located``, which carries
the key itself. The schema is walked from ``root`` (``pice.job.schema.Job``) to find a field's unit,
a vector's length or a table's allowed keys.
"""

from __future__ import annotations

from typing import Annotated, Any, Union, get_args, get_origin

from pydantic import BaseModel, ValidationError


class Located(ValueError):
    """A cross-field error that knows which key it is about; ``problems`` lists all of them."""

    def __init__(self, loc, value, msg):
        self.loc, self.value, self.msg = loc, value, msg
        self.problems = [self]
        super().__init__(msg)

    @classmethod
    def group(cls, problems: list["Located"]) -> "Located":
        first = problems[0]
        first.problems = list(problems)
        return first


def error_lines(exc: Located | ValidationError, *, source: str, root: type[BaseModel]) -> list[str]:
    """The lines of a failed validation of ``root``, each starting with ``source``; a key that failed
    several ways (e.g. each branch of ``dt = "auto" or a number``) gets one line joining them."""
    if isinstance(exc, Located):  # raised inside a model validator of the top-level model
        return [f"{source}: {_key(c.loc)} = {_show(c.value)}: {c.msg}" for c in exc.problems]
    problems: dict[str, tuple[Any, list[str]]] = {}
    for err in exc.errors(include_url=False):
        cause = err.get("ctx", {}).get("error")
        if isinstance(cause, Located):
            for c in cause.problems:
                problems.setdefault(_key(c.loc), (c.value, []))[1].append(c.msg)
            continue
        key, value, msg = _format(err, root)
        # a union (e.g. dt = "auto" or a number) fails once per branch: join them
        problems.setdefault(key, (value, []))[1].append(msg)
    lines = []
    for key, (value, msgs) in problems.items():
        msg = msgs[0] if len(msgs) == 1 else " or ".join(m.replace("must be ", "", 1) if i else m
                                                        for i, m in enumerate(msgs))
        lines.append(f"{source}: {key} = {_show(value)}: {msg}")
    return lines


_TYPE_WORDS = {
    "float_parsing": "must be a number", "float_type": "must be a number",
    "int_parsing": "must be a whole number", "int_type": "must be a whole number",
    "int_from_float": "must be a whole number",
    "bool_parsing": "must be true or false", "bool_type": "must be true or false",
    "string_type": "must be a string", "tuple_type": "must be a list",
    "model_type": "must be a table", "finite_number": "must be a finite number",
}


def _format(err: dict, root: type[BaseModel]) -> tuple[str, Any, str]:
    """One pydantic error -> (key, value, message)."""
    loc = tuple(p for p in err["loc"] if not (isinstance(p, str) and ("[" in p or p.startswith("function-"))))
    # pydantic inserts union-branch names like 'float' or "literal['auto']": drop them
    loc = tuple(p for p in loc if p not in ("float", "str", "int", "bool", "constrained-float"))
    typ, ctx = err["type"], err.get("ctx", {})
    unit = _field_unit(root, loc)
    u = f" {unit}" if unit else ""
    value = err.get("input")
    if typ == "extra_forbidden":
        allowed = ", ".join(_allowed_keys(root, loc))
        return _key(loc), value, f"unknown key; expected one of: {allowed}"
    if typ == "missing" and loc and isinstance(loc[-1], int):  # a list one entry short of a fixed length
        n = _tuple_length(root, loc[:-1])
        got = f", not {len(value)}" if isinstance(value, (list, tuple)) else ""
        return _key(loc[:-1]), value, f"must have {n} entries{got}" if n else "too few entries"
    if typ == "missing":
        table = _key(tuple(p for p in loc if not isinstance(p, int)))
        return _key(loc), None, (f"missing: the [{table}] table is required" if _is_table(root, loc)
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


def _key(loc) -> str:
    """('walls', 0, 'normal') -> 'walls[0].normal'."""
    out = ""
    for p in loc:
        out += f"[{p}]" if isinstance(p, int) else (f".{p}" if out else str(p))
    return out


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


# --- walking the schema from the root model along an error's location


def _field_unit(root, loc) -> str:
    """Unit of the field at ``loc`` (walks the model classes), '' if unknown."""
    model: Any = root
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
    """The pydantic model inside an annotation (Optional[M], tuple[M, ...], ...), None if there is none."""
    if isinstance(ann, type) and issubclass(ann, BaseModel):
        return ann
    for arg in getattr(ann, "__args__", ()):
        m = _inner_model(arg)
        if m is not None:
            return m
    return None


def _tuple_length(root, loc) -> int | None:
    """Fixed length of the tuple field at ``loc`` (e.g. 3 for a Vec3), None if not a fixed tuple."""
    ann: Any = root
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


def _is_table(root, loc) -> bool:
    """True if the key at ``loc`` is a section (a pydantic model), not a value."""
    model: Any = root
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


def _allowed_keys(root, loc) -> list[str]:
    """The keys of the table that holds ``loc`` (for an unknown key's message)."""
    model: Any = root
    for part in loc[:-1]:
        if isinstance(part, int):
            continue
        f = getattr(model, "model_fields", {}).get(part)
        model = _inner_model(f.annotation) if f else None
        if model is None:
            return []
    return [k for k, f in model.model_fields.items() if not f.exclude]  # not Job.source, Job.text
