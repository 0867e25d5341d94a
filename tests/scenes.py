"""Small scenes shared by the tests (not a test module): job texts and the builders that parse them.

Every test folder (unit, physics, parallel, io) imports this as ``scenes``: tests/conftest.py puts
tests/ on sys.path.

* ``slope_job``: a 6 m x 4 m sheet carried at 1 m/s onto a 45-degree plane (run file, export,
  study, checkpoint tests);
* ``barge_job``: 12 m x 10 m of 1 m ice hitting a moored 20 m x 16 m x 6 m box barge (platform
  coupling, output, extremes, the 1-rank vs 2-rank platform contract);
* ``contract_job``: the level-ice demo moved closer to its panel and driven faster, so that it
  breaks within 2,000 steps (the rank contract, checkpoints, parallel HDF5);
* ``job_from_text``: a TOML text parsed as a job, as `pice` reads a file (``tomllib``: the standard
  library's, or tomli on Python 3.10).
"""

from __future__ import annotations

import pathlib

from pice.job import parse_job

try:
    import tomllib
except ModuleNotFoundError:  # pragma: no cover
    import tomli as tomllib

REPO = pathlib.Path(__file__).resolve().parents[1]
JOBS = REPO / "jobs"


def job_from_text(text: str, *, source: str = "job.toml", base_dir: pathlib.Path | None = None):
    """The job of a TOML text (pice.job.parse_job on tomllib's reading, with the text kept)."""
    return parse_job(tomllib.loads(text), source=source, text=text, base_dir=base_dir)


def slope_job(*, duration: float, snapshots: int, series_every: int = 2, dt: float | None = None) -> str:
    """A 6 m x 4 m sheet of Table 4 bonds carried at 1 m/s onto a 45-degree plane: clear of the sheet
    at t = 0 and touched within 0.05 s. ``dt`` [s] replaces the automatic step."""
    step = "" if dt is None else f"dt = {dt!r}\n"
    return f"""\
[run]
duration = {duration}
{step}series_every = {series_every}
snapshots = {snapshots}
[water]
density = 1035.0
current = [1.0, 0.0]
[ice]
length = 6.0
width = 4.0
velocity = [1.0, 0.0]
[bond]
normal_stiffness = 1.72e7
normal_strength = 1.5e6
friction = 0.3
[[walls]]
name = "slope"
type = "plane"
point = [6.53, 0.0, 0.0]
normal = [-0.7071068, 0.0, 0.7071068]
"""


# 12 m x 10 m of 1 m ice at 1 m/s, its front 0.05 m from a 20 m x 16 m x 6 m box barge
_BARGE = """\
[run]
duration = {duration}
dt = 1.0e-4
series_every = {series_every}
snapshots = 3

[water]
density = 1025.0
current = [{current}, 0.0]
ice_drag = "morison"
drag_coefficient = {drag}
depth = 60.0

[ice]
thickness = 1.0
element_diameter = 1.0
length = 12.0
width = 10.0
origin = [0.0, -5.0]
velocity = [1.0, 0.0]
youngs_modulus = 1.0e9
flexural_strength = 0.3e6
compressive_strength = 1.5e6

[bond]
damping_ratio = 0.05

[[bodies]]
name = "barge"
hull = {{type = "box", size = [20.0, 16.0, 6.0]}}
mass = "balance"
inertia = [4.0e8, 6.0e8, 9.0e8]
position = [22.05, 0.3, 0.0]
{body_extra}
"""

# four 120 m lines at 45 degrees to the barge's sides, anchored 57 m below the fairleads, 20 kN pretension
_MOORING = """
[[moorings]]
body = "barge"
model = "{model}"
fairleads = [[32.05, 8.3, -3.0], [12.05, 8.3, -3.0], [12.05, -7.7, -3.0], [32.05, -7.7, -3.0]]
headings = [45.0, 135.0, 225.0, 315.0]
anchor_depth = 57.0
pretension = 20.0e3
element_length = 10.0
[[moorings.segments]]
length = 120.0
ea = 5.0e8
diameter = 0.05
wet_weight = 150.0
"""


def barge_job(*, duration=0.05, series_every=50, current=0.0, drag=0.0, body_extra="", mooring=None) -> str:
    """The barge scene's text; ``mooring`` = "dem" or "quasi_static" adds the four lines."""
    text = _BARGE.format(duration=duration, series_every=series_every, current=current, drag=drag,
                         body_extra=body_extra)
    return text + (_MOORING.format(model=mooring) if mooring else "")


def contract_job(folder: pathlib.Path, name: str = "contract", *, dt: float = 1.4e-4, duration: float = 0.28,
                 checkpoint_every: float | None = None, series_every: int = 500, snapshots: int = 3) -> pathlib.Path:
    """jobs/level_ice_demo.toml moved 0.45 m closer to its panel and driven at 2 m/s, so that it breaks
    within 2,000 steps (0.28 s at dt = 1.4e-4 s), with a rebalance every 400 steps; written to
    ``folder/name.toml`` (the folder is made), whose path is returned."""
    text = (JOBS / "level_ice_demo.toml").read_text()
    ckpt = "" if checkpoint_every is None else f"\ncheckpoint_every = {checkpoint_every!r}"
    for old, new in (("origin = [0.0, 0.0]", "origin = [0.45, 0.0]"),
                     ("velocity = [1.0, 0.0]", "velocity = [2.0, 0.0]"),
                     ("speed = 1.0 ", "speed = 2.0 "),
                     ('dt = "auto"', f"dt = {dt!r}"),
                     ("duration = 3.0 ", f"duration = {duration!r}{ckpt} "),
                     ("series_every = 500 ", f"series_every = {series_every} "),
                     ("snapshots = 11", f"snapshots = {snapshots}"),
                     ("[bond]\n", "[parallel]\nbalance_every = 400\n\n[bond]\n")):
        assert old in text, old
        text = text.replace(old, new)
    folder.mkdir(parents=True, exist_ok=True)
    job = folder / f"{name}.toml"
    job.write_text(text)
    return job


_VERTICAL_PLANE = "point = [0.0, 0.0, 0.0]\nnormal = [-1.0, 0.0, 0.0]"


def crushing_face_job(*, length: float, width: float, d: float, speed: float, stiffness: float, run: str,
                      structure: str = '"iso19906"', h: float = 1.0, parallel: str = "",
                      water: str = "density = 1025.0", flexural_strength: float = 0.5e6,
                      plane: str = _VERTICAL_PLANE) -> str:
    """A sheet of plate cells (1 GPa, nu 0.3, sigma_f `flexural_strength` [Pa], sigma_c 2.5 MPa)
    `length` x `width` [m] of elements `d` [m], its rear two rows on far-field springs (`stiffness`
    [N/m per element]) drifting at `speed` [m/s], its front 0.05 m behind x = 0, against a plane as
    wide as the sheet (`plane`: its point and normal lines; by default vertical through x = 0), with
    [crushing] (`structure`: "iso19906" or a pressure [Pa]). `run` and `water` are those tables' bodies."""
    return f"""\
[run]
{run}
[water]
{water}
[ice]
length = {length!r}
width = {width!r}
thickness = {h!r}
element_diameter = {d!r}
element_volume = "cell"
origin = [{-length - 0.05!r}, {-width / 2!r}]
velocity = [{speed!r}, 0.0]
youngs_modulus = 1.0e9
flexural_strength = {flexural_strength!r}
compressive_strength = 2.5e6
push = {{speed = {speed!r}, rows = 2, stiffness = {stiffness!r}}}
[bond]
damping_ratio = 0.1
[contact]
friction = 0.15
[crushing]
structure = {structure}
[[walls]]
type = "plane"
{plane}
friction = 0.15
crushing_width = {width!r}
{parallel}"""


def floe_job(*, duration: float = 4.0, series_every: int = 50, snapshots: int = 3, checkpoint_every: float = 0.0,
             waves: bool = False) -> str:
    """Broken ice (issue 14): 85 % of 20-30 m floes in a 0.4 m/s current between confining walls, a
    conical structure (Kulluk-like profile) pushed into them at 2 m/s (a prescribed body)."""
    sea = '[waves]\nspectrum = "regular"\nheight = 2.0\nperiod = 10.0\n' if waves else ""
    return f"""
[run]
name = "floes"
duration = {duration}
series_every = {series_every}
snapshots = {snapshots}
checkpoint_every = {checkpoint_every}

[water]
density = 1025.0
depth = 52.0
current = [0.4, 0.0]
{sea}
[floes]
area = [-140.0, -50.0, -38.0, 50.0]
concentration = 0.85
size = [20.0, 30.0]
velocity = [0.0, 0.0]
seed = 3
sides = "confined"

[[bodies]]
name = "cone"
hull = {{type = "revolved", profile = [[-12.5, 31.0], [0.0, 35.0], [3.4, 40.5]], segments = 24}}
mass = "balance"
inertia = [1e10, 1e10, 1e10]
position = [0.0, 0.0, 0.0]
motion = "prescribed"
velocity = [[0.0, -2.0, 0.0, 0.0, 0.0, 0.0, 0.0]]
"""


def bonded_floe_job(*, wall_x: float = 0.0, duration: float = 1.0, speed: float = 1.0, current: float = 1.0,
                    skin: float = 0.05, series_every: int = 200, snapshots: int = 3) -> str:
    """Breakable floes (issue 14): about three 8-10 m floes of 0.5 m plate cells (1 GPa, sigma_f
    0.5 MPa) in a 30 m x 12 m area ending at x = -0.2 m, drifting at `speed` [m/s] in a `current`
    [m/s] (skin drag coefficient `skin`) against a vertical plane at x = `wall_x` [m]."""
    return f"""
[run]
name = "bonded_floes"
duration = {duration!r}
series_every = {series_every}
snapshots = {snapshots}

[water]
density = 1025.0
current = [{current!r}, 0.0]
skin_drag_coefficient = {skin!r}

[floes]
area = [-30.2, -6.0, -0.2, 6.0]
concentration = 0.6
size = [8.0, 10.0]
seed = 2
velocity = [{speed!r}, 0.0]
breakable = true

[ice]
thickness = 0.5
element_diameter = 1.0
element_volume = "cell"
youngs_modulus = 1.0e9
flexural_strength = 0.5e6
compressive_strength = 2.5e6

[bond]
damping_ratio = 0.1

[contact]
friction = 0.15

[[walls]]
type = "plane"
point = [{wall_x!r}, 0.0, 0.0]
normal = [-1.0, 0.0, 0.0]
friction = 0.15
"""


# A sweep file (study/sweep.py) over three barge designs of 1, 2 and 3 kt next to barge_job(duration=0.01,
# mooring="dem") written as barge.toml: the first phase keeps mass < 2.5 kt, the second all upright.
BARGE_SWEEP = """\
[study]
job = "barge.toml"
minimize = "mass_kg"
[study.vary]
"bodies[0].mass" = [1.0e6, 2.0e6, 3.0e6]
[study.set]
"run.snapshots" = 2
[[study.phases]]
name = "light"
criteria = ["mass_kg < 2.5e6"]
[[study.phases]]
name = "upright"
criteria = ["max_heel_deg < 90"]
set = {"run.duration" = 0.02}
"""

# --- ridge keels (issue 15): a micro keel (3.5 m x 1.5 m, 1 m deep) and a half ship a twelfth of
# Uikku's size; `pice keel` settles the keel (tests/physics/test_keel.py's fixture), a run meets it
MICRO_KEEL = """
[run]
name = "micro"
duration = {duration}
series_every = 100

[water]
density = 1010.0

[keel]
width = 3.5
length = 1.5
depth = 1.0
seed = {seed}
settle_friction = 0.0
lock_speed = 0.03
file = "micro.keel.h5"
"""

MINI_SHIP = """
[[bodies]]
name = "bow"
hull = {type = "ship", length = 12.0, midbody = 4.0, breadth = 2.0, draft = 1.5, waterline_angle = 25.0, stem_angle = 30.0, half = true}
mass = 1.0e5
inertia = [1e5, 1e5, 1e5]
position = [-9.0, 0.0, 0.0]
motion = "prescribed"
velocity = [[0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0]]
friction = 0.1
"""


def ship_ends_job(*, duration: float = 30.0, checkpoint_every: float = 2.0) -> str:
    """The mini ship through the micro keel (its file micro.keel.h5 beside the job), ending once R is
    past its peak (keel.end_after_peak = 0.5): about 14 s of its duration, measured."""
    text = MICRO_KEEL.format(duration=duration, seed=1).replace(
        'file = "micro.keel.h5"', 'file = "micro.keel.h5"\nend_after_peak = 0.5') + MINI_SHIP
    return text.replace("series_every = 100", f"series_every = 100\ncheckpoint_every = {checkpoint_every}")
