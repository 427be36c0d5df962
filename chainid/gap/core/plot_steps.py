"""The explanation chain as a figure: held-out NRMSE after each step, down to the noise floor."""

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
        ax.annotate(f"noise floor (NRMSE {floor:.3g})", (len(steps) - 0.5, floor), fontsize=7, va="bottom",
                    ha="right")
        ax.set_yscale("log")
        ax.set_ylim(min(vals + [floor]) / 3, max(vals) * 4)
    ax.set_xticks(list(xs))
    ax.set_xticklabels(names, rotation=15, fontsize=8)
    ax.set_ylabel("held-out NRMSE")
    ax.set_title(f"explanation chain: {result.get('verdict', '')}", fontsize=9)
    fig.tight_layout()
    return fig
