"""Figures of ``chainid diagnose --plots DIR`` for the time-domain route (:data:`chainid.gap.plots.TIME_PLOTS`).

loops.png — measured F(x) with the baseline and the final model, over each record's held-out samples;
residual_time.png — the residual over time per record (baseline and final model; held-out part marked);
residual_surface.png — the baseline residual over (x, ẋ) (multi-valued = memory);
records.png — NRMSE per record before / after (bars);
waterfall.png — the explanation chain (as the harmonic route).
(open_world.png, of both routes, is drawn by :func:`chainid.gap.plots.make_plots`.)

Units: mm, N, s.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Callable

import numpy as np


def time_plots(result: dict[str, Any], save: Callable[[Any, str], Path]) -> list[Path]:
    """Draw the five figures of a time-domain / mixed diagnosis; ``save(fig, name)`` writes one."""
    import matplotlib.pyplot as plt

    from chainid.gap.core.plot_steps import waterfall_figure
    from chainid.gap.core.verdict import trusted_path

    prob, path = result["_problem"], result["_path"]
    base, final = path[0], trusted_path(path)[0][-1]  # the verdict's chain (the baseline when it is empty)
    eb, ef = base._ev["time"], final._ev["time"]  # type: ignore[attr-defined]
    data = prob.tdata
    hold = {d.test: ~prob.train_mask(d.test) for d in data}
    paths = []
    n = len(data)
    fig, axs = plt.subplots(1, n, figsize=(4.4 * n, 3.8), squeeze=False)
    for ax, d in zip(axs[0], data):
        m = hold[d.test] if hold[d.test].any() else np.ones(d.t.size, bool)
        ax.plot(d.x[m], d.F[m], "k-", lw=0.4, label="measured")
        ax.plot(d.x[m], eb["force"][d.test][m], "C0-", lw=0.6, label="baseline")
        ax.plot(d.x[m], ef["force"][d.test][m], "C3--", lw=0.6, label="after the chain" if final is not base else "baseline (no step)")
        ax.set_title(f"{d.test} ({'held-out samples' if hold[d.test].any() else 'training'})", fontsize=9)
        ax.set_xlabel("x [mm]")
        ax.set_ylabel("F [N]")
    axs[0][0].legend(fontsize=7)
    fig.tight_layout()
    paths.append(save(fig, "loops.png"))
    fig, axs = plt.subplots(n, 1, figsize=(8, 2.2 * n), squeeze=False, sharex=False)
    for ax, d in zip(axs[:, 0], data):
        ax.plot(d.t, eb["res"][d.test], "C0-", lw=0.4, label="baseline")
        ax.plot(d.t, ef["res"][d.test], "C3-", lw=0.4, label="after the chain" if final is not base else "baseline (no step)")
        if hold[d.test].any():
            ax.axvspan(float(d.t[hold[d.test]].min()), float(d.t[hold[d.test]].max()), color="0.9", zorder=0)
        ax.set_ylabel(f"{d.test}\nresidual [N]", fontsize=8)
    axs[-1, 0].set_xlabel("t [s] (grey: held out)")
    axs[0, 0].legend(fontsize=7)
    fig.tight_layout()
    paths.append(save(fig, "residual_time.png"))
    fig, ax = plt.subplots(figsize=(5.5, 4.5))
    r = np.concatenate([eb["res"][d.test] for d in data])
    X, V = np.concatenate([d.x for d in data]), np.concatenate([d.xd for d in data])
    lim = float(np.quantile(np.abs(r), 0.99)) or 1.0
    sc = ax.scatter(X, V, c=r, s=2, cmap="coolwarm", vmin=-lim, vmax=lim, rasterized=True)
    fig.colorbar(sc, ax=ax, label="baseline residual [N] (colour clipped at its 99th percentile)")
    # the axes span the 0.5–99.5 % of each state: a derivative spike does not squash the picture
    for setlim, v in ((ax.set_xlim, X), (ax.set_ylim, V)):
        lo, hi = np.quantile(v, [0.005, 0.995])
        pad = 0.05 * (hi - lo) or 1.0
        setlim(lo - pad, hi + pad)
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("ẋ [mm/s]")
    ax.set_title("baseline residual over (x, ẋ), all records (0.5–99.5 % of each axis)", fontsize=8)
    fig.tight_layout()
    paths.append(save(fig, "residual_surface.png"))
    fig, ax = plt.subplots(figsize=(max(5, 0.9 * len(result["tests"])), 3.8))
    ids = [t["test"] for t in result["tests"]]
    bef = [t["nrmse_before"] if t["nrmse_before"] is not None else np.nan for t in result["tests"]]
    aft = [t["nrmse_after"] if t["nrmse_after"] is not None else np.nan for t in result["tests"]]
    xs = np.arange(len(ids))
    ax.bar(xs - 0.2, bef, 0.4, label="baseline")
    after = result.get("verdict") if result.get("verdict") not in (None, "none", "unexplained") else "baseline"
    ax.bar(xs + 0.2, aft, 0.4, label=f"after the chain ({after})")
    ax.set_xticks(xs, ids, rotation=45, ha="right", fontsize=7)
    ax.set_ylabel("NRMSE per record (held-out records: held-out)")
    ax.legend(fontsize=7)
    fig.tight_layout()
    paths.append(save(fig, "records.png"))
    paths.append(save(waterfall_figure(result), "waterfall.png"))
    return paths
