"""Checkpoints: the whole state of a run in one HDF5 file, readable on any rank count.

Layout::

    /                attrs: format, format_version, pice_version, ranks, step, time, dt, job_text,
                     job_source, physics (the job without [run] and [parallel], as JSON), written,
                     wall_time (the time loop's seconds to this step, over the run's calls)
    /particles/<a>   every owned particle's per-particle arrays (state.PER_PARTICLE: positions,
                     velocities, bond and contact histories, force and torque of the last step),
                     sorted by gid
    /decomposition/  x_cuts, y_cuts of the ranks that wrote it
    /counters/       per writing rank: broken, contacts, contact_energy, wall_energy
    /events/         the broken-bond log so far: step, time, gid_a, gid_b, mode, rank (who logged it)
    /walls/total     (n_walls, 6) the reduced ice loads of the last step (when the job has walls)
    /platform/       rank 0's bodies (body<k>/x, v, q, L, force, torque), mooring lines
                     (group<k>/...), the ice loads of the last step and the bodies' clock
    /peaks/          rank 0's sums and extremes of the body loads since the last series row (n, ice_sum,
                     ice_max, ice_min, tension_max; absent when the checkpoint falls on a row)
    /far_field/      shift, velocity of a finite far field (ice.push.far_field_length)

Rank 0 writes ``path + ".tmp"``, flushes and fsyncs it, then renames it over ``path``: a run killed
at any moment leaves either the previous checkpoint or the new one, never a broken file.
"""

from __future__ import annotations

import datetime
import json
import os
import pathlib

import h5py
import numpy as np

from .. import __version__
from ..errors import PiceError
from ..parallel.comm import on_root
from ..state import PER_PARTICLE

FORMAT = "pice checkpoint"
FORMAT_VERSION = 3  # 2: hull contact history and /platform (1 reads as 'no bodies');
#                    3: contact histories carry the plastic penetration (2 reads with none)
COUNTERS = ("broken", "contacts", "contact_energy", "wall_energy")
EVENT_FIELDS = ("step", "time", "gid_a", "gid_b", "mode", "rank")


class CheckpointError(PiceError):
    """A checkpoint cannot be written, read, or does not fit the job. Exit status 6."""

    exit_code = 6


def default_path(output) -> pathlib.Path:
    """The checkpoint beside a run file: runs/demo.h5 -> runs/demo.ckpt.h5."""
    out = pathlib.Path(output)
    stem = out.name[:-len(out.suffix)] if out.suffix in (".h5", ".hdf5") else out.name
    return out.with_name(stem + ".ckpt.h5")


def physics_text(job) -> str:
    """The job's physics as canonical JSON: everything but [run] (schedule) and [parallel] (layout).

    dt is compared separately (it comes from [run] but changes the physics)."""
    return json.dumps(job.model_dump(mode="json", exclude={"run", "parallel"}), sort_keys=True)


def _flat(obj, prefix=""):
    """{dotted key: value} of a job's JSON dump (lists of tables by index: bodies[0].mass)."""
    if isinstance(obj, dict):
        out = {}
        for k, v in obj.items():
            out.update(_flat(v, f"{prefix}.{k}" if prefix else k))
        return out
    if isinstance(obj, list) and obj and all(isinstance(v, dict) for v in obj):
        out = {}
        for i, v in enumerate(obj):
            out.update(_flat(v, f"{prefix}[{i}]"))
        return out
    return {prefix: obj}


def keys_at_default(job) -> set[str]:
    """The job's physics keys (as physics_differences names them) that it leaves at their defaults."""
    every = _flat(job.model_dump(mode="json", exclude={"run", "parallel"}))
    given = _flat(job.model_dump(mode="json", exclude={"run", "parallel"}, exclude_defaults=True))
    return {k for k in every if k not in given}


def physics_differences(old: str, new: str, limit: int = 5, at_default=frozenset()) -> list[str]:
    """Keys whose values differ between two physics_text strings, as 'key = new (checkpoint: old)'. A key
    the checkpoint lacks is no difference when the job leaves it at its default (``at_default``,
    keys_at_default): the checkpoint predates the key, and a key's default keeps the behaviour the
    code had before it."""
    a, b = _flat(json.loads(old)), _flat(json.loads(new))
    keys = sorted(k for k in set(a) | set(b) if a.get(k, "absent") != b.get(k, "absent")
                  and not (k not in a and k in at_default))
    return [f"{k} = {json.dumps(b.get(k, 'absent'))} (checkpoint: {json.dumps(a.get(k, 'absent'))})"
            for k in keys[:limit]]


def write_checkpoint(sim, path) -> pathlib.Path:
    """Write the state of ``sim`` to ``path`` (collective: every rank calls it; rank 0 writes).

    Raises CheckpointError on every rank when rank 0 cannot write.
    """
    comm, p, c = sim.comm, sim.p, sim.c
    sim.sync()  # both copies of every bond history agree
    n = p.nlocal
    part = {name: getattr(p, name)[:n] for name in PER_PARTICLE}
    parts = comm.gather(part)
    mine = (c.broken, c.contacts, c.contact_energy, c.wall_energy, list(c.events))
    counters = comm.gather(mine)
    floes = sim.floes.state() if sim.floes is not None else None  # collective
    path = pathlib.Path(path)

    def unwritable(exc):
        if isinstance(exc, (OSError, ValueError, RuntimeError)):
            return CheckpointError(f"{path}: cannot write the checkpoint ({getattr(exc, 'strerror', None) or exc}); "
                                   "choose a writable path with run.checkpoint or free some disk space")
        return None

    on_root(comm, lambda: _write(sim, path, parts, counters, floes), translate=unwritable)
    return path


def _write(sim, path: pathlib.Path, parts: list, counters: list, floes: dict | None) -> None:
    gid = np.concatenate([q["gid"] for q in parts])
    order = np.argsort(gid, kind="stable")
    events = [(*e, r) for r, cnt in enumerate(counters) for e in cnt[4]]
    tmp = path.with_name(path.name + ".tmp")
    path.parent.mkdir(parents=True, exist_ok=True)
    try:
        _write_file(sim, tmp, gid, order, parts, counters, events, floes)
    except BaseException:
        tmp.unlink(missing_ok=True)  # a full disk leaves no half-written .tmp behind
        raise
    os.replace(tmp, path)
    try:  # make the rename itself durable
        dfd = os.open(path.parent, os.O_RDONLY)
        try:
            os.fsync(dfd)
        finally:
            os.close(dfd)
    except OSError:
        return  # best effort: some file systems cannot fsync a folder; the rename itself stands


def _write_file(sim, tmp: pathlib.Path, gid, order, parts, counters, events, floes=None) -> None:
    """The checkpoint's content into ``tmp``, flushed and fsync'd."""
    with h5py.File(tmp, "w") as f:
        a = f.attrs
        a["format"] = FORMAT
        a["format_version"] = FORMAT_VERSION
        a["pice_version"] = __version__
        a["ranks"] = sim.comm.size
        a["step"] = sim.c.step
        a["time"] = sim.c.time
        a["wall_time"] = sim.c.wall_time
        a["dt"] = sim.dt
        a["job_text"] = sim.job.text
        a["job_source"] = sim.job.source
        a["physics"] = physics_text(sim.job)
        a["n_particles"] = len(gid)
        a["written"] = datetime.datetime.now(datetime.timezone.utc).isoformat()
        g = f.create_group("particles")
        for name in PER_PARTICLE:
            g.create_dataset(name, data=np.concatenate([q[name] for q in parts])[order])
        d = f.create_group("decomposition")
        d["x_cuts"] = sim.domain.decomp.x_cuts
        d["y_cuts"] = sim.domain.decomp.y_cuts
        cg = f.create_group("counters")
        cg["broken"] = np.array([cnt[0] for cnt in counters], np.int64)
        cg["contacts"] = np.array([cnt[1] for cnt in counters], np.int64)
        cg["contact_energy"] = np.array([cnt[2] for cnt in counters], np.float64)
        cg["wall_energy"] = np.array([cnt[3] for cnt in counters], np.float64)
        eg = f.create_group("events")
        for k, name in enumerate(EVENT_FIELDS):
            dtype = np.float64 if name == "time" else np.int64
            eg[name] = np.array([e[k] for e in events], dtype=dtype)
        if sim.wall_total is not None:
            f["walls/total"] = np.asarray(sim.wall_total, dtype=np.float64)
        if sim.platform is not None:  # rank 0's bodies and lines
            for name, value in sim.platform.state().items():
                f[f"platform/{name}"] = np.asarray(value)
            for name, value in sim.peaks.state().items():  # the loads' mean and extremes since the last row
                f[f"peaks/{name}"] = np.asarray(value)
        for name, value in (floes or {}).items():  # every floe: state and contact histories
            f[f"floes/{name}"] = np.asarray(value)
        if sim.boundary_term is not None:  # a finite far field's shift and speed (the same on every rank)
            for name, value in sim.boundary_term.state().items():
                f[f"far_field/{name}"] = np.asarray(value)
        f.flush()
    fd = os.open(tmp, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


OPTIONAL = ("hull_hist", "anchor", "anchor_k")  # absent from format 1 (no bodies, no spring boundary then)


def _particles(g: h5py.Group) -> dict:
    out = {n: g[n][()] for n in PER_PARTICLE if n in g}
    n = len(out["gid"])
    out.setdefault("hull_hist", np.zeros((n, 1, 4)))
    for name in ("contact_hist", "wall_hist", "hull_hist"):  # format <= 2: no plastic penetration yet
        if out[name].shape[-1] == 3:
            out[name] = np.concatenate([out[name], np.zeros(out[name].shape[:-1] + (1,))], axis=-1)
    out.setdefault("anchor", out["x"].copy())
    out.setdefault("anchor_k", np.zeros((n, 3)))
    if out["anchor_k"].ndim == 1:  # format <= 2: one stiffness for all three directions
        out["anchor_k"] = np.repeat(out["anchor_k"][:, None], 3, axis=1)
    return out


def _platform_state(f: h5py.File) -> dict | None:
    """The /platform group as {"body0/x": array, ...}, None when the run had no bodies."""
    if "platform" not in f:
        return None
    out = {}
    f["platform"].visititems(lambda name, obj: out.__setitem__(name, obj[()]) if isinstance(obj, h5py.Dataset)
                             else None)
    return out


def read_checkpoint(path) -> dict:
    """The checkpoint at ``path`` as a dict: attrs, particles, x_cuts, y_cuts, counters, events, wall_total.

    Raises CheckpointError naming the file when it is missing or is not a pice checkpoint.
    """
    path = pathlib.Path(path)
    if not path.is_file():
        raise CheckpointError(f"{path}: checkpoint not found; give a file written by `pice run` "
                              "(run.checkpoint, default <run>.ckpt.h5 beside the run file)")
    try:
        with h5py.File(path, "r") as f:
            attrs = {k: (v.item() if isinstance(v, np.generic) else v) for k, v in f.attrs.items()}
            if attrs.get("format") != FORMAT:
                raise CheckpointError(f"{path}: not a pice checkpoint (no format = {FORMAT!r} attribute); "
                                      "a run file cannot be restarted from, only its checkpoint")
            if int(attrs.get("format_version", 0)) > FORMAT_VERSION:
                raise CheckpointError(f"{path}: checkpoint format {attrs['format_version']} is newer than this "
                                      f"pice ({__version__}) reads ({FORMAT_VERSION}); upgrade pice")
            missing = [n for n in PER_PARTICLE if n not in f["particles"] and n not in OPTIONAL]
            if missing:
                raise CheckpointError(f"{path}: checkpoint lacks particle arrays {', '.join(missing)}")
            return dict(
                path=str(path), attrs=attrs,
                particles=_particles(f["particles"]),
                x_cuts=f["decomposition/x_cuts"][()], y_cuts=f["decomposition/y_cuts"][()],
                counters={n: f["counters"][n][()] for n in COUNTERS},
                events={n: f["events"][n][()] for n in EVENT_FIELDS},
                wall_total=f["walls/total"][()] if "walls/total" in f else None,
                platform=_platform_state(f),
                peaks={k: v[()] for k, v in f["peaks"].items()} if "peaks" in f else None,
                floes={k: v[()] for k, v in f["floes"].items()} if "floes" in f else None,
                far_field={k: v[()] for k, v in f["far_field"].items()} if "far_field" in f else None)
    except CheckpointError:
        raise
    except (OSError, KeyError) as exc:
        raise CheckpointError(f"{path}: cannot read the checkpoint ({exc})") from None
