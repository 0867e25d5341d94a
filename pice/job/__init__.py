"""TOML job -> validated, frozen job description.

Every problem is reported as one line naming the file, the key, the value and what is
expected, e.g. ``jobs/x.toml: ice.thickness = -1.0: must be > 0 m``. Validation happens before
anything is allocated or written.

types.py holds the field types (quantities with units, counts, vectors), schema.py the tables and
``Job``, platform.py the [[bodies]] and [[moorings]], messages.py the wording of validation errors,
load.py the reading of the file.
"""

from .load import load_job, parse_job
from .schema import Job

__all__ = ["Job", "load_job", "parse_job"]
