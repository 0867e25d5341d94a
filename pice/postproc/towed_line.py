"""The figure of the towed-line test (pice/scenes/towed_line.py): the top tension and the vertical
motion of the marker 0.8 m from the top against time, one curve per element count. Matplotlib's
Agg backend: no display needed.
"""

from __future__ import annotations


def plot_towed_line(results, path) -> None:
    """Save the top-tension and marker traces of ``pice.scenes.towed_line.run`` results to ``path`` (PNG)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (a, b) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    for r in results:
        a.plot(r["t"], r["tension"], label=f"{r['elements']} elements")
        b.plot(r["t"], 1e3 * (r["z"] - r["z"].mean()), label=f"{r['elements']} elements")
    a.set_ylabel("top tension [N]")
    b.set_ylabel("marker 0.8 m from top: z - mean [mm]")
    b.set_xlabel("time [s]")
    a.legend()
    a.set_title("Towed line (Zhu & Ji 2022, Table 2): top end in surge, 75 mm, 1.58 s")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
