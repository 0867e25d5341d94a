"""Reading a job: the TOML file -> text -> dict -> a validated ``Job``, or a JobError with one line
per problem naming the file, the key, the value and what is expected."""

from __future__ import annotations

import io
import pathlib

from pydantic import ValidationError

from ..errors import JobError
from .messages import Located, error_lines
from .schema import Job

try:  # Python >= 3.11
    import tomllib
except ModuleNotFoundError:  # pragma: no cover
    import tomli as tomllib


def load_job(path: str | pathlib.Path) -> Job:
    """Read and validate a TOML job file; raise JobError naming the file on any problem."""
    path = pathlib.Path(path)
    if not path.is_file():
        what = "is a directory" if path.is_dir() else "file not found"
        raise JobError(f"{path}: {what}: give the path of a TOML job file (see jobs/)")
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise JobError(f"{path}: cannot read the job file ({exc.strerror or exc})") from None
    text = decode_job_text(raw, path)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise JobError(f"{path}: not valid TOML: {exc}") from None
    if isinstance(data.get("study"), dict):  # a sweep's file (pice/study/sweep.py), not a job
        job = data["study"].get("job", "(absent)")
        raise JobError(f"{path}: [study] (job = {job!r}): a study file, not a job; run it with: pice study {path} "
                       "(or give its job file)")
    return parse_job(data, source=str(path), text=text, base_dir=path.parent)


def decode_job_text(raw: bytes, path) -> str:
    """The text of a job file's bytes: UTF-8 (as TOML requires; a leading byte-order mark is dropped),
    line endings read as Python's text files read them (\\r\\n and \\r become \\n). Any other encoding
    is a JobError naming the first byte that is not UTF-8 by its offset, line and column."""
    try:
        raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        at = exc.start
        line = raw.count(b"\n", 0, at) + 1
        column = at - (raw.rfind(b"\n", 0, at) + 1) + 1
        what = (" (it starts with a UTF-16 byte-order mark: the file is UTF-16)"
                if raw[:2] in (b"\xff\xfe", b"\xfe\xff") else "")
        raise JobError(f"{path}: not UTF-8 text: byte offset {at} (line {line}, column {column}) holds 0x{raw[at]:02x}, "
                       f"which is not UTF-8{what}; save the job file as UTF-8 (TOML files are UTF-8)") from None
    return io.TextIOWrapper(io.BytesIO(raw), encoding="utf-8-sig").read()


def parse_job(data: dict, source: str = "<job>", text: str = "", base_dir: pathlib.Path | None = None) -> Job:
    """Validate a job given as a dict; raise JobError with one line per problem.

    ``source`` names the job in the error lines, ``text`` is kept with the job (the run file stores
    it), and the mesh files of walls and hulls are looked up relative to ``base_dir`` (default: the
    working directory).
    """
    try:
        job = Job.model_validate({**data, "source": source, "text": text})
    except (Located, ValidationError) as exc:
        raise JobError(error_lines(exc, source=source, root=Job)) from None
    _check_mesh_files(job, source, base_dir or pathlib.Path("."))
    return job


def _check_mesh_files(job: Job, source: str, base: pathlib.Path) -> None:
    """Refuse a wall or hull mesh file that does not exist (reading it comes at set-up)."""
    for k, wall in enumerate(job.walls):
        if wall.type == "mesh" and not (base / wall.file).is_file():
            raise JobError(f"{source}: walls[{k}].file = {wall.file!r}: file not found "
                           f"(paths are relative to the job file's folder {str(base)!r})")
    for k, body in enumerate(job.bodies):
        if body.hull.type == "mesh" and not (base / body.hull.file).is_file():
            raise JobError(f"{source}: bodies[{k}].hull.file = {body.hull.file!r}: file not found "
                           f"(paths are relative to the job file's folder {str(base)!r})")
