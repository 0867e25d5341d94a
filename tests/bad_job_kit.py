"""The kit of the bad-input table (tests/bad_jobs.py), not a test module: the small valid job
``BASE`` the cases break, the scene fragments they add (water, walls, floes, waves, bodies, moorings),
``sub``/``add`` to edit a job's lines, ``Case``/``case``, and the helpers that write a case's files and
check its error lines.
"""

from __future__ import annotations

import dataclasses
import pathlib
import re

import pytest

# A tiny valid job (12 elements, one layer), with the stiffness and strengths of jobs/level_ice_demo.toml.
BASE = """\
[run]
name = "tiny"
duration = 0.01
snapshots = 1

[ice]
density = 920.0
thickness = 1.0
element_diameter = 1.0
length = 4.0
width = 3.0
youngs_modulus = 1.0e9
poissons_ratio = 0.3
flexural_strength = 0.5e6
compressive_strength = 2.0e6

[bond]
damping_ratio = 0.05

[contact]
restitution = 0.3
friction = 0.15
"""


def sub(old: str, new: str, text: str = BASE) -> str:
    """``text`` with the one line ``old`` replaced by ``new`` ('' removes it)."""
    lines = text.splitlines(keepends=True)
    hits = [i for i, line in enumerate(lines) if line.rstrip("\n") == old]
    assert len(hits) == 1, f"{old!r} is not exactly one line of the base job"
    lines[hits[0]] = new + "\n" if new else ""
    return "".join(lines)


def add(section: str, line: str, text: str = BASE) -> str:
    """``text`` with ``line`` added at the top of ``[section]`` ('' = the top level)."""
    if not section:
        return line + "\n" + text
    header = f"[{section}]\n"
    assert header in text, section
    return text.replace(header, header + line + "\n", 1)


@dataclasses.dataclass
class Case:
    id: str
    toml: str | bytes | None  # None: the job file does not exist; bytes: written as they are
    expect: list  # one entry per error line: a list of substrings / compiled regexes the line must contain
    files: dict = dataclasses.field(default_factory=dict)  # extra input files next to the job
    setup: bool = False  # fails during set-up (after validation), not in pice/job/


def case(id, toml, *expect, files=None, setup=False, lines=None):
    """One broken job. ``expect``: substrings of its one error line; ``lines``: several lines instead."""
    return Case(id, toml, lines or [list(expect)], files or {}, setup)


PLANE = '[[walls]]\ntype = "plane"\npoint = [0.0, 0.0, -5.0]\n'
WATER = "[water]\ndepth = 50.0\n"
NO_ICE = BASE[:BASE.index("[ice]")] + BASE[BASE.index("[bond]"):]
FLOES = "[floes]\narea = [0.0, 0.0, 100.0, 50.0]\nconcentration = 0.5\n"
WAVES = '[waves]\nspectrum = "regular"\nheight = 1.0\nperiod = 8.0\n'
BODY = """[[bodies]]
name = "barge"
hull = {type = "box", size = [10.0, 8.0, 4.0]}
mass = "balance"
inertia = [1.0e7, 2.0e7, 3.0e7]
position = [12.0, 1.5, 0.0]
"""
MOORING = """[[moorings]]
body = "barge"
fairleads = [[17.0, 1.5, -2.0]]
headings = [0.0]
anchor_depth = 48.0
pretension = 5.0e3
[[moorings.segments]]
length = 100.0
ea = 1.0e8
diameter = 0.05
wet_weight = 100.0
"""
BUOY = """[[bodies]]
name = "buoy"
hull = {type = "buoy", d_max = 9.0, alpha = 45.0, height = 3.0}
mass = "shell"
shell_thickness = 0.0619
position = "afloat"
"""
SHIP = """[[bodies]]
name = "uikku"
hull = {type = "ship", length = 150.0, midbody = 67.5, breadth = 22.2, draft = 9.5, waterline_angle = 25.2, stem_angle = 29.7}
mass = 2.1e7
inertia = [1.0e9, 3.0e10, 3.0e10]
position = [200.0, 0.0, 0.0]
motion = "prescribed"
velocity = [[0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0]]
"""
NUMBER_S = r"\d+(\.\d+)?(e-?\d+)? s"  # a time in seconds as printed



def params(cases):
    """pytest parameters of the cases, the validation ones marked ``nojit``."""
    return [pytest.param(c, id=c.id, marks=() if c.setup else pytest.mark.nojit) for c in cases]


def write_job(folder: pathlib.Path, c: Case) -> pathlib.Path:
    """The case's job file (and extra input files) in ``folder``; returns the job's path."""
    path = folder / ("x.toml" if c.toml is not None else "missing.toml")
    if isinstance(c.toml, bytes):
        path.write_bytes(c.toml)
    elif c.toml is not None:
        path.write_text(c.toml, encoding="utf-8")
    for name, data in c.files.items():
        (folder / name).write_bytes(data)
    return path


def inputs(c: Case) -> set[str]:
    """Names of the files the case writes (nothing else may be in its folder afterwards)."""
    return ({"x.toml"} if c.toml is not None else set()) | set(c.files)


def check_error_lines(err: str, path: pathlib.Path, c: Case) -> None:
    """``err`` is the case's lines: each starts with the job's path and holds what the case expects."""
    assert "Traceback" not in err, err
    assert err.endswith("\n"), repr(err)
    lines = err.splitlines()
    assert len(lines) == len(c.expect), f"expected {len(c.expect)} line(s), got:\n{err}"
    for line, expect in zip(lines, c.expect):
        assert line.startswith(f"{path}: "), line
        for part in expect:
            if isinstance(part, re.Pattern):
                assert part.search(line), f"{part.pattern!r} not in {line!r}"
            else:
                assert part in line, f"{part!r} not in {line!r}"
