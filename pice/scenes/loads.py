"""Loads, prescribed velocities and the drive of the sheet's rear rows, from the job."""

from __future__ import annotations

import numpy as np

from ..errors import JobError


def _select(p, region) -> np.ndarray:
    """Elements whose initial centre lies in the region box (bounds absent = unbounded)."""
    sel = np.ones(p.n, bool)
    for k, (lo, hi) in enumerate(((region.xmin, region.xmax), (region.ymin, region.ymax),
                                  (region.zmin, region.zmax))):
        sel &= (p.x[:, k] >= lo) & (p.x[:, k] <= hi)
    return sel


def _selects_nothing(job, p, key, region) -> JobError:
    given = ", ".join(f"{b} = {v}" for b, v in region.model_dump(exclude_defaults=True).items())
    lo, hi = p.x.min(axis=0), p.x.max(axis=0)
    span = ", ".join(f"{a} {lo[d]:.4g} .. {hi[d]:.4g}" for d, a in enumerate("xyz"))
    return JobError(f"{job.source}: {key} = {{{given}}}: selects no element; the box must contain some "
                    f"initial element centres, which span {span} m")


def apply_loads_and_fixes(job, p, *, spacing: float) -> None:
    """[[loads]] into p.ext_force [N], [[fixes]] into p.fix_mask / p.fix_velocity [m/s], and
    [ice.push]: the rear ``rows`` (row spacing ``spacing`` [m]) moving at ``speed``, either tied to
    anchors by springs (p.anchor_k [N/m]) or with their x velocity prescribed."""
    for k, load in enumerate(job.loads):
        sel = _select(p, load.region)
        if not sel.any():
            raise _selects_nothing(job, p, f"loads[{k}].region", load.region)
        p.ext_force[sel] += np.asarray(load.force) / np.count_nonzero(sel)
    for k, fix in enumerate(job.fixes):
        sel = _select(p, fix.region)
        if not sel.any():
            raise _selects_nothing(job, p, f"fixes[{k}].region", fix.region)
        for d, comp in enumerate(fix.velocity):
            if comp != "free":
                p.fix_mask[sel, d] = True
                p.fix_velocity[sel, d] = float(comp)
    push = job.ice.push if job.ice is not None else None
    if push is not None:
        xmin = p.x[:, 0].min()
        sel = p.x[:, 0] < xmin + (push.rows - 1e-6) * spacing  # odd rows sit d/2 further in
        p.v[sel, 0] = push.speed
        if push.stiffness is not None:  # a spring boundary
            p.anchor_k[sel] = push.stiffness
            if push.side_stiffness is not None:  # the side edges held in y (the far field beside the sheet)
                ymin, ymax = p.x[:, 1].min(), p.x[:, 1].max()
                side = (p.x[:, 1] < ymin + 0.5 * spacing) | (p.x[:, 1] > ymax - 0.5 * spacing)
                p.anchor_k[side & ~sel, 1] = push.side_stiffness
        else:
            p.fix_mask[sel, 0] = True
            p.fix_velocity[sel, 0] = push.speed
