"""The reference level-ice sheet of Zhu & Ji (2022), Table 4, as a job (benchmarks and scaling)."""

from __future__ import annotations


def zhu_ji_sheet_job(*, length: float = 400.0, width: float = 200.0, source: str = "reference", **sections):
    """A validated job: the 200 m x 400 m sheet of 1 m elements (Table 4 bonds) moving with a 1 m/s
    current; extra top-level sections (e.g. parallel={...}) are merged in."""
    from ..job import parse_job

    data = {
        "run": {"duration": 200.0},
        "water": {"density": 1035.0, "current": [1.0, 0.0]},  # skin drag (the default)
        "ice": {"length": length, "width": width, "density": 920.0, "velocity": [1.0, 0.0]},
        "bond": {"normal_stiffness": 1.72e7, "shear_stiffness": 1.72e6, "normal_strength": 1.5e6,
                 "shear_strength": 1.5e6, "friction": 0.3},
    }
    data.update(sections)
    return parse_job(data, source=source)
