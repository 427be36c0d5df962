"""Issue 20 §5: behaviours of the gap package (modelio.predict, diagnose's checks, the time route's units, the
figures and the route choice) that the mutation runs found unpinned (seed 22 and own seeds).

Each test checks a documented behaviour against a hand computation or the documented contract; the expensive
parts (simulation, diagnosis) are replaced by recorders where the test is about what the benchmark hands them.
Units: mm, N, s.
"""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from chainid.model.base import LinearModel


# ---------------------------------------------------------------- modelio.predict by hand (time-domain records)

def test_predict_time_domain_nrmse_and_pooling_by_hand():
    """Two ramps (not harmonic tests: predicted in the time domain), F = 100·x + e measured; the model is the
    100 N/mm spring, its baseline an 80 N/mm one (no damping, no mass).  NRMSE = sqrt(SSE/Σ(F − F̄)²) per test,
    pooled over the tests' sums; shrinkage 1 − model/baseline."""
    from chainid.gap.modelio import predict
    from chainid.model.augmented import AugmentedModel
    from chainid.model.timedamping import Damping
    from chainid.records.record import Record

    rng = np.random.default_rng(4)
    recs, want = [], {}
    for name, slope in (("A", 1.0), ("B", 2.0)):
        t = np.linspace(0.0, 1.0, 400)
        x = slope * t
        e = 0.5 * rng.normal(size=t.size)
        F = 100.0 * x + e
        recs.append(Record(name, t, x, F))
        var = float(np.sum((F - F.mean()) ** 2))
        want[name] = (float(np.sum((20.0 * x + e) ** 2)), float(np.sum(e * e)), var)
    model = AugmentedModel(LinearModel(100.0, 0.0), [], Damping("none"), 0.0)
    model.baseline = AugmentedModel(LinearModel(80.0, 0.0), [], Damping("none"), 0.0)
    out = predict(model, recs)
    for row in out["tests"]:
        sb, sm, var = want[row["test"]]
        assert row["mode"] == "time-domain"
        assert row["nrmse_baseline"] == pytest.approx(math.sqrt(sb / var), rel=1e-9)
        assert row["nrmse_model"] == pytest.approx(math.sqrt(sm / var), rel=1e-9)
        assert row["shrinkage"] == pytest.approx(1 - math.sqrt(sm / sb), rel=1e-9)
    sb, sm, var = (sum(v[i] for v in want.values()) for i in range(3))
    p = out["pooled"]
    assert (p["nrmse_baseline"], p["nrmse_model"]) == (pytest.approx(math.sqrt(sb / var), rel=1e-9),
                                                       pytest.approx(math.sqrt(sm / var), rel=1e-9))
    assert p["shrinkage"] == pytest.approx(1 - math.sqrt(sm / sb), rel=1e-9)
    assert out["damping_used"] == "none" and "_series" not in out  # the model's damping form (no law here)
    one = predict(model, recs, tests=["B"], fitted=True, keep=True)
    assert [r["test"] for r in one["tests"]] == ["B"] and one["damping_used"] == "none"  # no law: fitted c_e do not exist
    np.testing.assert_allclose(one["_series"]["B"][3], 100.0 * recs[1].x, rtol=1e-12)  # the model's force
    np.testing.assert_allclose(one["_series"]["B"][4], 80.0 * recs[1].x, rtol=1e-12)  # the baseline's
    assert one["pooled"]["nrmse_model"] == pytest.approx(math.sqrt(want["B"][1] / want["B"][2]), rel=1e-9)
    with pytest.raises(ValueError, match=r"--tests: test id\(s\) \['C'\] not in the data; valid ids: A, B"):
        predict(model, recs, tests=["A", "C"])
    with pytest.raises(ValueError, match="no records to predict"):
        predict(model, [])
    # no baseline: the model is its own, shrinkage 0; a constant force has no variance: None, not a NaN
    own = AugmentedModel(LinearModel(100.0, 0.0), [], Damping("none"), 0.0)
    assert predict(own, recs)["pooled"]["shrinkage"] == pytest.approx(0.0, abs=1e-12)
    flat = Record("F", recs[0].t, recs[0].x, np.full(400, 7.0))
    row = predict(own, [flat])["tests"][0]
    assert row["nrmse_model"] is None and row["shrinkage"] is None


# ---------------------------------------------------------------- diagnose: input checks, linear baseline, jack-knife

def _recs(n=5):
    from chainid.records.record import Record

    t = np.linspace(0, 1, 50)
    return [Record(str(i), t, 2.0 + 0.1 * np.sin(2 * np.pi * t), 100.0 * np.sin(2 * np.pi * t) + i)
            for i in range(1, n + 1)]


def test_check_magnitudes_limits_and_dead_channel():
    """|F| <= 1e12 N and |x| <= 1e9 mm (the documented limits, inclusive); a constant F is refused; a record with
    a non-finite value is left to the later checks."""
    from chainid.gap.diagnose import check_magnitudes
    from chainid.records.record import Record

    t = np.linspace(0, 1, 5)
    ok = Record("a", t, np.array([0, 1e9, 0, -1e9, 0.0]), np.array([1e12, -1e12, 0, 1, 2.0]))
    check_magnitudes([ok])
    with pytest.raises(ValueError, match=r"test 'b': \|F\| = 1\.5e\+12 N is out of range; valid range \|F\| <= "
                                         r"1e\+12 N \(check the column's unit\)"):
        check_magnitudes([ok, Record("b", t, ok.x, np.array([0, 1.5e12, 0, 1, 2.0]))])
    with pytest.raises(ValueError, match=r"test 'c': \|x\| = 2e\+09 mm is out of range; valid range \|x\| <= "
                                         r"1e\+09 mm"):
        check_magnitudes([Record("c", t, np.array([0, -2e9, 0, 1, 2.0]), ok.F)])
    with pytest.raises(ValueError, match=r"test 'd': the force F is constant \(7 N in all 5 samples\): a dead "
                                         "channel"):
        check_magnitudes([Record("d", t, ok.x, np.full(5, 7.0))])
    check_magnitudes([Record("e", t, ok.x, np.array([np.nan, 3e12, 7, 7, 7.0]))])  # NaN: not judged here


def test_diagnose_refuses_bad_holdout_options_before_any_work():
    from chainid.gap.diagnose import diagnose

    recs = _recs()
    with pytest.raises(ValueError, match=r"max_combo = 0 is out of range; valid range 1 to 3"):
        diagnose(recs, ["1"], max_combo=0)
    for k in (1, -1):
        with pytest.raises(ValueError, match=rf"--holdout-blocks = {k} is out of range; valid: 0 \(off\) or >= 2"):
            diagnose(recs, ["1"], holdout_blocks=k)
    with pytest.raises(ValueError, match=r"--holdout: no test held out; give test ids or --holdout-blocks K"):
        diagnose(recs, [" ", ""])
    with pytest.raises(ValueError, match=r"--holdout: all 5 tests are held out; leave at least 3 for training"):
        diagnose(recs, [" 1", "2 ", "3", "4", "5"])  # ids are stripped
    with pytest.raises(ValueError, match=r"--holdout: test id\(s\) \['9'\] not in the data; valid ids: 1, 2, 3, 4, 5"):
        diagnose(recs, ["9"])
    bad = _recs(2)
    bad[1] = type(bad[1])("2", bad[1].t, bad[1].x, np.full(50, 3.0))
    with pytest.raises(ValueError, match="the force F is constant"):  # the --validate set is checked too
        diagnose(recs, ["1"], validate=bad)


def test_fit_linear_model_uses_the_training_records_only():
    from chainid.gap.diagnose import fit_linear_model
    from chainid.records.record import Record

    t = np.linspace(0, 1, 30)
    x = 1.0 + 0.5 * np.sin(2 * np.pi * t)
    recs = [Record("a", t, x, 50.0 * (x - 0.2)), Record("b", t, x + 0.3, 50.0 * (x + 0.1)),
            Record("h", t, x, 999.0 * x)]
    m = fit_linear_model(recs, ["h"])
    assert (m.k, m.x_ref) == (pytest.approx(50.0, rel=1e-9), pytest.approx(0.2, rel=1e-9))


def test_jackknife_sd_by_hand():
    """Leave-one-test-out refits give 1, 2, 4: sd = sqrt((n − 1)/n · Σ(v − v̄)²) = sqrt(2/3 · 42/9); a law
    coefficient (``law.*``) is not jack-knifed."""
    from chainid.gap.harmonic.route import jackknife as _jackknife

    vals = iter([1.0, 2.0, 4.0])
    seen = []

    def fit(names, train_only, start, polish_only):  # noqa: ANN001
        seen.append(([d.test for d in train_only], polish_only, dict(start)))
        return SimpleNamespace(params={"friction.F_c": next(vals)})

    prob = SimpleNamespace(train=[SimpleNamespace(test=s) for s in "ABC"], fit=fit)
    cand = SimpleNamespace(names=["friction"], params={"friction.F_c": 2.5, "law.0": 9.0})
    sd = _jackknife(prob, cand)
    assert sd == {"friction.F_c": pytest.approx(math.sqrt(2 / 3 * 42 / 9), rel=1e-12)}
    assert [s[0] for s in seen] == [["B", "C"], ["A", "C"], ["A", "B"]] and all(s[1] for s in seen)


# ---------------------------------------------------------------- the time-domain route is free of the force unit

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


def test_harmonic_diagnosis_baseline_is_invariant_to_the_force_unit():
    """The phase-bin route on 11 steady tests (friction F_c = 150 N, 20 N noise) with F × 1e-7: the baseline
    (linear spring, Eq. 21, per-test NRMSE, dB over noise) is the same to round-off, the noise σ scales by 1e-7,
    the verdict is the same.  (The friction fit itself lands within 2 % of the unscaled one: the optimiser's
    path is not exactly scale-free, so it is held to a looser tolerance.)"""
    from chainid.gap import diagnose
    from chainid.gap.benchmark.grid import grid3x3_plan
    from chainid.model.base import ChainModel
    from chainid.model.effects import parse_effect
    from chainid.model.laws import PolynomialLaw
    from chainid.records.record import Record
    from chainid.records.simulate import simulate

    m = ChainModel()
    recs = simulate(grid3x3_plan(prefix=""), m, PolynomialLaw([0.5, 1.0, 100.0, 20.0, 50.0]), n_cycles=6,
                    samples_per_cycle=64, noise_F=20.0, seed=2, force_fn=parse_effect("friction:F_c=150", m))
    a, b = (diagnose([Record(r.test, r.t, r.x, r.F * s) for r in recs], ["3", "7"], None, quiet=True,
                     uncertainty=False, max_combo=1, effects=["friction", "slack"]) for s in (1.0, 1e-7))
    assert a["verdict"] == b["verdict"] == "friction"
    assert b["baseline"]["damping_law"] == a["baseline"]["damping_law"]
    for k in ("nrmse_train", "nrmse_holdout", "db_over_noise", "nrmse_loto"):
        assert b["baseline"][k] == pytest.approx(a["baseline"][k], rel=1e-9), k
    for k in ("noise_sigma_N", "excess_rms_N"):
        assert b["baseline"][k] == pytest.approx(1e-7 * a["baseline"][k], rel=1e-9), k
    for ta, tb in zip(a["tests"], b["tests"]):
        assert tb["nrmse_before"] == pytest.approx(ta["nrmse_before"], rel=1e-9)
        assert tb["sigma_N"] == pytest.approx(1e-7 * ta["sigma_N"], rel=1e-9)
        assert tb["nrmse_after"] == pytest.approx(ta["nrmse_after"], rel=0.02)
    assert b["steps"][-1]["params"]["friction.F_c"] == pytest.approx(1e-7 * a["steps"][-1]["params"]["friction.F_c"],
                                                                      rel=0.03)


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


# ---------------------------------------------------------------- the phase-route figures show the result's numbers

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
    assert ax1.get_title() == "with friction (red edge: held-out)"
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


# ---------------------------------------------------------------- diagnose_time.build_problem: which route a test takes

def test_build_problem_routes_harmonic_tests_by_the_documented_rule(monkeypatch):
    """Harmonic tests keep the phase-bin route when at least MIN_TRAIN = 3 of them are for training and no
    --holdout-blocks is given; otherwise they join the time-domain records, with a warning saying why; every
    time-domain record is cut in LOO_BLOCKS = 4 blocks (or the --holdout-blocks K)."""
    from chainid.gap.timedomain import route as dt

    made = {}
    monkeypatch.setattr(dt, "prepare_time", lambda r, nb: SimpleNamespace(test=r.test, nb=nb))
    monkeypatch.setattr(dt, "Problem", lambda data, model, hold, law, require_hold: SimpleNamespace(
        tests=[d.test for d in data], hold=hold, law=law, require_hold=require_hold))

    def anyp(tdata, model, holdout, blocks, hprob):  # noqa: ANN001
        made.update(tdata=[(d.test, d.nb) for d in tdata], hprob=hprob, blocks=blocks)
        return made

    monkeypatch.setattr(dt, "AnyProblem", anyp)
    recs = [SimpleNamespace(test=s) for s in ("h1", "h2", "h3", "h4", "r1")]
    hdata = [SimpleNamespace(test=s) for s in ("h1", "h2", "h3", "h4")]
    warn = []
    dt.build_problem(recs, hdata, [recs[4]], ["h4"], 0, "M", "viscous", warn)
    assert made["tdata"] == [("r1", 4)] and warn == []
    assert (made["hprob"].tests, made["hprob"].hold, made["hprob"].law) == (["h1", "h2", "h3", "h4"], ["h4"], "viscous")
    assert made["hprob"].require_hold is False
    dt.build_problem(recs, hdata, [recs[4]], ["h3", "h4"], 0, "M", "auto", warn)  # 2 harmonic training tests
    assert made["hprob"] is None and made["tdata"] == [("r1", 4), ("h1", 4), ("h2", 4), ("h3", 4), ("h4", 4)]
    assert warn == ["4 harmonic test(s) analysed in the time domain with the other records (fewer than 3 harmonic "
                    "training tests for the phase-bin route)"]
    warn.clear()
    dt.build_problem(recs, hdata, [recs[4]], [], 3, "M", "auto", warn)
    assert made["hprob"] is None and made["blocks"] == 3 and {nb for _, nb in made["tdata"]} == {3}
    assert warn == ["4 harmonic test(s) analysed in the time domain with the other records (--holdout-blocks "
                    "splits every record in time)"]
    warn.clear()
    dt.build_problem(recs[4:], [], [recs[4]], ["r1"], 0, "M", "auto", warn)
    assert made["hprob"] is None and warn == [] and made["tdata"] == [("r1", 4)]


# ---------------------------------------------------------------- the time-route figures show the result's numbers
def test_time_route_figures_show_the_results_numbers(time_friction, tmp_path, figs):
    """heatmap.png: one pair of bars per record at x ∓ 0.2 (width 0.4), heights the JSON ``tests`` NRMSE before
    and after; loops.png: the held-out record's held-out samples only (measured F over x); residual_phase.png:
    the held-out time span shaded; residual_surface.png: the baseline residual over (x, ẋ), colour scale ± its
    99th percentile of |r|."""
    from chainid.gap.plots import make_plots

    res = time_friction
    make_plots(res, tmp_path / "p")
    tests = res["tests"]
    ax = figs["heatmap.png"].axes[0]
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
    spans = figs["residual_phase.png"].axes[2].patches
    assert len(spans) == 1 and not figs["residual_phase.png"].axes[0].patches
    sp = spans[0]  # a Rectangle (matplotlib >= 3.9) or a Polygon (older)
    xs = [sp.get_x(), sp.get_x() + sp.get_width()] if hasattr(sp, "get_width") else np.asarray(sp.get_xy())[:, 0]
    assert (min(xs), max(xs)) == (pytest.approx(d.t[held].min()), pytest.approx(d.t[held].max()))
    sc = figs["residual_surface.png"].axes[0].collections[0]
    r = np.concatenate([res["_path"][0]._ev["time"]["res"][dd.test] for dd in prob.tdata])
    np.testing.assert_allclose(sc.get_array(), r, rtol=1e-12)
    assert sc.norm.vmax == pytest.approx(np.quantile(np.abs(r), 0.99), rel=1e-12) and sc.norm.vmin == -sc.norm.vmax


def test_predict_names_the_damping_it_used():
    """A c_e law: "law" (with fitted=True: the fitted c_e only where the law was fitted on the test — none here, so
    the law for the one test); any other form: its name."""
    from chainid.gap.modelio import predict
    from chainid.model.augmented import AugmentedModel
    from chainid.model.timedamping import Damping
    from chainid.records.record import Record

    t = np.linspace(0.0, 1.0, 400)
    recs = [Record("A", t, 1.0 + 0.1 * np.sin(2 * np.pi * 3 * t), 100.0 + 10.0 * np.sin(2 * np.pi * 3 * t))]
    for damping, fitted, want in ((Damping("law", law="viscous", coefficients=[0.0]), False, "law"),
                                  (Damping("law", law="viscous", coefficients=[0.0]), True,
                                   "per-test fitted c_e on 0 test(s) the law was fitted on; the law on the other 1"),
                                  (Damping("law", law="viscous", coefficients=[0.0], per_test={"A": 0.0}), True,
                                   "per-test fitted c_e"),
                                  (Damping("viscous", {"c": 0.0}), True, "viscous"),
                                  (Damping("none"), False, "none")):
        model = AugmentedModel(LinearModel(100.0, 0.0), [], damping, 0.0)
        assert predict(model, recs, fitted=fitted)["damping_used"] == want
