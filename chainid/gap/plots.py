"""Figures of ``chainid diagnose --plots DIR``: one set of file names, drawn by the route that diagnosed the set
(:mod:`chainid.gap.harmonic.plots`, :mod:`chainid.gap.timedomain.plots`).

loops.png — measured (cycle-averaged) / baseline / augmented loops per held-out test;
residual_phase.png — baseline residual vs cycle phase per test;
residual_surface.png — baseline residual over (x, ẋ) (multi-valued = memory);
heatmap.png — per-test NRMSE before / after over (ω, A);
waterfall.png — the explanation chain: held-out NRMSE after each step, down to the noise floor.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any


#: The files :func:`make_plots` writes, in order.
PLOT_NAMES = ("loops.png", "residual_phase.png", "residual_surface.png", "heatmap.png", "waterfall.png")


def make_plots(result: dict[str, Any], outdir: str | Path, force: bool = True) -> list[Path]:
    """Write the five figures (:data:`PLOT_NAMES`) atomically; returns their paths.

    With ``force`` False an existing file of those names is an error (checked before drawing).
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from chainid.infra.fileio import check_output_dir, save_figure

    out = check_output_dir(outdir, "--plots", PLOT_NAMES, force=force)
    out.mkdir(parents=True, exist_ok=True)
    def save(fig: Any, name: str) -> Path:
        assert name in PLOT_NAMES
        try:
            return save_figure(fig, out / name, force=force, what="--plots", dpi=90)
        finally:
            plt.close(fig)

    if result.get("route") in ("time", "mixed"):  # records analysed in the time domain
        from chainid.gap.timedomain.plots import time_plots

        return time_plots(result, save)
    from chainid.gap.harmonic.plots import harmonic_plots

    return harmonic_plots(result, save)
