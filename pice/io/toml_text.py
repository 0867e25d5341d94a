"""Write a job dict (as ``tomllib`` reads it) back as TOML text.

Python reads TOML but has no writer, and a study writes each of its variants as a job file you can
run again. Only what a job holds is written: tables, arrays of tables, strings, booleans, integers,
floats (inf and nan included) and arrays of them. Comments of the original file are not kept.

``tomllib.loads(toml_text(data)) == data`` for every such dict (tests/io/test_study.py checks it).
"""

from __future__ import annotations

import datetime
import json
import math
import re

_BARE_KEY = re.compile(r"^[A-Za-z0-9_-]+$")


def toml_text(data: dict, *, header: str = "") -> str:
    """``data`` as TOML; ``header`` lines go on top as comments."""
    lines = [f"# {line}".rstrip() for line in header.splitlines()]
    _table(data, (), lines)
    return "\n".join(lines).strip("\n") + "\n"


def _table(table: dict, path: tuple[str, ...], lines: list[str]) -> None:
    """Values first, then sub-tables ``[a.b]``, then arrays of tables ``[[a.b]]`` (TOML's order)."""
    subtables = {k: v for k, v in table.items() if isinstance(v, dict)}
    arrays = {k: v for k, v in table.items() if _is_table_array(v)}
    for key, value in table.items():
        if key not in subtables and key not in arrays:
            lines.append(f"{_key(key)} = {_value(value)}")
    for key, value in subtables.items():
        lines += ["", f"[{_dotted(path + (key,))}]"]
        _table(value, path + (key,), lines)
    for key, items in arrays.items():
        for item in items:
            lines += ["", f"[[{_dotted(path + (key,))}]]"]
            _table(item, path + (key,), lines)


def _is_table_array(value) -> bool:
    return isinstance(value, list) and bool(value) and all(isinstance(v, dict) for v in value)


def _key(key: str) -> str:
    return key if _BARE_KEY.match(key) else _string(key)


def _dotted(path: tuple[str, ...]) -> str:
    return ".".join(_key(k) for k in path)


def _string(text: str) -> str:
    """A TOML basic string (JSON's escapes are TOML's; DEL must be escaped as well)."""
    return json.dumps(text, ensure_ascii=False).replace("\x7f", "\\u007f")


def _value(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        return repr(value)  # shortest round trip; 'inf', '-inf', '1e-05' are TOML floats
    if isinstance(value, str):
        return _string(value)
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_value(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{_key(k)} = {_value(v)}" for k, v in value.items()) + "}"
    if isinstance(value, (datetime.datetime, datetime.date, datetime.time)):
        return value.isoformat()
    raise TypeError(f"cannot write {type(value).__name__} {value!r} as TOML")
