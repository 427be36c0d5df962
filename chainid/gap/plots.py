"""Figures of ``chainid diagnose --plots DIR``: one set of file names, drawn by the route that diagnosed the set
(:mod:`chainid.gap.harmonic.plots`, :mod:`chainid.gap.timedomain.plots`).

Both routes: loops.png (measured, baseline and final model), residual_surface.png (the baseline residual over x and
ẋ), waterfall.png (the held-out NRMSE after each step, down to the noise floor), open_world.png (the model-free
learner's partial dependence of what is left on x, ẋ and the travel since reversal).  The harmonic route adds
residual_phase.png (the residual over the cycle phase) and heatmap.png (per-test NRMSE over (ω, A)); the
time-domain route residual_time.png (the residual over time) and records.png (per-record NRMSE).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any


#: The files of each route, in order (both: loops, residual surface, waterfall, open world).
HARMONIC_PLOTS = ("loops.png", "residual_phase.png", "residual_surface.png", "heatmap.png", "waterfall.png",
                  "open_world.png")
TIME_PLOTS = ("loops.png", "residual_time.png", "residual_surface.png", "records.png", "waterfall.png",
              "open_world.png")
#: every file :func:`make_plots` may write (checked before a diagnosis runs, when the route is not yet known)
PLOT_NAMES = tuple(dict.fromkeys(HARMONIC_PLOTS + TIME_PLOTS))


def make_plots(result: dict[str, Any], outdir: str | Path, force: bool = True) -> list[Path]:
    """Write the route's figures (:data:`HARMONIC_PLOTS` or :data:`TIME_PLOTS`) atomically; returns their paths.

    With ``force`` False an existing file of those names is an error (checked before drawing).
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from chainid.infra.fileio import check_output_dir, save_figure

    names = TIME_PLOTS if result.get("route") in ("time", "mixed") else HARMONIC_PLOTS
    out = check_output_dir(outdir, "--plots", names, force=force)
    out.mkdir(parents=True, exist_ok=True)

    def save(fig: Any, name: str) -> Path:
        assert name in names
        try:
            return save_figure(fig, out / name, force=force, what="--plots", dpi=90)
        finally:
            plt.close(fig)

    if result.get("route") in ("time", "mixed"):  # records analysed in the time domain
        from chainid.gap.timedomain.plots import time_plots

        paths = time_plots(result, save)
    else:
        from chainid.gap.harmonic.plots import harmonic_plots

        paths = harmonic_plots(result, save)
    from chainid.gap.core.plot_steps import open_world_figure

    return paths + [save(open_world_figure(result), "open_world.png")]
