"""The waterfall figure of the explanation chain (chainid.gap.core.plot_steps): bars, shrinkage and noise floor."""
from __future__ import annotations

import pytest


# ---------------------------------------------------------------- plot_steps.waterfall_figure
def test_waterfall_figure_bars_shrinkage_and_noise_floor():
    """Bars of the held-out NRMSE per step (0.4 → 0.1 → 0.05), each later bar annotated with its held-out change
    against the previous (−75 %, −50 %), and the noise floor 0.05/10^(6/20) = 0.02506 (the last step 6 dB over the
    noise) as a dashed line; log axis from min/3 to max·4 (by hand).  A step that raises the held-out error
    (``worsened_holdout``: 0.05 → 0.08, +60 %) is marked "(worse)" and drawn light grey."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from chainid.gap.core.plot_steps import waterfall_figure

    steps = [{"effect": "baseline", "nrmse_holdout": 0.4, "db_over_noise": 24.0},
             {"effect": "friction", "nrmse_holdout": 0.1, "db_over_noise": 12.0},
             {"effect": "slack", "nrmse_holdout": 0.05, "db_over_noise": 6.0}]
    fig = waterfall_figure({"steps": steps, "verdict": "friction+slack"})
    try:
        ax = fig.axes[0]
        assert [p.get_height() for p in ax.patches] == [0.4, 0.1, 0.05]
        assert [a.xy for a in ax.texts[:3]] == [(0.0, 0.4), (1.0, 0.1), (2.0, 0.05)]  # on top of each bar's centre
        assert [t.get_text() for t in ax.get_xticklabels()] == ["baseline", "+ friction", "+ slack"]
        texts = [t.get_text() for t in ax.texts]
        assert texts[:3] == ["NRMSE 0.4\n24.0 dB over noise", "held-out -75 %\nNRMSE 0.1\n12.0 dB over noise",
                             "held-out -50 %\nNRMSE 0.05\n6.0 dB over noise"]
        floor = 0.05 / 10 ** (6.0 / 20)
        (line,) = ax.lines
        assert line.get_ydata()[0] == pytest.approx(floor, rel=1e-12) and line.get_linestyle() == "--"
        assert texts[3] == "noise floor (NRMSE 0.0251)"
        # the label is drawn: inside the axes once rendered (a label anchored beyond the last bar is not drawn)
        fig.canvas.draw()
        box, frame = ax.texts[3].get_window_extent(), ax.get_window_extent()
        assert ax.texts[3].get_visible() and frame.x0 <= box.x0 and box.x1 <= frame.x1
        assert box.y0 == pytest.approx(ax.transData.transform((0.5, floor))[1], abs=1.0)  # just above the line
        assert ax.get_yscale() == "log"
        assert ax.get_ylim() == (pytest.approx(floor / 3, rel=1e-12), pytest.approx(1.6, rel=1e-12))
        assert ax.get_title() == "explanation chain: friction+slack" and ax.get_ylabel() == "held-out NRMSE"
        # below the noise (dB < 0) the floor is the last step itself
        steps[-1]["db_over_noise"] = -3.0
        fig2 = waterfall_figure({"steps": steps})
        assert fig2.axes[0].lines[0].get_ydata()[0] == pytest.approx(0.05, rel=1e-12)
        plt.close(fig2)
        worse = steps + [{"effect": "backlash", "nrmse_holdout": 0.08, "db_over_noise": 8.0, "worsened_holdout": True}]
        fig3 = waterfall_figure({"steps": worse})
        ax3 = fig3.axes[0]
        assert ax3.texts[3].get_text() == "held-out +60 % (worse)\nNRMSE 0.08\n8.0 dB over noise"
        grey = [p.get_facecolor()[:3] for p in ax3.patches]
        assert grey[3] == pytest.approx((0.8, 0.8, 0.8)) and grey[1] != grey[3] and grey[2] == grey[1]
        plt.close(fig3)
    finally:
        plt.close(fig)
