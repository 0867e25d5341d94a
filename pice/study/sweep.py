"""A sweep file: a study whose designs pass through phases, each phase running only the designs that
passed every phase before it (issue 16; the buoy optimisation of Cai 2018, seed 004 chapter 6).

``pice study jobs/cai_2018_buoy_sweep.toml`` reads a TOML file with one ``[study]`` table::

    [study]
    job = "cai_2018_buoy.toml"          # relative to the sweep file
    group_size = 1                      # optional: pice study --group-size
    minimize = "mass_kg"                # optional: the objective, a metric of the CSV
    [study.vary]                        # the designs: every combination
    "bodies[0].hull.d_max" = [7.0, 7.5]
    [study.set]                         # optional: one value for every design and phase
    "bodies[0].shell_thickness" = 0.0619
    [[study.phases]]
    name = "normal"                     # its runs go to <out>/normal/
    criteria = ["max_heel_deg < 90"]    # as --criterion
    set = {"run.duration" = 0.1}        # optional: this phase's own values
    settle = 0.0                        # optional: as --settle

Each phase is an ordinary study (study/runner.run_study) in ``<out>/<phase>/``: its runs, report and
resume after a kill are those of ``pice study``. A design goes on to the next phase when its run
passed every criterion of this one. ``sweep.csv`` and ``sweep.json`` in ``<out>`` then list every
design, each phase's verdict, and, with ``minimize``, the selected design: the one of least objective
among those that passed every phase. Everything is checked before anything runs: every phase's
variants are built and validated (parse_job), every criterion parsed.
"""

from __future__ import annotations

import csv
import json
import math
import pathlib
from typing import Any, Optional

from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator

from ..errors import JobError
from ..io.errors import OutputError
from ..job.messages import error_lines
from ..parallel.comm import on_root, world
from .criteria import COLUMNS, parse_criterion
from .variants import Vary, key_path, make_variants, show_value

try:  # Python >= 3.11
    import tomllib
except ModuleNotFoundError:  # pragma: no cover
    import tomli as tomllib


class Phase(BaseModel):
    """One phase: its name (its folder), its criteria, the values it sets for itself."""

    model_config = ConfigDict(extra="forbid")
    name: str = Field(pattern=r"^[A-Za-z0-9_-]+$")
    criteria: list[str] = []
    set: dict[str, Any] = {}
    settle: float = Field(0.0, ge=0.0)  # [s]


class Study(BaseModel):
    """The ``[study]`` table (module docstring)."""

    model_config = ConfigDict(extra="forbid")
    job: str
    vary: dict[str, list[Any]] = Field(min_length=1)
    set: dict[str, Any] = {}
    phases: list[Phase] = Field(min_length=1)
    group_size: Optional[int] = Field(None, ge=1)
    minimize: Optional[str] = None
    out: Optional[str] = None

    @field_validator("vary")
    @classmethod
    def _values(cls, vary):
        for key, values in vary.items():
            if not values:
                raise ValueError(f"{key} has no values: list at least one")
        return vary

    @field_validator("phases")
    @classmethod
    def _names(cls, phases):
        names = [p.name for p in phases]
        if len(set(names)) != len(names):
            raise ValueError(f"phase names must differ: {', '.join(names)}")
        return phases

    @field_validator("minimize")
    @classmethod
    def _metric(cls, name):
        if name is not None and name not in COLUMNS:
            raise ValueError(f"no metric {name!r}; one of {', '.join(COLUMNS)}")
        return name


class SweepFile(BaseModel):
    model_config = ConfigDict(extra="forbid")
    study: Study


def is_sweep_file(path) -> bool:
    """True when ``path`` is a TOML file with a top-level [study] table (a job has none)."""
    try:
        return "study" in tomllib.loads(pathlib.Path(path).read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError):
        return False


def load_sweep(path) -> Study:
    """The validated [study] of the sweep file ``path``; JobError naming the key and the fix."""
    path = pathlib.Path(path)
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except OSError as exc:
        raise JobError(f"{path}: cannot read the sweep file ({exc.strerror or exc})") from None
    except tomllib.TOMLDecodeError as exc:
        raise JobError(f"{path}: not valid TOML: {exc}") from None
    try:
        study = SweepFile.model_validate(data).study
    except ValidationError as exc:
        raise JobError(error_lines(exc, source=str(path), root=SweepFile)) from None
    for phase in study.phases:
        both = (set(study.vary) | set(study.set)) & set(phase.set)
        if both or set(study.vary) & set(study.set):
            key = sorted(both or set(study.vary) & set(study.set))[0]
            raise JobError(f"{path}: {key} is given twice (in [study.vary], [study.set] or a phase's set): "
                           "give each key once")
    return study


def _design(values: dict, keys) -> str:
    """A design's identity across phases: its values of the [study.vary] keys."""
    return json.dumps([values[k] for k in keys])


def _phase_specs(study: Study, phase: Phase) -> list[Vary]:
    fixed = {**study.set, **phase.set}
    return ([Vary(k, key_path(k), tuple(v)) for k, v in study.vary.items()]
            + [Vary(k, key_path(k), (v,)) for k, v in fixed.items()])


def run_sweep(path, *, out_dir=None, group_size: int | None = None, progress="stderr", comm=None) -> dict | None:
    """Run the phases of the sweep file ``path`` (collective); return the sweep's summary on rank 0,
    None on the others. ``out_dir``, ``group_size``: the command line's, else the file's."""
    import sys

    from .runner import run_study

    progress = sys.stderr if progress == "stderr" else progress
    comm = comm if comm is not None else world()
    path = pathlib.Path(path)
    study = load_sweep(path)
    job_path = path.parent / study.job
    out = pathlib.Path(out_dir or (path.parent / study.out if study.out else pathlib.Path("runs") / path.stem))
    group_size = group_size or study.group_size
    keys = list(study.vary)
    for phase in study.phases:  # every phase checked before the first runs
        for text in phase.criteria:
            parse_criterion(text)
        make_variants(job_path, _phase_specs(study, phase), out_dir=out / phase.name)
    designs = make_variants(job_path, _phase_specs(study, study.phases[0]), out_dir=out)
    verdict = {_design(v.values, keys): {} for v in designs}
    objective = {}
    passed = None  # the designs still in the sweep (None: all)
    for phase in study.phases:
        if passed is not None and not passed:
            break
        if progress is not None and comm.rank == 0:
            n = len(verdict) if passed is None else len(passed)
            print(f"pice study: phase {phase.name}: {n} design(s) in {out / phase.name}", file=progress, flush=True)
        left = passed
        result = run_study(job_path, _phase_specs(study, phase), out_dir=out / phase.name, criteria=phase.criteria,
                           settle=phase.settle, group_size=group_size, progress=progress, comm=comm,
                           keep=None if left is None else (lambda values: _design(values, keys) in left))
        if comm.rank == 0:
            for row in result["variants"]:
                d = _design(row["values"], keys)
                verdict[d][phase.name] = "pass" if row["passed"] else "fail: " + "; ".join(row["failed"])
                if study.minimize:
                    objective[d] = row["metrics"].get(COLUMNS[study.minimize], math.nan)
        passed = comm.bcast({d for d, v in verdict.items() if v.get(phase.name) == "pass"} if comm.rank == 0 else None)

    def report():
        return write_sweep(study, path, out, designs, keys, verdict, objective, passed or set())

    def translate(exc):
        if isinstance(exc, OSError):
            return OutputError(f"{out}: cannot write the sweep's report ({exc.strerror or exc}); choose another "
                               "folder with --out DIR")
        return None

    return on_root(comm, report, translate=translate)


def write_sweep(study: Study, path, out: pathlib.Path, designs, keys, verdict, objective, passed) -> dict:
    """sweep.csv and sweep.json in ``out``: every design's verdict per phase (pass, fail: why, or
    "not run" when an earlier phase dropped it), its objective, and the selected design."""
    names = [p.name for p in study.phases]
    rows = []
    for v in designs:
        d = _design(v.values, keys)
        row = {k: v.values[k] for k in keys}
        row.update({name: verdict[d].get(name, "not run") for name in names})
        row["passed"] = d in passed and all(verdict[d].get(name) == "pass" for name in names)
        if study.minimize:
            row[study.minimize] = objective.get(d, math.nan)
        rows.append(row)
    kept = [r for r in rows if r["passed"]]
    selected = None
    if study.minimize and kept:
        selected = min(kept, key=lambda r: r[study.minimize])
    summary = dict(sweep=str(path), job=study.job, out_dir=str(out), phases=names, vary=keys,
                   minimize=study.minimize, designs=rows, passed=len(kept), selected=selected)
    with open(out / "sweep.csv", "w", newline="", encoding="utf-8") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows({k: show_value(x) if k in keys else x for k, x in r.items()} for r in rows)
    safe = json.loads(json.dumps(summary, default=str).replace("NaN", "null"))
    (out / "sweep.json").write_text(json.dumps(safe, indent=2) + "\n", encoding="utf-8")
    summary["files"] = [str(out / "sweep.csv"), str(out / "sweep.json")]
    return summary


def sweep_table(summary: dict) -> list[str]:
    """The printed summary: one line per design, its verdict per phase; the selected design last."""
    keys, names = summary["vary"], summary["phases"]
    head = [*keys, *names] + ([summary["minimize"]] if summary["minimize"] else [])
    body = []
    for r in summary["designs"]:
        cells = [show_value(r[k]) for k in keys] + [r[n] for n in names]
        if summary["minimize"]:
            cells.append(f"{r[summary['minimize']]:.6g}")
        body.append(cells)
    widths = [max(len(c[i]) for c in [head, *body]) for i in range(len(head))]
    lines = ["  ".join(c.ljust(w) for c, w in zip(r, widths)).rstrip() for r in [head, *body]]
    lines.append(f"{summary['passed']} of {len(body)} design(s) passed every phase")
    sel = summary["selected"]
    if sel is not None:
        lines.append("selected (least " + summary["minimize"] + "): "
                     + ", ".join(f"{k} = {show_value(sel[k])}" for k in keys) + f": {sel[summary['minimize']]:.6g}")
    return lines
