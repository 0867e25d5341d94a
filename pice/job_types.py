"""Field types shared by the job schema (pice.job, pice.job_platform): quantities with units,
strict counts, fixed-length vectors, and the frozen section base class."""

from __future__ import annotations

from typing import Annotated

from pydantic import BaseModel, ConfigDict, Field, Strict


def _q(unit: str, gt: float | None = 0.0, ge: float | None = None, le: float | None = None, lt: float | None = None):
    """A float quantity with a unit (shown in error messages) and bounds.

    Strict: a TOML integer or float is accepted, a string or boolean is not (``"1.0"`` is a typo,
    not a number).
    """
    kw = {k: v for k, v in dict(gt=gt, ge=ge, le=le, lt=lt).items() if v is not None}
    return Annotated[float, Strict(), Field(json_schema_extra={"unit": unit}, allow_inf_nan=False, **kw)]


def _count(ge: int):
    """A whole number >= ``ge`` (strict: 2.5, 2.0, "2" and true are refused)."""
    return Annotated[int, Strict(), Field(ge=ge)]


def _vec(vec, unit: str):
    """A fixed-length vector field whose unit is shown in error messages."""
    return Annotated[vec, Field(json_schema_extra={"unit": unit})]


_Real = Annotated[float, Strict(), Field(allow_inf_nan=False)]  # a finite number
_Bound = Annotated[float, Strict()]  # a region bound: a number, +-inf allowed
Vec2 = tuple[_Real, _Real]
Vec3 = tuple[_Real, _Real, _Real]


class _Section(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True, strict=False)
