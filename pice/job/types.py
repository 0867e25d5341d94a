"""Field types of the job schema: quantities with units, strict counts, fixed-length vectors, and the
frozen section base class every table of a job derives from."""

from __future__ import annotations

from typing import Annotated

from pydantic import BaseModel, ConfigDict, Field, Strict


def quantity(unit: str, gt: float | None = 0.0, ge: float | None = None, le: float | None = None,
             lt: float | None = None):
    """A float quantity with a unit (shown in error messages) and bounds; by default > 0.

    Strict: a TOML integer or float is accepted, a string or boolean is not (``"1.0"`` is a typo,
    not a number).
    """
    kw = {k: v for k, v in dict(gt=gt, ge=ge, le=le, lt=lt).items() if v is not None}
    return Annotated[float, Strict(), Field(json_schema_extra={"unit": unit}, allow_inf_nan=False, **kw)]


def count(ge: int):
    """A whole number >= ``ge`` (strict: 2.5, 2.0, "2" and true are refused)."""
    return Annotated[int, Strict(), Field(ge=ge)]


def vector(vec, unit: str):
    """A fixed-length vector field whose unit is shown in error messages."""
    return Annotated[vec, Field(json_schema_extra={"unit": unit})]


Real = Annotated[float, Strict(), Field(allow_inf_nan=False)]  # a finite number
Bound = Annotated[float, Strict()]  # a region bound: a number, +-inf allowed
Vec2 = tuple[Real, Real]
Vec3 = tuple[Real, Real, Real]


class Section(BaseModel):
    """A table of the job: unknown keys are refused, and the parsed values are frozen."""

    model_config = ConfigDict(extra="forbid", frozen=True, strict=False)
