"""`pice study`: run variants of one job and weigh their cost against what designers read off them.

``pice study jobs/x.toml --vary run.dt=1e-4,2e-4 --vary ice.element_diameter=1.0,2.0`` makes the
Cartesian product of the values (4 variants) and validates every one, including the set-up checks
that need the built scene (the stability limit of run.dt), before anything runs. Each variant is
written as ``<out>/x_<k>.toml`` (a job you can run again; its run.output is ``<out>/x_<k>.h5``) and
run to ``<out>/x_<k>.h5``, one after the other inside this MPI job (run_job is collective: under
``mpiexec -n 2`` every variant runs on 2 ranks). Rank 0 then reads the metrics of each run file
(peak ice loads [N], offsets [m], fairlead tension [N]: pice/study_report.py), compares them with
the reference variant (by default the finest: the most particle-steps) and writes the report.

Cost: ``wall_time`` [s] of the time loop as run_job measures it (set-up excluded; every variant is
set up and stepped twice beforehand, so numba's compile time falls on none of them) and
``particle_steps`` = elements x steps.
"""

from __future__ import annotations

import copy
import dataclasses
import itertools
import math
import pathlib
import re
import sys

from .errors import JobError, PiceError
from .io.toml_text import toml_text
from .job import load_job, parse_job
from .study_report import METRICS, compare, run_metrics, show_value

try:  # Python >= 3.11
    import tomllib
except ModuleNotFoundError:  # pragma: no cover
    import tomli as tomllib

_NAME = r"[A-Za-z_][A-Za-z0-9_-]*"
_KEY_PATH = re.compile(rf"^{_NAME}(\[\d+\])*(\.{_NAME}(\[\d+\])*)*$")
WARM_UP_STEPS = 2  # steps each variant takes before the runs, to compile the kernels (not timed)
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


def _own_paths(data: dict, base_dir: pathlib.Path, run: pathlib.Path) -> None:
    """Make a variant self-contained: its run file is ``run`` (run.output), its checkpoint the default
    beside it, and mesh files are absolute (the variant lives in another folder than the job)."""
    data.setdefault("run", {})["output"] = str(run)
    data["run"].pop("checkpoint", None)
    for wall in data.get("walls", []):
        if isinstance(wall.get("file"), str):
            wall["file"] = str((base_dir / wall["file"]).resolve())
    for body in data.get("bodies", []):
        hull = body.get("hull")
        if isinstance(hull, dict) and isinstance(hull.get("file"), str):
            hull["file"] = str((base_dir / hull["file"]).resolve())


def make_variants(job_path, specs: list[str], *, out_dir) -> list[Variant]:
    """Every combination of the ``--vary`` specs, validated by parse_job (JobError for the first bad
    one, before anything is written). Writes nothing."""
    job_path, out_dir = pathlib.Path(job_path), pathlib.Path(out_dir)
    base = load_job(job_path)
    data0 = tomllib.loads(base.text)
    varies = [parse_vary(s) for s in specs]
    seen = set()
    for v in varies:
        if v.key in seen:
            raise JobError(f"--vary {v.key}: given twice; list all its values in one --vary")
        seen.add(v.key)
        check_key(base, v)
    variants = []
    for k, combo in enumerate(itertools.product(*(v.values for v in varies))):
        values = {v.key: value for v, value in zip(varies, combo)}
        label = f"{job_path} with " + ", ".join(f"{key} = {show_value(x)}" for key, x in values.items())
        data = copy.deepcopy(data0)
        for v, value in zip(varies, combo):
            set_value(data, base, v.path, value)
        toml, run = out_dir / f"{job_path.stem}_{k}.toml", out_dir / f"{job_path.stem}_{k}.h5"
        _own_paths(data, job_path.parent, run)
        text = toml_text(data, header=f"pice study variant {k} of {job_path}: "
                         + ", ".join(f"{key} = {show_value(x)}" for key, x in values.items())
                         + f"\nrun it again: pice run {toml} --overwrite")
        job = parse_job(tomllib.loads(text), source=label, text=text, base_dir=job_path.parent)
        variants.append(Variant(index=k, values=values, job=job.model_copy(update={"source": str(toml)}),
                                text=text, toml=toml, run=run, label=label))
    return variants


def _preflight(variants: list[Variant], *, out_dir, comm) -> None:
    """Set every variant up and advance it WARM_UP_STEPS (collective), writing nothing: the checks
    that need the built scene (the stability limit of run.dt, overlaps, regions) fail here, before
    the first run, and numba has loaded or compiled every kernel before the timed runs."""
    from .simulation import Simulation

    for v in variants:
        sim = Simulation(v.job.model_copy(update={"source": v.label}), base_dir=out_dir, comm=comm)
        sim.advance(min(WARM_UP_STEPS, sim.total_steps))


def run_study(job_path, specs: list[str], *, out_dir=None, reference: int | None = None, settle: float = 0.0,
              progress=sys.stderr, comm=None) -> dict | None:
    """Run every variant (collective) and write the report; return the study dict on rank 0, None on
    the others. ``settle`` [s]: offsets are taken over t >= settle. Bad input raises JobError
    before anything is written or run."""
    from .io.run_file import OutputError
    from .parallel.comm import world
    from .runner import run_job

    comm = comm if comm is not None else world()
    job_path = pathlib.Path(job_path)
    out_dir = pathlib.Path(out_dir) if out_dir else pathlib.Path("runs") / f"{job_path.stem}_study"
    if not settle >= 0.0 or math.isinf(settle):
        raise JobError(f"--settle {settle}: must be a time >= 0 s")
    variants = make_variants(job_path, specs, out_dir=out_dir)
    if reference is not None and not 0 <= reference < len(variants):
        raise JobError(f"--reference {reference}: must be a variant number 0..{len(variants) - 1}")
    _preflight(variants, out_dir=out_dir, comm=comm)
    _on_rank0(comm, lambda: _write_jobs(out_dir, variants), OutputError, f"{out_dir}: cannot write the variants")
    if comm.rank != 0:
        progress = None
    rows = []
    for v in variants:
        if progress is not None:
            print(f"pice study: variant {v.index} of 0..{len(variants) - 1}: "
                  + ", ".join(f"{k} = {show_value(x)}" for k, x in v.values.items()) + f" -> {v.run}",
                  file=progress, flush=True)
        summary = run_job(v.job, output=str(v.run), overwrite=True, base_dir=out_dir, progress=progress, comm=comm)
        rows.append(dict(variant=v.index, values=v.values, toml=str(v.toml), run=str(v.run),
                         wall_time=summary["wall_time"], steps=summary["steps"], elements=summary["elements"],
                         particle_steps=summary["elements"] * summary["steps"],
                         particle_steps_per_second=summary["particle_steps_per_second"], ranks=summary["ranks"]))

    def report():
        from .study_report import write_report

        for row in rows:
            row["metrics"] = run_metrics(row["run"], settle=settle)
        ref = compare(rows, reference)
        study = dict(job=str(job_path), out_dir=str(out_dir), varied=list(variants[0].values),
                     reference=ref, reference_rule="--reference" if reference is not None else "most particle-steps",
                     loads_on="body 0" if variants[0].job.bodies else "the walls (sum)",
                     settle=settle, units={name: unit for name, unit, _ in METRICS}, variants=rows)
        study["files"] = [str(p) for p in write_report(study, out_dir)]
        return study

    return _on_rank0(comm, report, OutputError, f"{out_dir}: cannot write the study report")


def _write_jobs(out_dir: pathlib.Path, variants: list[Variant]) -> None:
    out_dir.mkdir(parents=True, exist_ok=True)
    for v in variants:
        v.toml.write_text(v.text, encoding="utf-8")


def _on_rank0(comm, work, error_type, what: str):
    """``work()`` on rank 0; a PiceError or OSError there is raised on every rank (as ``error_type``)."""
    result, error = None, None
    if comm.rank == 0:
        try:
            result = work()
        except PiceError as exc:
            error = exc
        except OSError as exc:
            error = error_type(f"{what} ({exc.strerror or exc}); choose another folder with --out DIR")
    error = comm.bcast(error)
    if error is not None:
        raise error
    return result
