"""The dynamics figures (chainid.dynamics.plots) show the result in kN and m."""
from __future__ import annotations

import numpy as np
import pytest


def test_figures_show_the_result_in_kN_and_m():
    """The heat map is segment tension [kN] at segment mid-points [m]; the drive plot has segment 1's tension,
    the drive force and the static level in kN with the peak and dynamic factor in the title; the mode plot
    starts each shape at the drive (0 at 0 m) and labels its frequency (hand-made result, 2 segments)."""
    from types import SimpleNamespace

    import matplotlib.pyplot as plt

    from chainid.dynamics.plots import plot_drive_tension, plot_heatmap, plot_modes

    res = SimpleNamespace(t=np.array([0.0, 0.1, 0.2]), positions=np.array([0.0, 1000.0, 3000.0]),
                          tension=np.array([[1e3, 2e3], [3e3, 4e3], [5e3, 6e3]]), drive_force=np.array([0.0, 7e3, 8e3]),
                          static_tension=2500.0, peak_tension=6000.0, dynamic_factor=2.4)
    fig = plot_heatmap(res)
    mesh = fig.axes[0].collections[0]
    np.testing.assert_allclose(np.asarray(mesh.get_array()).reshape(2, 3), res.tension.T * 1e-3)
    # cells centred on the mid-points 0.5 and 2 m (half their spacing, 0.75 m, either side)
    assert fig.axes[0].get_ylim() == (pytest.approx(-0.25), pytest.approx(2.75))
    plt.close(fig)
    fig = plot_drive_tension(res)
    ax = fig.axes[0]
    seg, drive, static = ax.lines
    np.testing.assert_allclose(seg.get_ydata(), [1.0, 3.0, 5.0])
    np.testing.assert_allclose(drive.get_ydata(), [0.0, 7.0, 8.0])
    assert static.get_ydata()[0] == pytest.approx(2.5)
    assert ax.get_title() == "Drive-end tension (peak 6 kN, dynamic factor 2.4)"
    plt.close(fig)
    res.static_tension = 0.0  # no steady level: no line
    fig = plot_drive_tension(res)
    assert len(fig.axes[0].lines) == 2
    plt.close(fig)
    md = SimpleNamespace(positions=np.array([1000.0, 2000.0]), omega=np.array([10.0, 20.0, 30.0]),
                         shapes=np.array([[0.5, 1.0, 0.2], [1.0, -1.0, 0.3]]), frequency_hz=np.array([1.6, 3.2, 4.8]))
    fig = plot_modes(md, n=2)
    lines = fig.axes[0].lines
    assert len(lines) == 2 and [ln.get_label() for ln in lines] == ["mode 1: 1.6 Hz", "mode 2: 3.2 Hz"]
    np.testing.assert_allclose(lines[1].get_xdata(), [0.0, 1.0, 2.0])
    np.testing.assert_allclose(lines[1].get_ydata(), [0.0, 1.0, -1.0])
    plt.close(fig)


def test_save_writes_the_figure_at_120_dpi_and_refuses_to_overwrite(tmp_path):
    """plots.save writes the drive-tension figure (8.0 × 3.6 in) as a PNG of 960 × 432 pixels at the default
    120 dpi (by hand), refuses an existing file without ``force`` (a ValueError naming it, file untouched) and
    overwrites it with ``force``; the figure is closed either way.
    Bugs caught: the default dpi, ``force`` not passed on, the figure left open."""
    from types import SimpleNamespace

    import matplotlib.pyplot as plt

    from chainid.dynamics.plots import plot_drive_tension, save

    res = SimpleNamespace(t=np.array([0.0, 0.1]), tension=np.array([[1e3], [2e3]]), drive_force=np.array([0.0, 1e3]),
                          static_tension=0.0, peak_tension=2e3, dynamic_factor=float("nan"))
    out = tmp_path / "drive.png"
    fig = plot_drive_tension(res)
    assert save(fig, out) == out and not plt.fignum_exists(fig.number)
    assert plt.imread(out).shape[:2] == (432, 960)
    before = out.read_bytes()
    fig = plot_drive_tension(res)
    with pytest.raises(ValueError, match="exists"):
        save(fig, out)
    assert out.read_bytes() == before and not plt.fignum_exists(fig.number)
    fig = plot_drive_tension(res)
    save(fig, out, force=True, dpi=60)
    assert plt.imread(out).shape[:2] == (216, 480)
