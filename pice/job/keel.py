"""The job's ridge keel: [keel] (seed 002, Gong, Polojärvi & Tuhkuri 2017; issue 15): rigid ice blocks
released under water beneath a rigid cover, packed by their buoyancy and trimmed to the keel's shape
(pice/scenes/rubble.py, pice/physics/keel.py). Absent: no keel, at no cost.
"""

from __future__ import annotations

from pydantic import model_validator

from .floes import FloeContactSpec
from .types import Real, Section, Vec2, count, quantity, vector


class BlocksSpec(Section):
    """[keel.blocks]: rigid rectangular blocks, ``thickness`` thick, ``length`` uniform in [lo, hi] and
    ``aspect`` x length wide (seed 002, Table 1: 0.3 m, 0.615; the lengths are an assumption: the seed
    cites Kulyakhtin (2014) for their distribution but gives no numbers; docs/ridge_keel.md)."""

    thickness: quantity("m") = 0.3
    aspect: quantity("", le=1.0) = 0.615
    length: vector(Vec2, "m") = (0.6, 1.4)
    density: quantity("kg/m^3") = 920.0

    @model_validator(mode="after")
    def _sizes(self):
        lo, hi = self.length
        if not 0.0 < lo <= hi:
            raise ValueError("length: give [shortest, longest] with 0 < shortest <= longest (m)")
        return self


NO_CRUSHING = 1.0e15  # [Pa]


class KeelContactSpec(FloeContactSpec):
    """[keel.contact]: block-block and block-cover contact, seed 003's law (kernels/contact_law.py) with
    its defaults for rubble (assumptions, docs/ridge_keel.md "Contact"): seed 002's penalty term read
    as k_n = 1e7 N/m, k_t = 0.6 k_n (seed 003's ratio), a dashpot of 0.3 of each pair's critical
    damping (for two blocks of 1 m x 0.615 m x 0.3 m, m_eff 84.9 kg, c_n = 1.75e4 N s/m; a ``damping``
    given instead is one c_n for every pair), and no crushing, as seed 002's elastic-viscous contact: a
    plastic limit that never binds (a corner's tiny contact area would otherwise cap its force and let
    it crush centimetres into a wall)."""

    normal_stiffness: quantity("N/m") = 1.0e7
    damping: quantity("N s/m", gt=None, ge=0.0) = 1.75e4  # used only when given (then instead of the ratio)
    damping_ratio: quantity("", gt=None, ge=0.0, lt=1.0) | None = 0.3
    tangential_stiffness: quantity("N/m", gt=None, ge=0.0) = 0.6e7
    compressive_strength: quantity("Pa") = NO_CRUSHING

    @model_validator(mode="before")
    @classmethod
    def _given_damping(cls, data):
        """A c_n given without a ratio replaces the default ratio."""
        if isinstance(data, dict) and "damping" in data and "damping_ratio" not in data:
            data = {**data, "damping_ratio": None}
        return data


MAX_STEP_FRACTION = 0.3  # keel.step_fraction's largest: measured, docs/ridge_keel.md "The step beyond 0.2"
TRIANGLE_SLACK = 0.005  # a width this fraction short of the triangle's is the triangle (its tip cut)


class KeelSpec(Section):
    """[keel]: a first-year ridge keel of rubble under a rigid cover spanning the basin (seed 002,
    Figs. 1-2). Its cross-section in x-z is a trapezoid, ``width`` w at the cover's underside (z =
    ``cover``), sides at ``pile_angle`` from the horizontal down to ``depth`` (a triangle when w = 2
    depth / tan(pile_angle)); it runs ``length`` along y from y = ``y0``, centred on x = ``x``.
    Walls close the length at both ends (seed 002's basin walls; in a half model the one at y0 is the
    symmetry plane, the ship's centreline, and the ship's hull is its half). Generation
    (``pice keel``): blocks drawn from ``seed`` fill the keel's box, are released under water, rise
    against the cover until their RMS speed is below ``settle_speed`` (at most ``settle_time`` of
    simulated time), and are trimmed to the shape; the settled keel is ``file`` (relative to the job's
    folder; default <job>.keel.h5 beside it), which ship runs start from (io/keel_file.py)."""

    width: quantity("m")
    length: quantity("m")
    depth: quantity("m") = 5.0
    pile_angle: quantity("deg", lt=90.0) = 30.0
    x: Real = 0.0
    y0: Real = 0.0
    cover: Real = 0.0
    seed: count(0) = 0
    blocks: BlocksSpec = BlocksSpec()
    contact: KeelContactSpec = KeelContactSpec()
    settle_speed: quantity("m/s") = 2.0e-3
    # the ice-ice and ice-cover friction while the blocks settle (default: keel.contact.friction, seed 002's
    # procedure): with it the pile locks loose (porosity 0.56-0.62 measured), frictionless (0) it packs
    # closer (0.33-0.39), but slides for longer; docs/ridge_keel.md "Porosity"
    settle_friction: quantity("", gt=None, ge=0.0) | None = None
    # the RMS speed below which the contact's friction returns while the blocks settle (default: never;
    # settle_friction to the end): frictionless packing, then locked by friction to rest
    lock_speed: quantity("m/s") | None = None
    settle_time: quantity("s") = 120.0
    # the step: this fraction of the lightest pair's contact time m_eff / c_n; up to 0.3, the largest measured free of
    # the corners' instability (docs/ridge_keel.md "The step beyond 0.2"; 0.4 showed its onset)
    step_fraction: quantity("") = 0.1
    # C_d of each block's form drag in the water (kernels/floe_hydro.py; 1 as the floes'): each block drags
    # alone, though the water in a packed rubble moving together moves with it (docs/ridge_keel.md)
    form_drag_coefficient: quantity("", gt=None, ge=0.0) = 1.0
    file: str = ""  # the settled keel (default: beside the run file, <run>.keel.h5)
    # instead of a generation of its own, `pice keel` trims this keel from the middle of a wider one's
    # settled file (relative to the job's folder), generated from the same blocks, depth, angle, length,
    # cover, seed and settling: one generation for a width sweep (docs/ridge_keel.md "One generation")
    trim_from: str | None = None
    # a ship's run ends once R = -f_x on the first body is past its peak (postproc/resistance.PeakWatch):
    # its stem past the keel's far edge at the cover and the 6 m running average of R below this fraction of
    # its highest value, R^p then known; default: the whole run.duration (docs/ridge_keel.md "Ending a run")
    end_after_peak: quantity("", lt=1.0) | None = None

    @model_validator(mode="after")
    def _shape(self):
        import math

        bottom = self.width - 2.0 * self.depth / math.tan(math.radians(self.pile_angle))
        if bottom < -TRIANGLE_SLACK * self.width:  # seed 002's 17.3 m rounds the triangle's 17.32 m
            raise ValueError(f"width: the sides at pile_angle = {self.pile_angle:g} deg meet above the keel's depth "
                             f"{self.depth:g} m; give width >= {(self.width - bottom) * (1 - TRIANGLE_SLACK):.4g} m "
                             "(a triangle) or a "
                             "shallower depth")
        if self.step_fraction > MAX_STEP_FRACTION:
            raise ValueError(f"step_fraction: above {MAX_STEP_FRACTION:g}, the largest step measured free of the blocks' "
                             "corner instability (docs/ridge_keel.md \"The step beyond 0.2\": 0.4 showed its onset); "
                             f"give at most {MAX_STEP_FRACTION:g}")
        if self.lock_speed is not None:
            if self.settle_friction is None:
                raise ValueError("lock_speed: it ends the settling friction, and settle_friction is not given; "
                                 "give settle_friction (e.g. 0.0) or drop lock_speed")
            if self.lock_speed <= self.settle_speed:
                raise ValueError("lock_speed: the friction would return only once the blocks are at rest "
                                 f"(settle_speed = {self.settle_speed:g} m/s); give lock_speed > "
                                 "settle_speed")
        return self
