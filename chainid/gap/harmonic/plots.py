"""Figures of the harmonic route (``chainid diagnose --plots DIR``, file names :data:`chainid.gap.plots.PLOT_NAMES`).

loops.png — measured (cycle-averaged) / baseline / augmented loops per held-out test;
residual_phase.png — baseline residual vs cycle phase per test;
residual_surface.png — baseline residual over (x, ẋ) (multi-valued = memory);
heatmap.png — per-test NRMSE before / after over (ω, A);
waterfall.png — the explanation chain: held-out NRMSE after each step, down to the noise floor.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Callable

import numpy as np

__all__ = ["harmonic_plots"]


def harmonic_plots(result: dict[str, Any], save: Callable[[Any, str], Path]) -> list[Path]:
    """Draw the five figures of a harmonic diagnosis ``result``; ``save(fig, name)`` writes one and returns its path."""
    import matplotlib.pyplot as plt

    from chainid.gap.core.verdict import trusted_path

    prob = result["_problem"]
    path = result["_path"]
    final = trusted_path(path)[0][-1]  # the verdict's chain: the baseline itself when no step was taken
    base, aug = path[0]._ev, final._ev  # type: ignore[attr-defined]
    after = "after the chain" if final is not path[0] else "baseline (no step)"
    paths = []
    # loops
    hold = prob.hold
    fig, axs = plt.subplots(1, len(hold), figsize=(4.2 * len(hold), 3.6), squeeze=False)
    for ax, d in zip(axs[0], hold):
        xb = d.binmean(d.x)
        ax.plot(xb, d.Fbar, "k.", ms=3, label="measured (cycle mean)")
        for ev, lab, st in ((base, "baseline", "C0-"), (aug, after, "C3--")):
            Fn, v = ev["parts"][d.test]
            c = ev["c_hold"].get(d.test, ev["c_e"][d.test])
            ax.plot(np.append(xb, xb[0]), np.append(Fn + c * v, (Fn + c * v)[0]), st, lw=1.2, label=lab)
        ax.set_title(f"held-out {d.test}: ω={d.omega:.3g} rad/s, A={d.A:.3g} mm", fontsize=9)
        ax.set_xlabel("x [mm]")
        ax.set_ylabel("F [N]")
    axs[0][0].legend(fontsize=7)
    fig.tight_layout()
    paths.append(save(fig, "loops.png"))
    # residual vs phase
    fig, ax = plt.subplots(figsize=(6.5, 4))
    for d in prob.data:
        r = base["res"][d.test]
        psi = (np.arange(r.size) + 0.5) * 360 / r.size
        ax.plot(psi, r, lw=1.5 if d in hold else 0.7, label=d.test if d in hold else None)
    ax.axhline(0, color="k", lw=0.5)
    ax.set_xlabel("cycle phase ψ of x = x0 + A sin ψ [deg] (90: top turning point)")
    ax.set_ylabel("baseline residual [N]")
    ax.set_title("residual vs cycle phase (thick: held-out)", fontsize=9)
    ax.legend(fontsize=7)
    fig.tight_layout()
    paths.append(save(fig, "residual_phase.png"))
    # residual surface over (x - x0)/A, xdot/(ωA)
    fig, ax = plt.subplots(figsize=(5.5, 4.5))
    allr = np.concatenate([base["res"][d.test] for d in prob.data])
    lim = float(np.max(np.abs(allr))) or 1.0
    for d in prob.data:
        r = base["res"][d.test]
        psi = (np.arange(r.size) + 0.5) * 2 * math.pi / r.size
        rad = d.A / max(dd.A for dd in prob.data)
        sc = ax.scatter(rad * np.sin(psi), rad * np.cos(psi), c=r, cmap="coolwarm", vmin=-lim, vmax=lim, s=10)
    fig.colorbar(sc, ax=ax, label="residual [N]")
    ax.set_xlabel("(x − x0)/A_max")
    ax.set_ylabel("ẋ/(ω A_max)")
    ax.set_aspect("equal")
    ax.set_title("residual restoring-force surface (all tests)", fontsize=9)
    fig.tight_layout()
    paths.append(save(fig, "residual_surface.png"))
    # heat map before / after over (ω, A)
    fig, axs = plt.subplots(1, 2, figsize=(9, 3.8), sharey=True)
    w = np.array([d.omega for d in prob.data])
    A = np.array([d.A for d in prob.data])
    before = np.array([base["per_test"][d.test] for d in prob.data])
    after_v = np.array([aug["per_test"][d.test] for d in prob.data])
    vmax = float(np.nanmax(before)) or 1.0
    for ax, val, title in ((axs[0], before, "baseline NRMSE"), (axs[1], after_v, f"NRMSE {after}")):
        sc = ax.scatter(w, A, c=val, s=700, cmap="viridis", vmin=0, vmax=vmax, marker="s",
                        edgecolors=["r" if d in hold else "none" for d in prob.data], linewidths=1.5)
        for wi, ai, v in zip(w, A, val):  # dark text on the bright end of viridis
            ax.annotate(f"{v:.2g}", (wi, ai), fontsize=7, ha="center", va="center",
                        color="k" if np.isfinite(v) and v > 0.6 * vmax else "w")
        ax.margins(0.12)
        ax.set_xlabel("ω [rad/s]")
        ax.set_title(title + " (red edge: held-out)", fontsize=9)
    axs[0].set_ylabel("A [mm]")
    fig.subplots_adjust(bottom=0.16, right=0.84)
    fig.colorbar(sc, cax=fig.add_axes([0.87, 0.16, 0.02, 0.72]), label="NRMSE per test")
    paths.append(save(fig, "heatmap.png"))
    from chainid.gap.core.plot_steps import waterfall_figure

    paths.append(save(waterfall_figure(result), "waterfall.png"))
    return paths
