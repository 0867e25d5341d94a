"""The figure of a study (pice/study/): for each metric some variant recorded, its change against the
reference variant [%] over the wall time [s] of each variant, points labelled by variant number; and
the cost (particle-steps over wall time). A study that recorded none shows the first five, saying so.
Matplotlib's Agg backend: no display needed. 1200 x 700 pixels.
"""

from __future__ import annotations

import math
import pathlib

from .metrics import METRICS

FIGSIZE = (12.0, 7.0)  # inches
DPI = 100


def plot_study(study: dict, path) -> pathlib.Path:
    """Write the figure of ``study`` (the dict run_study returns) to ``path`` (PNG); return the path."""
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    rows, ref = study["variants"], study["reference"]
    wall = [r["wall_time"] for r in rows]
    log_x = min(wall) > 0 and max(wall) / min(wall) > 20.0
    panels = [(label, [r["change_pct"].get(name, math.nan) for r in rows], "change vs reference [%]")
              for name, _, label in METRICS]
    recorded = [p for p in panels if any(not math.isnan(y) for y in p[1])]
    panels = (recorded or panels[:5]) + [("cost", [float(r["particle_steps"]) for r in rows], "particle-steps")]
    ncols = 3 if len(panels) <= 6 else 4  # every recorded metric gets a panel, the cost last
    fig, axes = plt.subplots(max(2, math.ceil(len(panels) / ncols)), ncols, figsize=FIGSIZE, dpi=DPI,
                             squeeze=False)
    for ax in axes.flat[len(panels):]:
        ax.set_visible(False)
    for ax, (label, ys, ylabel) in zip(axes.flat, panels):
        points = [(x, y, r["variant"]) for x, y, r in zip(wall, ys, rows) if not math.isnan(y)]
        if not points:
            why = "not recorded\n(no body in the job)" if study.get("loads_on") != "body 0" else "not recorded"
            ax.text(0.5, 0.5, why, ha="center", va="center",
                    transform=ax.transAxes, color="0.4")
        for x, y, k in points:
            ax.plot(x, y, "o", color="C3" if k == ref else "C0", ms=6)
            ax.annotate(f"{k}{'*' if k == ref else ''}", (x, y), textcoords="offset points", xytext=(4, 4),
                        fontsize=8)
        if ylabel.startswith("change"):
            ax.axhline(0.0, color="0.6", lw=0.8)
        if log_x:
            ax.set_xscale("log")
        ax.set_title(label, fontsize=9)
        ax.set_xlabel("wall time [s]")
        ax.set_ylabel(ylabel)
        ax.grid(alpha=0.3)
    varied = ", ".join(study["varied"])
    fig.suptitle(f"Study of {pathlib.Path(study['job']).name}: {varied}; loads on {study.get('loads_on', 'body 0')} "
                 f"(* = reference, variant {ref})",
                 fontsize=11)
    fig.tight_layout()
    path = pathlib.Path(path)
    fig.savefig(path, dpi=DPI)
    plt.close(fig)
    return path
