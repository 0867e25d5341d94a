"""The spread mooring's surge restoring force under different layout assumptions (Zhu & Ji 2022, section 4.1).

The paper gives the line (Table 5: 20 m anchor chain, 250 m steel cable, 190 m platform chain, 460 m
and 165 kN in water), 12 lines in 4 bundles 5 degrees apart, the fairlead 385 m above the anchor in
400 m of water and a 221.7 kN pretension; it does not give the fairleads' positions, the bundles'
headings or which tension the 221.7 kN is. Each layout below is a set of those assumptions; the
lines are the independent elastic catenary with seabed contact of tests/reference_catenary.py
(Faltinsen 1990 / Irvine 1981), not pice's. For a pure translation the fairleads' horizontal
positions do not matter (each anchor is placed relative to its fairlead): only the headings, the
fairlead-anchor height and the anchor radius do.

Printed per layout: anchor radius R [m], fairlead tension T0 and horizontal tension H0 at rest [kN],
the restoring force F [MN] at the paper's mean (14.7 m) and maximum (17.6 m) offsets, the largest
fairlead tension at 17.6 m, the static surge offsets [m] at which F equals our coarse run's mean ice
load (4.4 MN), the mean load the lines held in that run (4.8 MN: ice plus the current's drag on the
hull) and the paper's maximum restoring force (7.2 MN), and the largest fairlead tension at 7.2 MN
(the paper: 1.9 MN). With --coupled, also the static offset at the run's mean loads with heave and
pitch free (the hull's hydrostatics from pice.platform.hull_buoyancy; the run's mean ice force and
moment), beside the run's mean offset, heave and pitch.

    python benchmarks/mooring_layouts.py [--coupled]
"""

from __future__ import annotations

import argparse
import math
import pathlib
import sys
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq, root

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "tests"))
import reference_catenary as rc  # noqa: E402

# Table 5, anchor first: (length [m], wet weight [N/m], EA [N])
LINE = [rc.Piece(20.0, 430.0, 675.0e6), rc.Piece(250.0, 230.0, 900.2e6), rc.Piece(190.0, 520.0, 700.8e6)]
PRETENSION = 221.7e3       # [N] (section 4.1)
HEIGHT = 385.0             # [m] fairlead above the anchor (section 4.1)
SPREAD = 5.0               # [deg] between the lines of a bundle
PAPER = dict(mean=14.7, max=17.6, force=7.2e6, tension=1.9e6)  # section 4.2 and Fig. 18 (h = 1 m)
# The coarse full-size 200 s run of jobs/zhu_ji_2022_semisub.toml (2 m ice, 20 m line elements;
# coarse200.h5 of the run queue, docs/reference_scene.md), means over 100-200 s of its series: ice
# force (x, z) [N], ice moment about the CG (y) [N m], the current's drag on the hull (current_drag
# 3.8e5 N s^2/m^2 at 1 m/s) [N]; surge [m], heave [m] (CG from -5.1 m), pitch [deg], the lines' pull [N].
RUN = dict(ice_x=4.416e6, ice_z=0.322e6, ice_my=35.10e6, hull_drag=0.38e6, surge=23.27, heave=-0.78,
           pitch=-1.62, mooring_x=4.815e6)
DIAGONALS, AXES = (45.0, 135.0, 225.0, 315.0), (0.0, 90.0, 180.0, 270.0)


@dataclass(frozen=True)
class Layout:
    """One set of assumptions: bundle headings [deg], fairlead-anchor height [m], and the anchor
    radius given directly (``radius`` [m]) or by the tension at rest, ``tension`` [N], read where
    ``measured`` says: "fairlead" (its tension there), "horizontal" (H) or "anchor"."""

    name: str
    headings: tuple = DIAGONALS
    height: float = HEIGHT
    tension: float = PRETENSION
    measured: str = "fairlead"
    radius: float | None = None

    def anchor_radius(self) -> float:
        if self.radius is not None:
            return self.radius
        if self.measured == "fairlead":
            return rc.anchor_radius(LINE, self.height, self.tension)
        weight = sum(p.w * p.length for p in LINE)

        def miss(X):
            H, V = rc.solve(LINE, X, self.height)
            return (H if self.measured == "horizontal" else math.hypot(H, max(V - weight, 0.0))) - self.tension
        return brentq(miss, touchdown_radius(self.height), taut_radius(self.height), xtol=1e-9)

    def line_headings(self) -> list[float]:
        """Heading of each of the 12 lines [deg]: its bundle's, -5, 0 and +5 degrees."""
        return [h + d for h in self.headings for d in (-SPREAD, 0.0, SPREAD)]

    def anchors(self) -> np.ndarray:
        """(12, 3) anchors relative to their fairlead at rest [m]."""
        return rc.spread(self.line_headings(), radius=self.anchor_radius(), Z=self.height)


def slack_radius(height: float) -> float:
    """Anchor radius [m] below which the line would pile up on the seabed."""
    return sum(p.length for p in LINE) - height


def taut_radius(height: float, tension: float = 4.4e6) -> float:
    """Anchor radius [m] of the line stretched straight at ``tension`` [N] (its breaking strength)."""
    return math.sqrt(sum(p.length * (1.0 + tension / p.ea) for p in LINE) ** 2 - height ** 2)


def touchdown_radius(height: float = HEIGHT) -> float:
    """Anchor radius [m] at which the line at rest just reaches the seabed (no uplift at the anchor)."""
    weight = sum(p.w * p.length for p in LINE)
    return brentq(lambda X: rc.solve(LINE, X, height)[1] - weight, slack_radius(height) * 1.001, taut_radius(height))


def offset_at(anchors: np.ndarray, force: float, top: float = 100.0) -> float:
    """Surge [m] at which the restoring force is ``force`` [N] (pure translation)."""
    return brentq(lambda s: rc.restoring(LINE, anchors, s)[0] - force, 0.0, top, xtol=1e-4)


def radius_for(headings, force: float = PAPER["force"], surge: float = PAPER["max"]) -> float:
    """Anchor radius [m] at which the restoring force at ``surge`` [m] is ``force`` [N]."""
    def miss(R):
        return rc.restoring(LINE, Layout("", headings, radius=R).anchors(), surge)[0] - force
    return brentq(miss, touchdown_radius() * 0.9, taut_radius(HEIGHT, 1e5), xtol=1e-6)


def row(layout: Layout) -> dict:
    """The printed quantities of one layout (forces [N], lengths [m])."""
    a = layout.anchors()
    R = layout.anchor_radius()
    H0, V0 = rc.solve(LINE, R, layout.height)
    f147, _ = rc.restoring(LINE, a, PAPER["mean"])
    f176, t176 = rc.restoring(LINE, a, PAPER["max"])
    x72 = offset_at(a, PAPER["force"])
    return dict(name=layout.name, R=R, T0=math.hypot(H0, V0), H0=H0, f147=f147, f176=f176, t176=t176,
                x44=offset_at(a, RUN["ice_x"]), x48=offset_at(a, RUN["mooring_x"]), x72=x72,
                t72=rc.restoring(LINE, a, x72)[1])


# -- heave and pitch free ----------------------------------------------------------------------
class Hull:
    """The job's semi-submersible (pice.platform.hulls, braces included) with the "balance" mass of
    jobs/zhu_ji_2022_semisub.toml: it floats at the 14 m draft with the lines' pull at rest."""

    def __init__(self, layout: Layout, fairleads: np.ndarray, rho_w: float = 1035.0, g: float = 9.81):
        from pice.platform.hull_buoyancy import buoyancy
        from pice.platform.hulls import semi_submersible, semi_submersible_braces

        self.vertices, self.triangles = semi_submersible()
        self.braces, self.buoyancy = semi_submersible_braces(), buoyancy
        self.rho_w, self.g, self.cg = rho_w, g, np.array([0.0, 0.0, -5.1])
        self.fairleads = np.repeat(np.asarray(fairleads, float), 3, axis=0) - self.cg  # body frame, per line
        self.anchors = self.cg + self.fairleads + layout.anchors()                    # space frame
        self.mass = 0.0
        pull = self.lines(np.zeros(3), pitched(0.0))[0]
        self.mass = (self.hydro(self.cg, pitched(0.0))[0][2] + pull[2]) / g

    def hydro(self, x, q):
        """(force, moment about the CG) [N, N m] of buoyancy and gravity at CG ``x``, attitude ``q``."""
        f, m, _ = self.buoyancy(self.vertices, self.triangles, self.braces, position=x, attitude=q,
                                rho_w=self.rho_w, g=self.g, level=0.0)
        return f + np.array([0.0, 0.0, -self.mass * self.g]), m

    def lines(self, x_shift, q):
        """(force, moment about the CG, largest fairlead tension) [N, N m, N] of the 12 lines, the
        body moved by ``x_shift`` (3,) [m] and turned to attitude ``q``."""
        from pice.kernels.geometry import rotation_matrix

        arm = self.fairleads @ rotation_matrix(q).T
        fl = self.cg + x_shift + arm
        pull, tension = rc.pulls(LINE, self.anchors - fl, np.zeros(3))
        return pull.sum(axis=0), np.cross(arm, pull).sum(axis=0), float(tension.max())

    def equilibrium(self, surge: float, load: np.ndarray, load_my: float):
        """(heave [m], pitch [rad], the lines' horizontal force [N], largest fairlead tension [N]) with
        heave and pitch free at ``surge`` [m], under the external force ``load`` (3,) [N] and
        y-moment ``load_my`` [N m] about the CG."""
        def residual(u):
            fh, mh = self.hydro(self.cg + [surge, 0.0, u[0]], pitched(u[1]))
            fl, ml, _ = self.lines(np.array([surge, 0.0, u[0]]), pitched(u[1]))
            return [(fh[2] + fl[2] + load[2]) / 1e6, (mh[1] + ml[1] + load_my) / 1e8]
        sol = root(residual, [0.0, 0.0], method="hybr", options={"xtol": 1e-10})
        if not sol.success and max(abs(r) for r in residual(sol.x)) > 1e-6:  # 1 N, 100 N m
            raise RuntimeError(f"no heave-pitch equilibrium at {surge} m: {sol.message}")
        f, _, tension = self.lines(np.array([surge, 0.0, sol.x[0]]), pitched(sol.x[1]))
        return sol.x[0], sol.x[1], f[0], tension


def pitched(angle: float) -> np.ndarray:
    """Unit quaternion (w, x, y, z) of a pitch of ``angle`` [rad] about +y."""
    return np.array([math.cos(angle / 2), 0.0, math.sin(angle / 2), 0.0])


def coupled_force(hull: Hull, surge: float, lever: float) -> tuple[float, float, float, float]:
    """(restoring force [N], heave [m], pitch [deg], largest fairlead tension [N]) at ``surge`` [m]
    with heave and pitch free, the body held by a horizontal load equal to the restoring force
    acting ``lever`` [m] above the CG."""
    force = rc.restoring(LINE, hull.anchors - hull.cg - hull.fairleads, surge)[0]
    for _ in range(20):  # the load's moment depends on the force it balances: fixed point
        heave, pitch, fx, tension = hull.equilibrium(surge, np.array([force, 0.0, 0.0]), force * lever)
        if abs(fx + force) < 1e-7 * abs(force) + 1.0:
            break
        force = -fx
    return force, heave, math.degrees(pitch), tension


def coupled_offset(layout: Layout, fairleads: np.ndarray) -> tuple[float, float, float]:
    """(surge [m], heave [m], pitch [deg]) of the static equilibrium under the run's mean loads."""
    hull = Hull(layout, fairleads)
    load = np.array([RUN["ice_x"] + RUN["hull_drag"], 0.0, RUN["ice_z"]])
    surge = brentq(lambda s: hull.equilibrium(s, load, RUN["ice_my"])[2] + load[0], 0.0, 100.0, xtol=1e-3)
    heave, pitch, _, _ = hull.equilibrium(surge, load, RUN["ice_my"])
    return surge, heave, math.degrees(pitch)


CORNERS = np.array([[43.1, 32.3, -15.0], [-43.1, 32.3, -15.0], [-43.1, -32.3, -15.0], [43.1, -32.3, -15.0]])
FACES = np.array([[43.1, 0.0, -15.0], [0.0, 32.3, -15.0], [-43.1, 0.0, -15.0], [0.0, -32.3, -15.0]])


def layouts() -> list[tuple[Layout, np.ndarray]]:
    """The layouts compared, each with its fairleads (for --coupled only) [m]."""
    keel = CORNERS + [0.0, 0.0, 1.0]
    return [(Layout("ours: diagonals, T0 at the fairlead, corners 15 m deep"), CORNERS),
            (Layout("fairleads at the keel (-14 m; 386 m to the anchor on the seabed)", height=386.0), keel),
            (Layout("bundles on the axes 0/90/180/270", headings=AXES), FACES),
            (Layout("bundles 30 deg off the x axis", headings=(30.0, 150.0, 210.0, 330.0)), CORNERS),
            (Layout("bundles 60 deg off the x axis", headings=(60.0, 120.0, 240.0, 300.0)), CORNERS),
            (Layout("221.7 kN read as the horizontal tension H0", measured="horizontal"), CORNERS),
            (Layout("221.7 kN read as the anchor tension", measured="anchor"), CORNERS),
            (Layout("line just touching down at rest", radius=touchdown_radius()), CORNERS),
            (Layout("diagonals, R for 7.2 MN at 17.6 m", radius=radius_for(DIAGONALS)), CORNERS),
            (Layout("axes, R for 7.2 MN at 17.6 m", headings=AXES, radius=radius_for(AXES)), FACES)]


def tension_bound(tension: float = PAPER["tension"], height: float = HEIGHT) -> float:
    """Largest horizontal tension [N] of a line with fairlead tension ``tension`` [N] hanging ``height``
    [m]: the top is at least as steep as the mean slope, sin >= height / stretched length."""
    stretched = sum(p.length * (1.0 + tension / p.ea) for p in LINE)
    return tension * math.sqrt(1.0 - (height / stretched) ** 2)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--coupled", action="store_true", help="also the offset with heave and pitch free (slower)")
    args = ap.parse_args()
    print("| layout | R [m] | T0 / H0 [kN] | F(14.7 m) [MN] | F(17.6 m) [MN] | T_max(17.6 m) [MN] "
          "| x at 4.4 / 4.8 / 7.2 MN [m] | T_max at 7.2 MN [MN] |" + (" coupled x, heave, pitch at the run's loads |"
                                                                      if args.coupled else ""))
    print("|---|---|---|---|---|---|---|---|" + ("---|" if args.coupled else ""))
    for layout, fairleads in layouts():
        r = row(layout)
        line = (f"| {r['name']} | {r['R']:.1f} | {r['T0'] / 1e3:.1f} / {r['H0'] / 1e3:.1f} | {r['f147'] / 1e6:.2f} | "
                f"{r['f176'] / 1e6:.2f} | {r['t176'] / 1e6:.2f} | {r['x44']:.1f} / {r['x48']:.1f} / {r['x72']:.1f} | "
                f"{r['t72'] / 1e6:.2f} |")
        if args.coupled:
            s, h, p = coupled_offset(layout, fairleads)
            line += f" {s:.1f} m, {h:.2f} m, {p:.2f} deg |"
        print(line)
    bound = tension_bound()
    print(f"\nthe run's mean (100-200 s): surge {RUN['surge']} m, heave {RUN['heave']} m, pitch {RUN['pitch']} deg, "
          f"lines' pull {RUN['mooring_x'] / 1e6:.2f} MN")
    print(f"a Table 5 line hanging {HEIGHT:g} m with {PAPER['tension'] / 1e6:g} MN at its fairlead pulls at most "
          f"{bound / 1e6:.3f} MN horizontally: {PAPER['force'] / 1e6:g} MN needs at least "
          f"{PAPER['force'] / bound:.1f} lines pulling straight against the offset (a 4-bundle spread has 6 on the "
          "windward side)")


if __name__ == "__main__":
    main()
