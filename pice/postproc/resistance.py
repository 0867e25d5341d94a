"""The keel resistance of a ship run as seed 002 reports it (Gong, Polojärvi & Tuhkuri 2017, Figs. 4-8;
issue 15): R = -f_x, the rubble's force on the ship against its penetration delta, the running
average of R over ``WINDOW`` m of penetration, and its peak R^p. Numbers only; postproc/plots.py
draws them (``keel_resistance.png``).

R at a series row is the mean of the ice's force over the steps since the row before
(``ice_force_mean``; the instantaneous ``ice_force`` in runs without it), so the record misses no
block's impact between rows. delta is the body's x displacement since t = 0.

The water's share: along x the rubble is pushed by the ship (R) and held by the water's drag, the
cover's and the walls' friction (its buoyancy and weight are vertical). ``water_drag_record`` gives
the drag, minus the x component of the series' ``floe_water_force`` (at the row's step, not a mean):
the part of R spent moving the rubble through the water rather than failing it.

Where R acts: ``piece_resistance_record`` splits it over the hull's convex pieces, for a ship its bow
(Malmberg's first term, the rubble failed and pushed down by the bow) and its parallel midbody (the
second, friction along the side and the bottom).
"""

from __future__ import annotations

import numpy as np

WINDOW = 6.0  # [m] of penetration (seed 002, Fig. 5)


def resistance_record(run, body: int = 0):
    """(delta [m], R [N]) of bodies[body] of a run; None when it has no body or no ice load."""
    x, f = run.series("body_position"), run.series("ice_force_mean")
    if f is None:
        f = run.series("ice_force")
    if x is None or f is None or x.ndim != 3 or x.shape[1] <= body:
        return None
    return x[:, body, 0] - x[0, body, 0], -f[:, body, 0]


def keel_record(run):
    """(delta [m], R [N]) of a ship run through a [keel] (``resistance_record`` of body 0); None for any
    other run (no [keel] in the job the run file keeps, or no body)."""
    if "[keel]" not in str(run.attrs.get("job_text", "")):
        return None
    return resistance_record(run)


def water_drag_record(run):
    """(delta [m], D [N]): the water's drag on all the floes against -x (the rubble held back) at each
    row; None when the run has no ``floe_water_force`` (runs before the column) or no body."""
    x, w = run.series("body_position"), run.series("floe_water_force")
    if x is None or w is None or x.ndim != 3 or x.shape[1] == 0:
        return None
    return x[:, 0, 0] - x[0, 0, 0], -w[:, 0]


def piece_resistance_record(run, body: int = 0):
    """(delta [m], R of each hull piece [N] (rows, pieces), the pieces' names): bodies[body]'s resistance
    split over its hull's convex pieces (series ``body_piece_force``, at the row's step, not a mean; a
    ship's bow, midbody and stern, Malmberg's bow and midbody terms). Rows written before the column
    existed (a run continued from an older pice's checkpoint: zeros, the ice's load not) are NaN. None
    when the run has no such column (a hull of one piece) or no body."""
    x, f = run.series("body_position"), run.series("body_piece_force")
    if x is None or f is None or x.ndim != 3 or x.shape[1] <= body or f.shape[1] <= body:
        return None
    r = -f[:, body, :, 0]
    ice = run.series("ice_force")
    if ice is not None:
        r[(f[:, body] == 0.0).all(axis=(1, 2)) & (ice[:, body, 0] != 0.0)] = np.nan
    job = run.job
    hull = job.bodies[body].hull if job is not None and len(job.bodies) > body else None
    from ..platform.ship import PIECES

    names = list(PIECES) if hull is not None and hull.type == "ship" and r.shape[1] == len(PIECES) else \
        [f"piece {k}" for k in range(r.shape[1])]
    return x[:, body, 0] - x[0, body, 0], r, names


def malmberg_for_job(job, body: int = 0):
    """Malmberg's R_A (physics/ridge.py, seed 002's Eqs. 1-2) for a job's ship through its [keel]:
    bodies[body]'s hull dimensions and ice friction, the keel's depth, the blocks' and the water's
    densities, and the rubble's phi = 40 deg and p = 0.3 with which seed 002 quotes about 1000 kN. A
    half hull (``hull.half``) meets half of both terms. None when the job has no [keel] or the body's
    hull is not a "ship"."""
    from ..physics.ridge import KeelResistance, malmberg_resistance

    if job is None or job.keel is None or len(job.bodies) <= body:
        return None
    b = job.bodies[body]
    hull = b.hull
    if hull is None or hull.type != "ship":
        return None
    r = malmberg_resistance(draft=hull.draft, breadth=hull.breadth, midbody=hull.midbody,
                            waterline_angle_deg=hull.waterline_angle, stem_angle_deg=hull.stem_angle,
                            keel_depth=job.keel.depth, ship_friction=b.friction, water_density=job.water.density,
                            ice_density=job.keel.blocks.density)
    share = 0.5 if hull.half else 1.0
    return KeelResistance(bow=share * r.bow, midbody=share * r.midbody)


def running_average(delta: np.ndarray, r: np.ndarray, window: float = WINDOW) -> np.ndarray:
    """The mean of R over the penetration (delta - window, delta] at each row (delta increasing);
    NaN until a whole window has been penetrated."""
    csum = np.concatenate([[0.0], np.cumsum(r)])
    start = np.searchsorted(delta, delta - window * (1.0 - 1e-9), side="right")  # the row at delta - window: out
    count = np.arange(1, len(r) + 1) - start
    out = (csum[1:] - csum[start]) / np.maximum(count, 1)
    out[delta - delta[0] < window] = np.nan
    return out


def peak_resistance(delta: np.ndarray, r: np.ndarray, window: float = WINDOW):
    """(R^p [N], the penetration at which the running average peaks [m]); (nan, nan) before a window."""
    avg = running_average(delta, r, window)
    if not np.isfinite(avg).any():
        return float("nan"), float("nan")
    k = int(np.nanargmax(avg))
    return float(avg[k]), float(delta[k])


def resistance_work(delta: np.ndarray, r: np.ndarray) -> float:
    """The work of R over the penetration [J]: the trapezoid rule over the record's rows."""
    return float(np.sum(0.5 * (r[1:] + r[:-1]) * np.diff(delta)))


def past_peak(delta: np.ndarray, r: np.ndarray, *, beyond: float, drop: float, window: float = WINDOW) -> bool:
    """True when R is past its peak: the penetration is beyond ``beyond`` [m] (the stem past the keel)
    and the running average (``running_average``) at the last row has fallen below ``drop`` times its
    highest value so far. R^p (``peak_resistance``) of the record is then that highest value."""
    if len(delta) == 0 or delta[-1] - delta[0] <= beyond:
        return False
    avg = running_average(delta, r, window)
    if not np.isfinite(avg[-1]):
        return False
    return bool(avg[-1] < drop * np.nanmax(avg))


def stem_at(vertices: np.ndarray, triangles: np.ndarray, z: float) -> float:
    """The foremost x [m] of a closed hull mesh (world vertices (n, 3) [m], triangles (m, 3)) on the
    horizontal plane at height ``z`` [m]: the largest x where an edge crosses it (or a vertex lies on
    it); the foremost vertex when the hull does not reach that height."""
    a = vertices[triangles]                      # (m, 3 corners, 3)
    b = np.roll(a, -1, axis=1)                   # each corner's next: the triangle's three edges
    za, zb = a[..., 2] - z, b[..., 2] - z
    on = za == 0.0
    cross = (za * zb < 0.0)
    xs = []
    if on.any():
        xs.append(a[..., 0][on].max())
    if cross.any():
        s = za[cross] / (za[cross] - zb[cross])
        xs.append((a[..., 0][cross] + s * (b[..., 0][cross] - a[..., 0][cross])).max())
    return float(max(xs)) if xs else float(vertices[:, 0].max())


class PeakWatch:
    """Ends a ship's run through a keel once R is past its peak (``[keel] end_after_peak``, issue 15):
    fed the first body's x position [m] and the x ice load on it [N] (R = -f_x) at every series row
    (rank 0), ``past`` is ``past_peak`` of the record so far, with ``beyond`` the penetration at which
    the body's stem reaches the keel's far edge at the cover (``from_job``)."""

    def __init__(self, beyond: float, drop: float, window: float = WINDOW):
        self.beyond, self.drop, self.window = float(beyond), float(drop), float(window)
        self.x: list[float] = []
        self.r: list[float] = []

    @classmethod
    def from_job(cls, job, hull, pose) -> "PeakWatch":
        """The watch of a keel job: ``hull`` the first body's (platform.hull_contact.Hull, body frame),
        ``pose`` its (13,) x, q, ... at t = 0; the stem is its foremost point at the cover's underside
        (``stem_at``), the keel's far edge x + width / 2 (the run drives the body along +x)."""
        from ..kernels.geometry import rotation_matrix

        k = job.keel
        world = hull.vertices @ rotation_matrix(np.asarray(pose[3:7], float)).T + pose[:3]
        far = k.x + 0.5 * k.width
        return cls(far - stem_at(world, hull.triangles, k.cover), k.end_after_peak)

    def add(self, x: float, fx: float) -> None:
        self.x.append(float(x))
        self.r.append(-float(fx))

    @property
    def past(self) -> bool:
        x = np.asarray(self.x)
        return past_peak(x - x[0] if len(x) else x, np.asarray(self.r), beyond=self.beyond, drop=self.drop,
                         window=self.window)
