"""The variants of a study: ``--vary KEY=v1,v2,...`` parsed, checked against the job, and every
combination written out as a job of its own (validated by parse_job before anything runs).

``moorings[0].element_length`` is the key path ("moorings", 0, "element_length"); values read as
TOML scalars (a bare word such as ``auto`` is the string it spells). Each variant is the job text
with its values set, its run file named by the study (``<out>/<job>_<k>.h5``) and its mesh paths
made absolute, so the variant's TOML file is a job you can run again.
"""

from __future__ import annotations

import copy
import dataclasses
import itertools
import math
import pathlib
import re

from ..errors import JobError
from ..io.toml_text import toml_text
from ..job import load_job, parse_job

try:  # Python >= 3.11
    import tomllib
except ModuleNotFoundError:  # pragma: no cover
    import tomli as tomllib

_NAME = r"[A-Za-z_][A-Za-z0-9_-]*"
_KEY_PATH = re.compile(rf"^{_NAME}(\[\d+\])*(\.{_NAME}(\[\d+\])*)*$")
_OWNED = ("run.output", "run.checkpoint")  # the study names each variant's files itself


@dataclasses.dataclass(frozen=True)
class Vary:
    """One ``--vary KEY=v1,v2,...``: the key as written, its path in the job dict, the TOML values."""

    key: str
    path: tuple
    values: tuple


@dataclasses.dataclass(frozen=True)
class Variant:
    """One validated variant: ``values`` maps each varied key to its value."""

    index: int
    values: dict
    job: object  # pice.job.Job, its source the variant's TOML file
    text: str
    toml: pathlib.Path
    run: pathlib.Path
    label: str  # "x.toml with run.dt = 0.0001": the source named by its error messages
    total: int = 1  # the number of combinations of the study (variants left out by ``keep`` included)
    shown: tuple = ()  # the keys its progress line names: those given more than one value (else all)


def key_path(key: str) -> tuple:
    """``"moorings[0].element_length"`` -> ``("moorings", 0, "element_length")``."""
    if not _KEY_PATH.match(key):
        raise JobError(f"--vary {key}: not a key; write it as the TOML file does, e.g. ice.thickness or "
                       "moorings[0].element_length")
    return tuple(int(p) if p.isdigit() else p for p in re.findall(r"[^.\[\]]+", key))


def split_values(text: str) -> list[str]:
    """Split ``v1,v2,...`` at the commas outside brackets and quotes (``[1.0, 0.0]`` stays one value)."""
    parts, depth, quote, start = [], 0, "", 0
    for i, ch in enumerate(text):
        if quote:
            quote = "" if ch == quote else quote
        elif ch in "\"'":
            quote = ch
        elif ch in "[{":
            depth += 1
        elif ch in "]}":
            depth -= 1
        elif ch == "," and depth == 0:
            parts.append(text[start:i].strip())
            start = i + 1
    parts.append(text[start:].strip())
    return parts


def toml_value(text: str):
    """A value as TOML reads it (``1e-4``, ``2``, ``true``, ``"auto"``, ``[1.0, 0.0]``); a bare word
    such as ``auto`` is the string it spells."""
    try:
        return tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        return text


def parse_vary(spec: str) -> Vary:
    """``"run.dt=1e-4,2e-4"`` -> Vary; raises JobError for a malformed spec (not for an unknown key)."""
    key, eq, values = spec.partition("=")
    key = key.strip()
    if not eq or not key:
        raise JobError(f"--vary {spec}: expected KEY=v1,v2,... (e.g. --vary run.dt=1e-4,2e-4)")
    texts = split_values(values)
    if not all(texts):
        raise JobError(f"--vary {spec}: an empty value; give the values of {key} separated by commas")
    return Vary(key=key, path=key_path(key), values=tuple(toml_value(t) for t in texts))


def check_key(job, vary: Vary) -> None:
    """Raise JobError unless ``vary.key`` names a value of ``job`` (a parsed Job) that may be varied:
    a known key, list indices in range, no table switched on that the job leaves off."""
    from pydantic import BaseModel

    where = f"{job.source}: --vary {vary.key}"
    if vary.key in _OWNED:
        raise JobError(f"{where}: the study names each variant's files itself (<out>/<job>_<k>.h5)")
    obj, done = job, ""
    for i, part in enumerate(vary.path):
        last = i == len(vary.path) - 1
        if isinstance(part, int):
            if not isinstance(obj, tuple):
                raise JobError(f"{where}: {done} is not a list: drop [{part}]")
            if part >= len(obj):
                raise JobError(f"{where}: {done} has {len(obj)} entr{'y' if len(obj) == 1 else 'ies'} "
                               f"(indices from 0)")
            obj, done = obj[part], f"{done}[{part}]"
        else:
            if not isinstance(obj, BaseModel):
                hint = f"give an index, e.g. {done}[0].{part}" if isinstance(obj, tuple) else "it is a value"
                raise JobError(f"{where}: {done} has no keys ({hint})")
            fields = [k for k in type(obj).model_fields if k not in ("source", "text")]
            if part not in fields:
                table = f"[{done}]" if done else "the job"
                raise JobError(f"{where}: unknown key {part!r} in {table}; expected one of: {', '.join(fields)}")
            obj, done = getattr(obj, part), f"{done}.{part}" if done else part
        if obj is None and not last:
            raise JobError(f"{where}: the job has no [{done}] table (that part is off): add it to the job "
                           "to vary its keys")
    if isinstance(obj, BaseModel) or (isinstance(obj, tuple) and obj and isinstance(obj[0], BaseModel)):
        raise JobError(f"{where}: {done} is a table, not a value: vary one of its keys")


def _plain(value):
    """A parsed job value as tomllib would give it (tuples -> lists)."""
    return [_plain(v) for v in value] if isinstance(value, tuple) else value


def set_value(data: dict, job, path: tuple, value) -> None:
    """Set ``value`` at ``path`` in the job dict ``data`` (in place); a table or list the file leaves
    at its default is added (a list with the default's entries, taken from the parsed ``job``)."""
    node, model = data, job
    for part, nxt in itertools.pairwise(path):
        model = model[part] if isinstance(part, int) else getattr(model, part)
        if isinstance(part, str) and part not in node:
            node[part] = _plain(model) if isinstance(model, tuple) else {}
        node = node[part]
        if isinstance(nxt, str) and not isinstance(node, dict):
            raise JobError(f"{job.source}: {part} is not a table")  # excluded by check_key
    node[path[-1]] = value


def _own_paths(data: dict, base_dir: pathlib.Path, run: pathlib.Path, stem: str) -> None:
    """Make a variant self-contained: its run file is ``run`` (run.output), its checkpoint the default
    beside it, and mesh files and the keel file are absolute (the variant lives in another folder
    than the job; its variants share the job's keel, io/keel_file.keel_path)."""
    data.setdefault("run", {})["output"] = str(run)
    data["run"].pop("checkpoint", None)
    if isinstance(data.get("keel"), dict):
        data["keel"]["file"] = str((base_dir / (data["keel"].get("file") or f"{stem}.keel.h5")).resolve())
    for wall in data.get("walls", []):
        if isinstance(wall.get("file"), str):
            wall["file"] = str((base_dir / wall["file"]).resolve())
    for body in data.get("bodies", []):
        hull = body.get("hull")
        if isinstance(hull, dict) and isinstance(hull.get("file"), str):
            hull["file"] = str((base_dir / hull["file"]).resolve())


def make_variants(job_path, specs: list, *, out_dir, keep=None) -> list[Variant]:
    """Every combination of the ``--vary`` specs (texts, or Vary), validated by parse_job (JobError for
    the first bad one, before anything is written). Writes nothing. ``keep``: a test of a combination's
    values (dict key -> value); the combinations it rejects are left out, and the others keep their
    numbers in the full product (a phase of a sweep, study/sweep.py)."""
    job_path, out_dir = pathlib.Path(job_path), pathlib.Path(out_dir)
    base = load_job(job_path)
    data0 = tomllib.loads(base.text)
    varies = [s if isinstance(s, Vary) else parse_vary(s) for s in specs]
    total = math.prod(len(v.values) for v in varies)
    shown = tuple(v.key for v in varies if len(v.values) > 1) or tuple(v.key for v in varies)
    seen = set()
    for v in varies:
        if v.key in seen:
            raise JobError(f"--vary {v.key}: given twice; list all its values in one --vary")
        seen.add(v.key)
        check_key(base, v)
    variants = []
    for k, combo in enumerate(itertools.product(*(v.values for v in varies))):
        values = {v.key: value for v, value in zip(varies, combo)}
        if keep is not None and not keep(values):
            continue
        label = f"{job_path} with " + ", ".join(f"{key} = {show_value(x)}" for key, x in values.items())
        data = copy.deepcopy(data0)
        for v, value in zip(varies, combo):
            set_value(data, base, v.path, value)
        toml, run = out_dir / f"{job_path.stem}_{k}.toml", out_dir / f"{job_path.stem}_{k}.h5"
        _own_paths(data, job_path.parent, run, job_path.stem)
        text = toml_text(data, header=f"pice study variant {k} of {job_path}: "
                         + ", ".join(f"{key} = {show_value(x)}" for key, x in values.items())
                         + f"\nrun it again: pice run {toml} --overwrite")
        job = parse_job(tomllib.loads(text), source=label, text=text, base_dir=job_path.parent)
        variants.append(Variant(index=k, values=values, job=job.model_copy(update={"source": str(toml)}),
                                text=text, toml=toml, run=run, label=label, total=total,
                                shown=shown))
    return variants


def show_value(value) -> str:
    """A value for tables and labels: 0.0001, auto, true, [1.0, 0.0]."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return f"{value:g}"
    if isinstance(value, list):
        return "[" + ", ".join(show_value(v) for v in value) + "]"
    return str(value)
