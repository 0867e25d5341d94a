"""The settled keel file (issue 15: "save the settled keel, so that many ship runs start from one
generation"): the blocks that ``pice keel`` settled and trimmed, with what generation measured.

HDF5: ``rects`` (n, 4, 2) [m] each block's rectangle in its principal frame, ``x`` (n, 3) [m] its
centre, ``q`` (n, 4) its attitude; attributes: the [keel] it was generated from (JSON, the key
``keel``), the porosity of the keel and of its core, the time it took to settle [s], the RMS speed
then [m/s], the number released, the time the staged settling's friction returned (``locked_at``
[s], NaN without keel.lock_speed), ``format``, and what made it: ``pice_version`` and ``commit`` (the
work tree's, "" outside a git checkout; a keel file kept in the repository, jobs/keels/, names the
code that generated it). Written to a temporary name and renamed, so a
killed generation leaves no half file.

The generation checkpoint (``generation_path``: the keel file's name + ".gen.h5"): the settling
blocks' state (physics/floe_system.FloeSystem.state) and the time reached, written at every check of
their speed, so that `pice keel` continues a killed generation, or one that had not settled in
keel.settle_time, where it stopped. It is continued for the same [keel] only, its contact and step
included (keel.settle_time and keel.settle_speed may change: they decide when to stop, not how the
blocks move; so may keel.lock_speed until the staged settling's friction has returned, as it decides
when that happens: a pile whose speed decays slowly can be locked sooner, and the keel file records
when it was, locked_at); a checkpoint of another is refused, not overwritten, with the keys that
differ named.
It is removed once the keel file is written.
"""

from __future__ import annotations

import json
import math
import os
import pathlib

import numpy as np

from .. import __version__
from ..errors import JobError
from ..provenance import commit_label

KEEL_FORMAT = 1
# keys of [keel] a ship run may change against its keel's generation (the contact: seed 002 runs each
# pile with mu_i 0.3 and 0.6; the file, the run's own step and its end)
RUN_KEYS = ("contact", "file", "step_fraction", "form_drag_coefficient", "end_after_peak")
# keys of [keel] a keel trimmed from a wider one (keel.trim_from) may have of its own: its shape's width
# and place, the key that names the wider keel, and settle_time (a limit, which the wider keel's
# generation met); the others must be the wider keel's
TRIM_KEYS = ("width", "x", "trim_from", "settle_time")


def keel_path(job, base_dir=None) -> pathlib.Path:
    """The job's keel file: keel.file, relative to the job's folder, else <job>.keel.h5 beside the job."""
    base = pathlib.Path(base_dir or ".")
    name = job.keel.file or f"{pathlib.Path(job.source).stem or job.run.name}.keel.h5"
    return base / name


def _generation_keys(keel) -> dict:
    """The [keel] keys a generation depends on; an optional key left unset (None) is left out, so that
    files written before it existed still match (keel.settle_friction)."""
    return {k: v for k, v in keel.model_dump(mode="json").items() if k not in RUN_KEYS and v is not None}


def write_keel(path, keel, result) -> pathlib.Path:
    """Write ``result`` (physics.keel.Keel) generated from ``keel`` (KeelSpec) to ``path``."""
    import h5py

    path = pathlib.Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.name + ".tmp")
    with h5py.File(tmp, "w") as f:
        f["rects"], f["x"], f["q"] = result.rects, result.x, result.q
        f.attrs.update(format=KEEL_FORMAT, keel=json.dumps(_generation_keys(keel)),
                       contact=json.dumps(keel.contact.model_dump(mode="json")), porosity=result.porosity,
                       core_porosity=result.core_porosity, settle_time=result.settle_time, locked_at=result.locked_at,
                       rms_speed=result.rms_speed, released=result.released, pice_version=__version__,
                       commit=commit_label())
    os.replace(tmp, path)
    return path


def read_keel_file(path, fix: str, what: str = "keel.file") -> dict:
    """The blocks and records of the keel file at ``path``, whatever keel it was generated from (its
    [keel] keys as ``made``); JobError naming ``what`` and ``fix`` when it is missing or unreadable."""
    import h5py

    path = pathlib.Path(path)
    if not path.exists():
        raise JobError(f"{what} = {str(path)!r}: not found; {fix}")
    try:
        with h5py.File(path, "r") as f:
            out = {k: f[k][()] for k in ("rects", "x", "q")}
            attrs = dict(f.attrs)
    except (OSError, KeyError) as exc:
        raise JobError(f"{what} = {str(path)!r}: not a keel file ({exc}); {fix}") from None
    if int(attrs.get("format", 0)) != KEEL_FORMAT:
        raise JobError(f"{what} = {str(path)!r}: format {attrs.get('format')}, not {KEEL_FORMAT}; {fix}")
    out.update(made=json.loads(attrs["keel"]), porosity=float(attrs["porosity"]),
               core_porosity=float(attrs["core_porosity"]), settle_time=float(attrs["settle_time"]),
               rms_speed=float(attrs.get("rms_speed", math.nan)), locked_at=float(attrs.get("locked_at", math.nan)),
               released=int(attrs["released"]), contact=json.loads(attrs["contact"]))
    out["rects"], out["x"], out["q"] = (np.asarray(out[k], float) for k in ("rects", "x", "q"))
    return out


def read_keel(path, keel, source: str) -> dict:
    """The blocks and records of the keel file at ``path`` for the job's ``keel``; JobError when it is
    missing, unreadable, or generated from another keel (the keys that differ are named)."""
    fix = f"generate it: pice keel {source}"
    out = read_keel_file(path, fix, f"{source}: keel.file")
    made, want = out.pop("made"), _generation_keys(keel)
    differ = sorted(k for k in set(made) | set(want) if made.get(k) != want.get(k))
    if differ:
        keys = ", keel.".join(differ)
        raise JobError(f"{source}: keel.file = {str(path)!r}: generated from another keel (keel.{keys} differ); "
                       f"give its own file (keel.file) or {fix}")
    return out


def read_trim_source(job, base_dir=None) -> dict:
    """The wider keel that the job's keel is trimmed from (keel.trim_from, relative to the job's folder),
    as read_keel_file gives it, with its ``path``; JobError when it is missing, or was generated from
    other blocks, depth, angle, length, cover, seed or settling than the job's [keel] (the keys that
    differ are named: only TRIM_KEYS may), or is narrower than the job's keel."""
    keel, source = job.keel, job.source
    path = pathlib.Path(base_dir or ".") / keel.trim_from
    fix = "generate the wider keel first (pice keel on its job), or give keel.trim_from its file"
    out = read_keel_file(path, fix, f"{source}: keel.trim_from")
    made, want = out.pop("made"), _generation_keys(keel)
    differ = sorted(k for k in set(made) | set(want) if k not in TRIM_KEYS and made.get(k) != want.get(k))
    if differ:
        keys = ", keel.".join(differ)
        raise JobError(f"{source}: keel.trim_from = {str(path)!r}: generated from another keel (keel.{keys} differ); "
                       "a keel is trimmed only from one of the same blocks, depth, pile_angle, length, cover, seed "
                       "and settling: give those keys the wider keel's values")
    if made["width"] < keel.width:
        raise JobError(f"{source}: keel.trim_from = {str(path)!r}: is {made['width']:g} m wide, narrower than this "
                       f"keel's keel.width = {keel.width:g} m; trim from a keel at least as wide")
    out.update(path=path, width=float(made["width"]), x_centre=float(made.get("x", 0.0)))
    return out


# keys of [keel] that decide when the settling stops, not how the blocks move: a generation checkpoint
# written under other values is continued (and under another lock_speed while it has not locked)
_STOP_KEYS = ("settle_time", "settle_speed")


def generation_path(path) -> pathlib.Path:
    """The generation checkpoint beside the keel file ``path``."""
    path = pathlib.Path(path)
    return path.with_name(path.name + ".gen.h5")


def _settling_run_keys(keel) -> str:
    """The keel file's run keys that the settling depends on too (the contact law, the step)."""
    return json.dumps({k: v for k, v in keel.model_dump(mode="json").items() if k in ("contact", "step_fraction")},
                      sort_keys=True)


def write_generation(path, keel, t: float, state: dict) -> None:
    """The settling blocks' ``state`` at time ``t`` [s] to the generation checkpoint ``path`` (atomic)."""
    import h5py

    path = pathlib.Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.name + ".tmp")
    with h5py.File(tmp, "w") as f:
        for name, value in state.items():
            f[name] = np.asarray(value)
        f.attrs.update(format=KEEL_FORMAT, keel=json.dumps(_generation_keys(keel), sort_keys=True),
                       run_keys=_settling_run_keys(keel), time=float(t))
    os.replace(tmp, path)


def read_generation(path, keel, source: str = "job"):
    """(t [s], state) of the generation checkpoint at ``path`` when it was written for this [keel], else
    None (no file, or not readable: the generation starts afresh); JobError when it was written for
    another keel, naming the keys that differ (a checkpoint written before its contact and step were
    recorded is taken on its [keel] alone)."""
    import h5py

    path = pathlib.Path(path)
    if not path.exists():
        return None
    try:
        with h5py.File(path, "r") as f:
            if int(f.attrs.get("format", 0)) != KEEL_FORMAT:
                return None
            made, want = json.loads(f.attrs["keel"]), _generation_keys(keel)
            locked = "locked_at" in f and math.isfinite(float(f["locked_at"][()]))
            free = _STOP_KEYS if locked else _STOP_KEYS + ("lock_speed",)
            made, want = ({k: v for k, v in d.items() if k not in free} for d in (made, want))
            run = f.attrs.get("run_keys")  # absent from checkpoints written before it: [keel] alone
            if run is not None:
                made.update(json.loads(run))
                want.update(json.loads(_settling_run_keys(keel)))
            differ = sorted(k for k in set(made) | set(want) if made.get(k) != want.get(k))
            if not differ:
                return float(f.attrs["time"]), {k: f[k][()] for k in f.keys()}
    except (OSError, KeyError, ValueError):
        return None
    raise JobError(f"{source}: {str(path)!r}: a generation checkpoint of another keel (keel.{', keel.'.join(differ)} "
                   "differ); give those keys back to continue it, or remove it to start afresh")
