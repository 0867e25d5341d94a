"""The job's broken ice and sea: [floes] (a field of rigid convex floes, pice/physics/floes.py) and
[waves] (linear waves, pice/physics/waves.py). Absent: no floes, still water, at no cost.
"""

from __future__ import annotations

from typing import Literal

from pydantic import StrictBool, model_validator

from .types import Real, Section, Vec2, count, quantity, vector


class FloeContactSpec(Section):
    """[floes.contact]: the viscoelastic-plastic contact of seed 003 (Eqs. 1-4), one law for ice-ice and
    ice-structure; the defaults are its Table 3."""

    normal_stiffness: quantity("N/m") = 1.3e6
    damping: quantity("N s/m", gt=None, ge=0.0) = 2.6e6          # c_n of the normal dashpot
    # or the dashpot as a fraction of each pair's critical damping 2 sqrt(m_eff k_n) (one of the two):
    # the same restitution for light and heavy pairs, where one c_n over-damps the light ones
    damping_ratio: quantity("", gt=None, ge=0.0, lt=1.0) | None = None
    tangential_stiffness: quantity("N/m", gt=None, ge=0.0) = 0.78e6
    friction: quantity("", gt=None, ge=0.0) = 0.3
    compressive_strength: quantity("Pa") = 2.5e6                  # the plastic limit sigma_c A_c

    @model_validator(mode="after")
    def _one_dashpot(self):
        if self.damping_ratio is not None and "damping" in self.model_fields_set:
            raise ValueError("damping_ratio: damping is given too; the dashpot is one of the two, a coefficient c_n "
                             "[N s/m] for every pair or a fraction of each pair's critical damping: remove one")
        return self


class FloesSpec(Section):
    """[floes]: a random field of rigid floes, right prisms over convex polygons (scenes/floe_field.py),
    drawn from ``seed``: equivalent diameters uniform in ``size``, thicknesses uniform in ``thickness``,
    covering ``concentration`` of ``area`` = [x0, y0, x1, y1]. ``sides = "confined"`` puts fixed walls
    along the drift at y0 and y1 (seed 003's "tight" field); "free" leaves them open.

``breakable = true``: the same field, each floe built of the bonded elements of [ice] (its material,
element, bonds and contact) so that a floe can break; the keys of rigid floes are then refused
(scenes/bonded_floes.py, docs/broken_ice.md "Breakable floes")."""

    area: vector(tuple[Real, Real, Real, Real], "m")
    concentration: quantity("", lt=1.0)
    size: vector(Vec2, "m") = (30.0, 40.0)
    thickness: vector(Vec2, "m") = (2.5, 2.7)
    seed: count(0) = 0
    density: quantity("kg/m^3") = 920.0
    velocity: vector(Vec2, "m/s") = (0.0, 0.0)
    sides: Literal["free", "confined"] = "free"
    skin_drag_coefficient: quantity("", gt=None, ge=0.0) = 0.0055  # ice-ocean skin friction under a floe
    form_drag_coefficient: quantity("", gt=None, ge=0.0) = 1.0     # on the submerged side (seed 003 Eq. 12)
    damping_ratio: quantity("", gt=None, ge=0.0, lt=1.0) = 0.1     # heave, roll, pitch (radiation; assumption)
    added_mass: Literal["plate", "none"] = "plate"  # thin floating disks (physics/floes.plate_added_mass)
    step_fraction: quantity("", le=0.2) = 0.1    # dt "auto": this fraction of the shortest contact, m_eff / c_n
                                                 # (docs/broken_ice.md, "The time step": 0.02-0.1 agree)
    contact: FloeContactSpec = FloeContactSpec()
    breakable: StrictBool = False  # bonded floes of [ice] elements instead of rigid prisms

    @model_validator(mode="after")
    def _field(self):
        x0, y0, x1, y1 = self.area
        if not (x1 > x0 and y1 > y0):
            raise ValueError("area: give [x0, y0, x1, y1] with x1 > x0 and y1 > y0 (m)")
        for key in ("size", "thickness"):
            lo, hi = getattr(self, key)
            if not 0.0 < lo <= hi:
                raise ValueError(f"{key}: give [smallest, largest] with 0 < smallest <= largest (m)")
        if self.breakable:
            rigid = sorted(RIGID_ONLY & self.model_fields_set)
            if rigid:
                raise ValueError(f"{rigid[0]}: a key of rigid floes (given: {', '.join(rigid)}); breakable floes are "
                                 "bonded elements of [ice], which sets their thickness, density, contact and drag: "
                                 "drop them")
        return self


# keys that describe rigid floes alone (physics/floes.py); bonded floes take [ice], [bond], [contact]
RIGID_ONLY = frozenset({"thickness", "density", "skin_drag_coefficient", "form_drag_coefficient", "damping_ratio",
                        "added_mass", "step_fraction", "contact"})


class WavesSpec(Section):
    """[waves]: linear waves over the water's depth (deep water without water.depth). ``spectrum``:
    "regular" (one Airy wave of height H = ``height`` and period ``period``) or "jonswap" (an irregular
    long-crested sea of significant height Hs = ``height``, ``period`` of kind ``period_kind``,
    peak enhancement ``gamma``, ``components`` frequencies with phases from ``seed``). ``direction``:
    the heading of propagation [deg] from +x."""

    spectrum: Literal["regular", "jonswap"]
    height: quantity("m")
    period: quantity("s")
    period_kind: Literal["peak", "mean", "zero_crossing"] = "peak"
    gamma: quantity("", gt=None, ge=1.0, le=7.0) = 3.3
    direction: Real = 0.0
    components: count(1) = 200
    seed: count(0) = 0
    phase: Real = 0.0  # regular: the phase [rad] at x = y = t = 0

    @model_validator(mode="after")
    def _kind(self):
        if self.spectrum == "regular" and self.period_kind != "peak":
            raise ValueError("period_kind: a regular wave has one period; drop period_kind")
        return self
