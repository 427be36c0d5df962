"""The damping figures (chainid.damping.plots): the loop of one test and the damping surface, their data by hand."""
from __future__ import annotations

import math

import numpy as np
import pytest

from stand_ins import LinearSpring


def Lin():
    """The closed-form spring of these tests: F = 10000·x."""
    return LinearSpring(10000.0)


def test_damping_surface_grid_spans_the_tests_with_10pct_margin(tmp_path):
    """The surface is evaluated on ω from ω_min − 10 % of the span to ω_max + 10 % (and A alike): tests at
    ω = 10, 20, 30 rad/s and A = 0.2, 0.4 mm give ω 8…32 and A 0.18…0.42.  Bugs caught: the margins garbled."""
    from types import SimpleNamespace

    from chainid.damping.plots import plot_damping_surface

    seen = {}

    class Law:
        name = "spy"

        def predict(self, w, A, x0):
            seen.update(w=(w.min(), w.max()), A=(A.min(), A.max()))
            return np.zeros_like(w)

    res = [SimpleNamespace(test=f"T{i}", omega=w, A=A, c_e=1.0, x0=2.0)
           for i, (w, A) in enumerate([(10.0, 0.2), (20.0, 0.4), (30.0, 0.2)])]
    plot_damping_surface(res, Law(), tmp_path / "s.png")
    assert seen["w"] == pytest.approx((8.0, 32.0), rel=1e-12)
    assert seen["A"] == pytest.approx((0.18, 0.42), rel=1e-12)


def test_plot_loop_draws_one_closed_model_cycle(tmp_path):
    """The model loop of plot_loop is one cycle of the fitted harmonic from the window's start: x(t) =
    x0 + A sin(ω(t − t_origin) + θ) over one period 2π/ω from t_start, so it closes and spans x0 ± A (by hand).
    Bug caught: the period's end t_start + 2π/ω garbled (t_start**2·π/ω)."""
    from types import SimpleNamespace

    from chainid.damping.plots import plot_loop

    seen = []

    class Spy(LinearSpring):
        def force(self, x):
            seen.append(np.array(x, float))
            return super().force(x)

    t = np.linspace(0.0, 3.0, 301)
    rec = SimpleNamespace(t=t, x=2.0 + 0.3 * np.sin(10.0 * t), F=1e4 * (2.0 + 0.3 * np.sin(10.0 * t)))
    res = SimpleNamespace(t_start=1.0, t_end=2.5, omega=10.0, t_origin=0.25, theta=0.4, x0=2.0, A=0.3, c_e=5.0,
                          mass_kg=3.2, test="T", W=1.0, W_ratio=1.0)
    plot_loop(rec, res, Spy(), tmp_path / "loop.png")
    xh = seen[-1]  # the elastic force's call on the model cycle
    assert xh.size == 400
    assert xh[0] == pytest.approx(2.0 + 0.3 * math.sin(10.0 * 0.75 + 0.4), rel=1e-12)
    assert xh[-1] == pytest.approx(xh[0], abs=1e-12)  # one whole period: the loop closes
    assert xh.max() == pytest.approx(2.3, abs=1e-4) and xh.min() == pytest.approx(1.7, abs=1e-4)


def _capture(monkeypatch):
    """The figures the damping plots hand to chainid.infra.fileio.save_figure (nothing written)."""
    import chainid.infra.fileio as fileio

    figs = []

    def grab(fig, path, force=True, what="figure", **kw):
        figs.append(fig)
        return path
    monkeypatch.setattr(fileio, "save_figure", grab)
    return figs


def test_plot_loop_shows_the_window_and_eq1_by_hand(monkeypatch, tmp_path):
    """plot_loop's curves in kN: the measured points of the steady window t_start <= t < t_end only; the model
    F = m·ẍ·1e-3 + k·x + c·ẋ on the fitted harmonic with the test's c_e and with the law's c_e(ω, A); the elastic
    force k·x.  k = 1e4 N/mm, m = 3.2 kg, c = 5, law c = 2 N·s/mm (by hand); labels and title state them."""
    from types import SimpleNamespace

    from chainid.damping.plots import plot_loop
    from chainid.model.laws import ViscousLaw

    figs = _capture(monkeypatch)
    t = np.linspace(0.0, 3.0, 301)
    x = 2.0 + 0.3 * np.sin(10.0 * t)
    rec = SimpleNamespace(t=t, x=x, F=1e4 * x + 7.0)
    res = SimpleNamespace(t_start=1.0, t_end=2.5, omega=10.0, t_origin=0.25, theta=0.4, x0=2.0, A=0.3, c_e=5.0,
                          mass_kg=3.2, test="T7", W=12.5, W_ratio=0.875)
    plot_loop(rec, res, Lin(), tmp_path / "loop.png", law=ViscousLaw([2.0]))
    ax = figs[-1].axes[0]
    meas, model, law, elastic = ax.lines
    win = (t >= 1.0) & (t < 2.5)
    np.testing.assert_allclose(meas.get_xdata(), x[win])
    np.testing.assert_allclose(meas.get_ydata(), (1e4 * x[win] + 7.0) * 1e-3)
    xh = np.asarray(model.get_xdata())
    tt = np.linspace(1.0, 1.0 + 2 * math.pi / 10.0, 400)
    psi = 10.0 * (tt - 0.25) + 0.4
    xe, xde, xdde = 2.0 + 0.3 * np.sin(psi), 3.0 * np.cos(psi), -30.0 * np.sin(psi)
    np.testing.assert_allclose(xh, xe, rtol=1e-12)
    for line, c in ((model, 5.0), (law, 2.0)):
        np.testing.assert_allclose(line.get_ydata(), (3.2 * xdde * 1e-3 + 1e4 * xe + c * xde) * 1e-3, rtol=1e-12)
    np.testing.assert_allclose(elastic.get_ydata(), 10.0 * xe, rtol=1e-12)
    labels = [ln.get_label() for ln in ax.lines]
    assert labels == ["measured (steady cycles)", "model, test c_e = 5 N·s/mm", "model, viscous law c_e = 2 N·s/mm",
                      "elastic force F_k(x)"]
    assert ax.get_xlabel() == "elongation x [mm]" and ax.get_ylabel() == "force F [kN]"
    assert ax.get_title() == ("test T7: ω = 10 rad/s, x0 = 2 mm, A = 0.3 mm\n"
                              "W = 12.5 N·mm, W/(π c_e ω A²) = 0.875")


def test_damping_surface_shows_the_law_and_the_tests(monkeypatch, tmp_path):
    """The surface and contour are the law on the padded grid (Eq. 21 with α = (0.01, 0, 0, 10, 1): extremes at the
    grid corners, ω 8…32, A 0.18…0.42: c = 0.01·64 + 1.8 + 1 = 3.44 and 0.01·1024 + 4.2 + 1 = 15.44, by hand);
    the points are the identified (ω, A, c_e), annotated with their test ids."""
    from types import SimpleNamespace

    from chainid.damping.plots import plot_damping_surface
    from chainid.model.laws import PolynomialLaw

    figs = _capture(monkeypatch)
    res = [SimpleNamespace(test=f"T{i}", omega=w, A=A, c_e=c, x0=2.0)
           for i, (w, A, c) in enumerate([(10.0, 0.2, 4.0), (20.0, 0.4, 8.0), (30.0, 0.2, 12.0)])]
    plot_damping_surface(res, PolynomialLaw([0.01, 0.0, 0.0, 10.0, 1.0]), tmp_path / "s.png")
    fig = figs[-1]
    ax3, ax = fig.axes[0], fig.axes[1]
    cs = next(c for c in ax.get_children() if hasattr(c, "zmin"))  # the contour set
    assert (cs.zmin, cs.zmax) == (pytest.approx(3.44, rel=1e-12), pytest.approx(15.44, rel=1e-12))
    pts = next(c for c in ax.collections if c.get_label() == "identified tests")
    np.testing.assert_allclose(pts.get_offsets(), [[10.0, 0.2], [20.0, 0.4], [30.0, 0.2]])
    np.testing.assert_allclose(pts.get_array(), [4.0, 8.0, 12.0])
    ann = [(a.get_text(), a.xy) for a in ax.texts]
    assert ann == [("T0", (10.0, 0.2)), ("T1", (20.0, 0.4)), ("T2", (30.0, 0.2))]
    assert ax3.get_title() == "polynomial law" and ax.get_xlabel() == "ω [rad/s]" and ax.get_ylabel() == "A [mm]"
    assert ax3.get_zlabel() == "c_e [N·s/mm]"


@pytest.mark.slow
def test_plot_all_writes_one_loop_per_test_and_the_surface_only_for_a_fitted_law(tmp_path):
    """``plot_all``: ``loop_<id>.png`` per identified test in result order, plus ``damping_surface.png`` only when
    the law has fitted parameters (``plot_names`` gives the same names); without ``force`` an existing target is
    refused before any figure is drawn (the other test's file is not written).
    Bugs caught: the surface drawn for an unfitted law or dropped for a fitted one, the up-front check skipped."""
    from chainid.damping.identify import identify_records
    from chainid.damping.plots import plot_all, plot_names
    from chainid.model.laws import ViscousLaw
    from chainid.records.simulate import TestSpec, simulate

    plan = [TestSpec(t, w, 2.2, 0.2) for t, w in (("B", 2.0), ("A", 1.0))]
    recs = simulate(plan, Lin(), ViscousLaw([300.0]), n_cycles=3, samples_per_cycle=60, ramp_rate=None)
    res = identify_records(recs, Lin())
    assert plot_names(["B", "A"]) == ["loop_B.png", "loop_A.png", "damping_surface.png"]
    assert plot_names(["B", "A"], surface=False) == ["loop_B.png", "loop_A.png"]
    out = plot_all(recs, res, Lin(), tmp_path / "none")
    assert [p.name for p in out] == ["loop_B.png", "loop_A.png"]
    assert sorted(p.name for p in (tmp_path / "none").iterdir()) == ["loop_A.png", "loop_B.png"]
    out = plot_all(recs, res, Lin(), tmp_path / "unfitted", law=ViscousLaw())
    assert [p.name for p in out] == ["loop_B.png", "loop_A.png"]
    out = plot_all(recs, res, Lin(), tmp_path / "fitted", law=ViscousLaw([300.0]))
    assert [p.name for p in out] == ["loop_B.png", "loop_A.png", "damping_surface.png"]
    d = tmp_path / "kept"
    d.mkdir()
    (d / "loop_A.png").write_bytes(b"mine")
    with pytest.raises(ValueError, match="loop_A.png"):
        plot_all(recs, res, Lin(), d, force=False)
    assert sorted(p.name for p in d.iterdir()) == ["loop_A.png"] and (d / "loop_A.png").read_bytes() == b"mine"
