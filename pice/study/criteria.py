"""User criteria over a study's metrics: ``--criterion "max_pitch_deg < 15"`` marks each variant pass or
fail (issue 16; the buoy design sweep's criteria (1)-(7) of Cai 2018 section 6.1).

A criterion is ``<metric> <op> <number>``: a metric of study/metrics.py named as its CSV column,
with its unit (``max_pitch_deg``, ``max_offset_m``, ``max_fairlead_tension_N``), one of ``<``,
``<=``, ``>``, ``>=``, and a number in that unit. A variant passes when every criterion
holds; a metric its run does not have (NaN) fails the criterion, said so. Parsed before anything
runs: a bad criterion is one JobError line (exit status 2).
"""

from __future__ import annotations

import math
import operator
import re
from dataclasses import dataclass

from ..errors import JobError
from .metrics import METRICS

OPS = {"<": operator.lt, "<=": operator.le, ">": operator.gt, ">=": operator.ge}
#: criterion name (the CSV column) -> metric name
COLUMNS = {f"{name}_{unit}": name for name, unit, _ in METRICS}
_PATTERN = re.compile(r"^\s*([A-Za-z_][A-Za-z0-9_]*)\s*(<=|>=|<|>)\s*([-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?)\s*$")


@dataclass(frozen=True)
class Criterion:
    metric: str
    op: str
    value: float

    def __str__(self) -> str:
        return f"{self.metric} {self.op} {self.value:g}"

    def holds(self, metrics: dict) -> bool:
        v = metrics.get(COLUMNS.get(self.metric, ""), math.nan)
        return not math.isnan(v) and OPS[self.op](v, self.value)


def parse_criterion(text: str) -> Criterion:
    """The criterion ``text`` (module docstring); JobError naming what is wrong and the fix."""
    names = list(COLUMNS)
    m = _PATTERN.match(text)
    if m is None:
        raise JobError(f"--criterion {text!r}: write <metric> <op> <number>, e.g. \"max_pitch_deg < 15\"; "
                       f"op one of {', '.join(OPS)}")
    if m.group(1) not in names:
        raise JobError(f"--criterion {text!r}: no metric {m.group(1)!r}; one of {', '.join(names)}")
    return Criterion(m.group(1), m.group(2), float(m.group(3)))


def judge(criteria: list[Criterion], metrics: dict) -> tuple[bool, list[str]]:
    """(every criterion holds, the texts of those that fail; a missing metric says so)."""
    failed = []
    for c in criteria:
        if not c.holds(metrics):
            missing = math.isnan(metrics.get(COLUMNS[c.metric], math.nan))
            failed.append(f"{c} (no {c.metric} in this run)" if missing else str(c))
    return not failed, failed
