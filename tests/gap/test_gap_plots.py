"""The diagnosis figures (chainid.gap.plots) show the result's numbers, for the phase-bin and the time-domain
routes; a time-domain diagnosis is invariant to the force unit."""
from __future__ import annotations

import numpy as np
import pytest


def _time_diag(scale):
    from chainid.gap import diagnose
    from chainid.records.record import Record
    from transient_forms import chain_set

    _, recs = chain_set("friction", {"F_c": 60.0}, n=1500)
    rr = [Record(r.test, r.t, r.x, r.F * scale) for r in recs]
    return diagnose(rr, ["r2"], None, quiet=True, uncertainty=False, max_combo=1, effects=["friction"])


@pytest.fixture(scope="module")
def time_friction():
    """A time-domain diagnosis of 3 random records with friction F_c = 60 N (tests/transient_forms.py)."""
    return _time_diag(1.0)


@pytest.mark.slow
def test_time_domain_diagnosis_is_invariant_to_the_force_unit(time_friction):
    """NRMSE is dimensionless and every fitted force scales with F: the same records with F × 1e-7 (a force
    channel in other units; each record's Σ(F − F̄)² then far below 1 N²) give the same per-test NRMSE, the same
    verdict and F_c × 1e-7 (the records: tests/transient_forms.py, friction F_c = 60 N on a random x)."""
    a, b = time_friction, _time_diag(1e-7)
    assert a["route"] == b["route"] == "time" and a["verdict"] == b["verdict"] == "friction"
    for ta, tb in zip(a["tests"], b["tests"]):
        assert tb["nrmse_before"] == pytest.approx(ta["nrmse_before"], rel=1e-9)
        assert tb["nrmse_after"] == pytest.approx(ta["nrmse_after"], rel=1e-4)
    assert b["steps"][-1]["params"]["friction.F_c"] == pytest.approx(1e-7 * a["steps"][-1]["params"]["friction.F_c"],
                                                                      rel=1e-4)
    assert b["steps"][-1]["shrinkage"] == pytest.approx(a["steps"][-1]["shrinkage"], rel=1e-4)


@pytest.fixture
def figs(monkeypatch):
    """The figures the plots save, by file name (``chainid.infra.fileio.save_figure`` spied, still writing)."""
    import chainid.infra.fileio

    saved = {}
    orig = chainid.infra.fileio.save_figure

    def spy(fig, path, *a, **k):  # noqa: ANN001
        saved[path.name] = fig
        return orig(fig, path, *a, **k)

    monkeypatch.setattr(chainid.infra.fileio, "save_figure", spy)
    return saved


@pytest.mark.slow
def test_phase_route_figures_show_the_results_numbers(tmp_path, figs):
    """heatmap: each square's colour and label are the test's NRMSE before/after of the JSON ``tests`` (2
    digits), colour scale 0 … the largest baseline NRMSE, held-out squares edged red; residual surface: every
    test's bins on a circle of radius A/A_max; residual vs phase: held-out lines thick (1.5), the others thin;
    loops: model loops closed (last point = first)."""
    from chainid.gap import diagnose
    from chainid.gap.benchmark.grid import grid3x3_plan
    from chainid.gap.plots import make_plots
    from chainid.model.base import ChainModel
    from chainid.model.effects import parse_effect
    from chainid.model.laws import PolynomialLaw
    from chainid.records.simulate import simulate

    m = ChainModel()
    recs = simulate(grid3x3_plan(prefix=""), m, PolynomialLaw([0.5, 1.0, 100.0, 20.0, 50.0]), n_cycles=6,
                    samples_per_cycle=64, noise_F=20.0, seed=2, force_fn=parse_effect("friction:F_c=150", m))
    res = diagnose(recs, ["3", "7"], m, quiet=True, uncertainty=False, max_combo=1, effects=["friction"])
    make_plots(res, tmp_path / "p")
    tests = {t["test"]: t for t in res["tests"]}
    vmax = max(t["nrmse_before"] for t in tests.values())
    ax0, ax1 = figs["heatmap.png"].axes[:2]
    for ax, key in ((ax0, "nrmse_before"), (ax1, "nrmse_after")):
        sc = ax.collections[0]
        want = [tests[t][key] for t in tests]  # the problem's data order is the records' order
        np.testing.assert_allclose(sc.get_array(), want, rtol=1e-12)
        assert sc.norm.vmin == 0 and sc.norm.vmax == pytest.approx(vmax, rel=1e-12)
        assert [a.get_text() for a in ax.texts] == [f"{v:.2g}" for v in want]
        # dark text on the bright end of viridis (above 0.6 of the scale), white below
        assert [a.get_color() for a in ax.texts] == ["k" if v > 0.6 * vmax else "w" for v in want]
        red = [tuple(c) for c in sc.get_edgecolors()]
        assert sum(c[:3] == (1.0, 0.0, 0.0) for c in red) == 2  # the two held-out tests
    assert res["verdict"] == "friction" and len(res["steps"]) == 2  # the chain whose NRMSE the right panel shows
    assert ax1.get_title() == "NRMSE after the chain (red edge: held-out)"
    assert {a.get_color() for a in ax0.texts + ax1.texts} == {"k", "w"}
    # the residual's systematic excess is sqrt(max(r2 − f2, 0)) and its dB 10·log10(r2/f2): below the floor
    # (friction leaves less than the noise, r2 < f2, dB < 0) the excess is 0
    r = res["residual"]
    assert r["db_over_noise"] < 0 and r["excess_rms_N"] == 0.0
    Amax = max(t["A"] for t in tests.values())
    surf = figs["residual_surface.png"].axes[0]
    for coll, t in zip(surf.collections, tests.values()):
        xy = coll.get_offsets()
        np.testing.assert_allclose(np.hypot(xy[:, 0], xy[:, 1]), t["A"] / Amax, rtol=1e-12)
    ph = figs["residual_phase.png"].axes[0]
    widths = {ln.get_label(): ln.get_linewidth() for ln in ph.lines[:-1]}
    assert widths["3"] == widths["7"] == 1.5 and sorted(widths.values()).count(0.7) == len(tests) - 2
    for ax in figs["loops.png"].axes:
        for ln in ax.lines[1:]:
            y = ln.get_ydata()
            assert y[0] == y[-1] and ln.get_xdata()[0] == ln.get_xdata()[-1]


# ---------------------------------------------------------------- the time-route figures show the result's numbers
@pytest.mark.slow
def test_time_route_figures_show_the_results_numbers(time_friction, tmp_path, figs):
    """The time route's files (TIME_PLOTS: no heatmap.png, no residual_phase.png); records.png: one pair of bars
    per record at x ∓ 0.2 (width 0.4), heights the JSON ``tests`` NRMSE before and after; loops.png: the held-out
    record's held-out samples only (measured F over x); residual_time.png: the held-out time span shaded;
    residual_surface.png: the baseline residual over (x, ẋ), colour scale ± its 99th percentile of |r|."""
    from chainid.gap.plots import make_plots

    res = time_friction
    paths = make_plots(res, tmp_path / "p")
    assert [p.name for p in paths] == ["loops.png", "residual_time.png", "residual_surface.png", "records.png",
                                       "waterfall.png", "open_world.png"]
    assert sorted(p.name for p in (tmp_path / "p").iterdir()) == sorted(p.name for p in paths)
    tests = res["tests"]
    ax = figs["records.png"].axes[0]
    bars = ax.patches
    assert len(bars) == 2 * len(tests)
    for i, t in enumerate(tests):
        b, a = bars[i], bars[len(tests) + i]
        assert (b.get_x(), b.get_width(), a.get_x()) == (pytest.approx(i - 0.4), pytest.approx(0.4), pytest.approx(i))
        assert b.get_height() == pytest.approx(t["nrmse_before"], rel=1e-12)
        assert a.get_height() == pytest.approx(t["nrmse_after"], rel=1e-12)
    assert [tl.get_text() for tl in ax.get_xticklabels()] == [t["test"] for t in tests]
    prob = res["_problem"]
    data = {d.test: d for d in prob.tdata}
    loops = {a.get_title().split(" ")[0]: a for a in figs["loops.png"].axes}
    d = data["r2"]
    held = ~prob.train_mask("r2")
    assert loops["r2"].get_title() == "r2 (held-out samples)" and loops["r0"].get_title() == "r0 (training)"
    np.testing.assert_array_equal(loops["r2"].lines[0].get_ydata(), d.F[held])
    np.testing.assert_array_equal(loops["r0"].lines[0].get_ydata(), data["r0"].F)
    spans = figs["residual_time.png"].axes[2].patches
    assert len(spans) == 1 and not figs["residual_time.png"].axes[0].patches
    sp = spans[0]  # a Rectangle (matplotlib >= 3.9) or a Polygon (older)
    xs = [sp.get_x(), sp.get_x() + sp.get_width()] if hasattr(sp, "get_width") else np.asarray(sp.get_xy())[:, 0]
    assert (min(xs), max(xs)) == (pytest.approx(d.t[held].min()), pytest.approx(d.t[held].max()))
    sc = figs["residual_surface.png"].axes[0].collections[0]
    r = np.concatenate([res["_path"][0]._ev["time"]["res"][dd.test] for dd in prob.tdata])
    np.testing.assert_allclose(sc.get_array(), r, rtol=1e-12)
    assert sc.norm.vmax == pytest.approx(np.quantile(np.abs(r), 0.99), rel=1e-12) and sc.norm.vmin == -sc.norm.vmax
