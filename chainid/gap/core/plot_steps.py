"""Figures of both routes: the explanation chain (held-out NRMSE after each step, down to the noise floor) and the
model-free check (the learner's partial dependence of what is left on the state)."""

from __future__ import annotations

import math
from typing import Any


def waterfall_figure(result: dict[str, Any]) -> Any:
    """Bar chart of the held-out NRMSE (log scale) after each step of ``result["steps"]``, with the shrinkage
    of each step, the dB over noise, and the noise floor's NRMSE as a dashed line.  Returns the Figure."""
    import matplotlib.pyplot as plt

    steps = result.get("steps") or []
    names = ["baseline"] + [f"+ {s['effect']}" for s in steps[1:]]
    vals = [s["nrmse_holdout"] for s in steps]
    fig, ax = plt.subplots(figsize=(1.6 + 1.5 * max(len(steps), 1), 3.8))
    xs = range(len(steps))
    colors = ["0.55"] + ["0.8" if s.get("worsened_holdout") else "C3" for s in steps[1:]]
    bars = ax.bar(xs, vals, color=colors, width=0.6)
    for i, (b, s) in enumerate(zip(bars, steps)):
        txt = f"NRMSE {s['nrmse_holdout']:.3g}\n{s['db_over_noise']:.1f} dB over noise"
        if i:
            chg = 100 * (s["nrmse_holdout"] / steps[i - 1]["nrmse_holdout"] - 1)
            txt = f"held-out {chg:+.0f} %" + (" (worse)" if chg > 0 else "") + "\n" + txt
        ax.annotate(txt, (b.get_x() + b.get_width() / 2, b.get_height()), ha="center", va="bottom", fontsize=7)
    # the NRMSE the noise alone would give: the last step's NRMSE scaled down by its dB over noise
    if steps and all(math.isfinite(v) and v > 0 for v in vals):
        last = steps[-1]
        floor = last["nrmse_holdout"] / 10 ** (max(last["db_over_noise"], 0.0) / 20)
        ax.axhline(floor, color="k", ls="--", lw=0.8)
        # at the left edge of the axes, just above the line, clear of the last bars' labels (in axes fraction: a
        # data x beyond the last bar falls outside the axes and is not drawn)
        ax.annotate(f"noise floor (NRMSE {floor:.3g})", (0.01, floor), xycoords=("axes fraction", "data"),
                    fontsize=7, va="bottom", ha="left")
        ax.set_yscale("log")
        ax.set_ylim(min(vals + [floor]) / 3, max(vals) * 4)
    ax.set_xticks(list(xs))
    ax.set_xticklabels(names, rotation=15, fontsize=8)
    ax.set_ylabel("held-out NRMSE")
    ax.set_title(f"explanation chain: {result.get('verdict', '')}", fontsize=9)
    fig.tight_layout()
    return fig


def open_world_figure(result: dict[str, Any]) -> Any:
    """Partial dependence of the model-free learner's prediction of what is left [N] on x, ẋ and the travel since
    the last reversal (:mod:`chainid.gap.core.openworld`), with its verdict as the title; a note when there is no
    learner.  Returns the Figure."""
    import matplotlib.pyplot as plt

    ow = result.get("open_world") or {}
    model, X = ow.get("_model"), ow.get("_X")
    fig, axs = plt.subplots(1, 3, figsize=(10.5, 3.2))
    names = ow.get("features") or []
    for ax, feat, label in zip(axs, ("x", "xd", "travel"), ("x [mm]", "ẋ [mm/s]", "travel since reversal [mm]")):
        ax.set_xlabel(label)
        if model is None or feat not in names or X is None:
            ax.text(0.5, 0.5, "no learner fitted", ha="center", va="center", transform=ax.transAxes, fontsize=8)
            continue
        from sklearn.inspection import partial_dependence

        j = names.index(feat)
        pdp = partial_dependence(model, X, [j], grid_resolution=40, percentiles=(0.02, 0.98))
        ax.plot(pdp["grid_values"][0], pdp["average"][0], "C3-")
        ax.axhline(0.0, color="0.6", lw=0.6)
    axs[0].set_ylabel("predicted residual [N]")
    share = ow.get("predictable_share")
    title = ow.get("message", "model-free check")
    if share is not None:
        title = f"{title} (held-out predictable share {100 * share:.0f} %)"
    fig.suptitle(title, fontsize=8)
    fig.tight_layout()
    return fig
