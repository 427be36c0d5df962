"""Pins of the audit's validation-case forward prediction (finding d) to the closed form (mutation survivors,
issue 20 §5).  Units: mm, N, s, kg."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.damping.audit import VALIDATION, audit
from stand_ins import LinearSpring


def Lin():
    """The closed-form spring of these tests: F = 10000·x."""
    return LinearSpring(10000.0)


def test_finding_d_forward_prediction_closed_form():
    """x = x0 + A sin ψ with ψ = ωt over one period: F = k x + m ẍ·1e-3 + c ẋ = k x0 + B sin ψ + C cos ψ with
    B = A(k − m ω²·1e-3), C = c ω A, so F_max,min = k x0 ± sqrt(B² + C²) (721 samples over the period: the sampled
    extreme misses by at most amp·(1 − cos(π/720)) < 1e-5·amp).
    Bugs caught: ẋ = ωA cos ψ garbled (ω/A), the prediction skipped when a model is given."""
    f = {x["id"]: x for x in audit(Lin())["findings"]}["d"]["numbers"]
    w = 2 * math.pi * VALIDATION["f_Hz"]
    A, x0, k, m = VALIDATION["A"], VALIDATION["x0"], 1e4, 3.2
    for key in ("omega_7", "omega_14pi"):
        c = f[f"c_e_{key}"]
        B, C = A * (k - m * w * w * 1e-3), c * w * A
        amp = math.hypot(B, C)
        assert f[f"F_max_N_{key}"] == pytest.approx(k * x0 + amp, abs=1e-5 * amp)
        assert f[f"F_min_N_{key}"] == pytest.approx(k * x0 - amp, abs=1e-5 * amp)
    assert f["F_k_range_N"] == pytest.approx([k * (x0 - A), k * (x0 + A)], rel=1e-9)


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


def test_finding_c_half_swing_of_a_linear_spring():
    """k = 1e4 N/mm: half the swing of F_k over x0 ± A is k·A, its value at x0 is k·x0 (EQ27's x0, A).
    Bug caught: 0.5·(F₊ − F₋) garbled."""
    from chainid.damping.audit import EQ27

    f = {x["id"]: x for x in audit(Lin())["findings"]}["c"]["numbers"]
    assert f["F_k_swing_half_N"] == pytest.approx(1e4 * EQ27["A"], rel=1e-12)
    assert f["F_k_at_x0_N"] == pytest.approx(1e4 * EQ27["x0"], rel=1e-12)
    assert f["k_e_range_x0_pm_A_N_per_mm"] == [1e4, 1e4]


# ---------------------------------------------------------------- seed-21 survivors (issue 20 §5)
class HeavySpring(LinearSpring):
    """F = 10000·x with a 500 kg moving mass: m·ω²·1e-3 = 967 N/mm at 7 Hz, a tenth of k (the inertia shows)."""

    mass_kg = 500.0


def test_finding_d_inertia_term_of_a_heavy_mass():
    """The closed form of test_finding_d_forward_prediction_closed_form with m = 500 kg, where the inertia term
    −m·ω²·A·sin ψ·1e-3 moves the extremes by hundreds of N.  Bug caught: ẍ = −ω²·A sin ψ garbled (−ω + 2·A sin ψ),
    invisible next to c·ω·A with the chain's 3.2 kg."""
    f = {x["id"]: x for x in audit(HeavySpring())["findings"]}["d"]["numbers"]
    w = 2 * math.pi * VALIDATION["f_Hz"]
    A, x0, k, m = VALIDATION["A"], VALIDATION["x0"], 1e4, 500.0
    for key in ("omega_7", "omega_14pi"):
        B, C = A * (k - m * w * w * 1e-3), f[f"c_e_{key}"] * w * A
        amp = math.hypot(B, C)
        assert f[f"F_max_N_{key}"] == pytest.approx(k * x0 + amp, abs=1e-5 * amp)
        assert f[f"F_min_N_{key}"] == pytest.approx(k * x0 - amp, abs=1e-5 * amp)


def test_finding_a_paper_omega_over_the_column_is_pi_over_10():
    """Eq. 25's ω of test 3 is 1.884 rad/s where Table 1's column says 6: 1.884/6 = 0.314 = π/10 to 0.051 %
    (by hand), the unit factor finding (a) is about.  Bug caught: 1.884 // 6 = 0."""
    f = {x["id"]: x for x in audit(Lin())["findings"]}["a"]["numbers"]
    assert f["eq25_omega_test3_rad_s"] == 1.884
    assert f["eq25_over_column_test3"] == pytest.approx(0.314, rel=1e-12)
    assert f["eq25_over_column_test3"] == pytest.approx(math.pi / 10, rel=6e-4)
    assert f["column_equals_f_Hz_times"] == pytest.approx(20.0, rel=1e-12)  # 2π/(π/10)


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


def test_test_result_defaults_of_a_hand_made_result():
    """A TestResult built by hand (a side file's values) used no cycles and no window: n_cycles 0, no kept
    cycles, source "estimated" (the documented defaults)."""
    from chainid.damping.identify import TestResult

    r = TestResult("T", 10.0, 2.0, 0.3, 2e4, 3e3, 0.1, 0.99, 300.0, 100.0, 50.0)
    d = r.to_dict()
    assert (d["n_cycles"], d["cycles_kept"], d["source"], d["t_start"], d["t_end"]) == (0, [], "estimated", 0.0, 0.0)


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


def test_findings_summaries_state_the_hand_numbers():
    """The audit's findings as the reader gets them: each summary's numbers from the paper's Table 1 and Eq. 26/27
    by hand (test 1: ω = 0.1π·1 rad/s, A = 0.25 mm; Eq. 26: F_A = 19522.1 N, φ = −0.835, F0 = 11117.21 N) on the
    spring k = 1e4 N/mm."""
    from chainid.damping.audit import format_audit, load_table1

    rep = audit(Lin())
    s = {x["id"]: x["summary"] for x in rep["findings"]}
    tb = load_table1()
    fac = tb["F_ac"] / (tb["c_e"] * tb["A"] * tb["omega_col"])  # ω / column implied by c_e = F_ac/(ωA)
    f29 = fac[1:]
    assert s["a"].startswith(f"For tests 2-9, F_ac/(c_e A) = {f29.mean():.5f} x column (spread "
                             f"{100 * np.ptp(f29) / f29.mean():.3f} %), i.e. pi/10 = 0.31416 to "
                             f"{100 * abs(f29.mean() / (math.pi / 10) - 1):.3f} % (the paper rounds it to 0.3140")
    assert f"F_ac/(omega A) is {f29.mean():.3f} x the tabulated c_e" in s["a"]
    w1 = 0.1 * math.pi
    ce1 = 8000.0 / (w1 * 0.25)
    assert s["b"] == (f"At omega = 0.3142 rad/s, F_ac = 8000 N gives c_e = {ce1:.1f} N s/mm, {ce1 / 5095.5:.2f} x the "
                      f"tabulated 5095.5; c_e = 5095.5 needs F_ac = {5095.5 * w1 * 0.25:.1f} N.")
    assert s["c"] == ("F_A/A = 19522.1/0.25 = 78088 N/mm. The model's k_e(2.2 mm) = 10000 N/mm, so F_A/A is 7.81 x k_e; "
                      "the model's F_k(2.2 mm) = 22000 N against F0 = 11117 N. F0 - F_A = -8404.9 N < 0: the fitted "
                      "force would compress the chain.")
    v = 19522.1 * math.sin(-0.835)
    assert s["e"].startswith(f"With x = x0 + A sin(omega t), the part of F in phase with the velocity is F_A sin(phi) = "
                             f"{v:.0f} N")
    assert f"W = pi A F_A sin(phi) = {math.pi * 0.25 * v:.0f} N mm < 0" in s["e"]
    d = {x["id"]: x for x in rep["findings"]}["d"]["numbers"]
    assert ("the elastic part alone spans [19300, 25700] N." in s["d"]  # k·(2.25 ∓ 0.32)
            and f"with omega = 14 pi = {14 * math.pi:.2f} rad/s" in s["d"]
            and f"({d['c_e_omega_14pi'] / d['c_e_omega_7']:.1f} x)" in s["d"]
            and "(20 f = 140)" in s["d"] and "0.314-3.142 rad/s" in s["d"])
    text = format_audit(rep)
    for f in rep["findings"]:
        assert f"({f['id']}) {f['title']}\n    {f['summary']}" in text
    assert "  matches the paper to 4 significant figures: yes" in text


def test_linear_spring_fitted_on_the_steady_window_only():
    """F = 1000·(x − 0.5) N exactly on the steady cycles, but 300 N off during the first 3 s of ramp-in (amplitude
    growing): the spring fitted on the steady window is k = 1000 N/mm, x_ref = 0.5 mm (the ramp left out)."""
    from chainid.damping.identify import linear_model_from_records
    from chainid.records.record import Record

    t = np.arange(0.0, 20.0, 1 / 128)
    amp = 0.3 * np.minimum(t / 3.0, 1.0)
    x = 2.0 + amp * np.sin(2 * math.pi * t)
    F = 1000.0 * (x - 0.5) + np.where(t < 3.0, 300.0, 0.0)
    m = linear_model_from_records([Record("R", t, x, F)])
    assert m.k == pytest.approx(1000.0, rel=1e-6) and m.x_ref == pytest.approx(0.5, abs=1e-6)


def test_finding_d_minimum_of_eq21_in_omega():
    """Eq. 21 is a parabola in ω with its minimum at −α₂/(2α₁) = 651.57/(2·28.024) = 11.63 column units (the paper's
    Eq. 28 by hand), outside the tested 1–10."""
    from chainid.damping.audit import EQ28_PAPER

    f = {x["id"]: x for x in audit(Lin())["findings"]}["d"]
    w_min = -EQ28_PAPER[1] / (2 * EQ28_PAPER[0])
    assert f["numbers"]["omega_of_minimum_c_e_column_unit"] == pytest.approx(w_min, rel=1e-3)
    assert f"the minimum of Eq. 21 in omega is at {w_min:.2f} column units, outside the tested 1-10." in f["summary"]


def test_finding_a_column_as_omega_ratio_per_test_by_hand():
    """Finding (a)'s c_e computed with the column used as ω, over the tabulated c_e, per test: F_ac/(col·A)/c_e from
    the paper's Table 1 typed in here (test 2: 1100/(4·0.25)/3503.2 = 0.31400; test 4: 1465/(8·0.25)/2332.8 = 0.31400).
    Bug caught: a floor division in F_ac/(col·A)."""
    col = [1, 4, 6, 8, 10, 6, 6, 6, 6]
    A = [0.25, 0.25, 0.25, 0.25, 0.25, 0.2, 0.3, 0.35, 0.4]
    F_ac = [8000, 1100, 1335, 1465, 1542, 985, 1643, 2017, 2329]
    c_e = [5095.5, 3503.2, 2834.4, 2332.8, 1964.3, 2614.1, 2906.9, 3058.8, 3090.5]
    hand = [f / (w * a) / c for f, w, a, c in zip(F_ac, col, A, c_e)]
    f = {x["id"]: x for x in audit(Lin())["findings"]}["a"]["numbers"]
    np.testing.assert_allclose(f["ce_from_Fac_with_column_as_omega_over_table_ce"], hand, rtol=1e-12)
    assert hand[1] == pytest.approx(0.31400, abs=1e-5) and hand[3] == pytest.approx(0.31400, abs=1e-5)


def _exact_law_tests(alpha):
    """Nine hand-made identified tests (ω 1–3 rad/s × A 0.2–0.4 mm) whose c_e follow Eq. 21 with ``alpha`` exactly
    (F_ac = c_e ω A, W = π c_e ω A²)."""
    from chainid.damping.identify import TestResult

    tests = []
    for n, (w, A) in enumerate([(1.0, 0.2), (2.0, 0.2), (3.0, 0.2), (1.0, 0.3), (2.0, 0.3), (3.0, 0.3),
                                (1.0, 0.4), (2.0, 0.4), (3.0, 0.4)]):
        c = alpha[0] * w * w + alpha[1] * w + alpha[2] * A * A + alpha[3] * A + alpha[4]
        tests.append(TestResult(test=str(n + 1), omega=w, x0=2.2, A=A, F0=20000.0, FA=8000.0 * A, phi=0.1, r2=1.0,
                                F_ac=c * w * A, c_e=c, W=math.pi * c * w * A * A))
    return tests


def test_audit_data_text_numbers_alpha1_to_alpha5():
    """``format_audit_data``: one row per Eq. 21 coefficient, named alpha1 … alpha5 in order, each with the fitted
    value; fed with nine hand-made tests whose c_e follow c_e = 100 ω² − 300 ω + 2000 A² − 500 A + 3000 exactly,
    so each row's lstsq value is the law's α to 6 digits.
    Bug caught: the row label's index (i + 1)."""
    from chainid.damping.audit_data import audit_results, format_audit_data

    alpha = (100.0, -300.0, 2000.0, -500.0, 3000.0)
    rep = audit_results(_exact_law_tests(alpha), Lin())
    rep["excluded"] = []
    rows = [ln.split() for ln in format_audit_data(rep).splitlines() if ln.strip().startswith("alpha")]
    assert [r[0] for r in rows] == ["alpha1", "alpha2", "alpha3", "alpha4", "alpha5"]
    np.testing.assert_allclose([float(r[1]) for r in rows], alpha, rtol=1e-5)


def test_test_result_theta_in_the_records_own_time():
    """``TestResult.to_dict`` gives θ for t itself: x = x0 + A sin(ω(t − t0) + θ) = x0 + A sin(ωt + θ − ω t0), so
    θ_json = θ − ω·t0 wrapped to (−π, π] (ω = 2, θ = 0.5, t0 = 3: 0.5 − 6 + 2π = 0.78319); t0 = 0 leaves θ as is;
    t_origin is not in the JSON.  Bug caught: the shift ω·t0 garbled."""
    from chainid.damping.identify import TestResult

    r = TestResult(test="1", omega=2.0, x0=2.2, A=0.3, F0=1.0, FA=1.0, phi=0.0, r2=1.0, F_ac=1.0, c_e=1.0, W=1.0,
                   theta=0.5, t_origin=3.0)
    d = r.to_dict()
    assert d["theta"] == pytest.approx(0.5 - 6.0 + 2 * math.pi, abs=1e-12) and "t_origin" not in d
    t = np.linspace(3.0, 6.0, 7)
    np.testing.assert_allclose(np.sin(2.0 * t + d["theta"]), np.sin(2.0 * (t - 3.0) + 0.5), atol=1e-12)
    r.t_origin = 0.0
    assert r.to_dict()["theta"] == 0.5


def test_finding_d_and_e_remaining_numbers_by_hand():
    """The validation case's other numbers by hand from the printed Eq. 28 (ω = 7 Hz·2π = 14π rad/s, A = 0.32 mm):
    the table's unit of 14π is 14π/(π/10) = 140; the tests span column 1–10 = π/10–π rad/s; F_ac of c_e(7) at the
    true velocity c·14π·0.32; the rad/s refit evaluated at 14π equals Eq. 28 at column 140 (ω_col = 10ω/π);
    finding (e)'s W = π·A·F_A·sin φ = π·0.25·19522.1·sin(−0.835); the text's rad/s row α1·(10/π)², α2·10/π, α3..α5.
    Bugs caught: any of these constants or conversions garbled."""
    from chainid.damping.audit import EQ28_PAPER, format_audit

    a = EQ28_PAPER

    def c(w, A):
        return a[0] * w * w + a[1] * w + a[2] * A * A + a[3] * A + a[4]

    rep = audit(Lin())
    f = {x["id"]: x for x in rep["findings"]}
    d = f["d"]["numbers"]
    w = 14 * math.pi
    assert d["omega_in_table_column_unit"] == pytest.approx(140.0, rel=1e-12)
    assert d["table_column_range"] == [1.0, 10.0]
    assert d["table_omega_range_rad_s"] == pytest.approx([math.pi / 10, math.pi], rel=1e-12)
    assert d["F_ac_omega_7_times_true_velocity_N"] == pytest.approx(c(7.0, 0.32) * w * 0.32, rel=1e-3)
    assert d["ratio_14pi_over_7"] == pytest.approx(c(w, 0.32) / c(7.0, 0.32), rel=1e-3)
    assert d["c_e_rad_s_refit_at_14pi"] == pytest.approx(c(140.0, 0.32), rel=1e-3)
    assert d["omega_of_minimum_c_e_column_unit"] == pytest.approx(651.57 / (2 * 28.02), rel=1e-3)
    e = f["e"]["numbers"]
    assert e["W_per_cycle_Nmm"] == pytest.approx(math.pi * 0.25 * 19522.1 * math.sin(-0.835), rel=1e-12)
    assert e["F_ac_eq27"] == 1335.0
    text = format_audit(rep)
    assert "matches the paper to 4 significant figures: yes" in text
    row = next(ln for ln in text.splitlines() if "same fit with omega in rad/s (pi/10 x column): " in ln)
    vals = [float(v) for v in row.split(": ")[1].split(", ")]
    s = 10 / math.pi
    np.testing.assert_allclose(vals, [a[0] * s * s, a[1] * s, a[2], a[3], a[4]], rtol=1e-3)
    assert rep["eq28_alpha_4sf"] == pytest.approx([28.02, -651.6, -8386.0, 7395.0, 4379.0], rel=1e-12)


def test_identify_records_leaves_out_a_non_finite_or_failed_estimate_and_checks_the_mass():
    """identify_records (three noise-free viscous tests, c = 300 N·s/mm on the spring 1e4 N/mm): a stiffness model
    whose force is NaN gives a non-finite c_e, and one that raises ValueError a failed estimate; each test is then
    left out with that reason (``strict`` raises it); ``progress`` is called (i, n, test) before each test; the mass
    must be a finite number >= 0 kg (0 accepted; the inertia is in phase with x, so c_e does not depend on it).
    Bugs caught: the finiteness check inverted, the failed-estimate branch dropped, the mass bound made > 0."""
    from chainid.damping.identify import identify_records
    from chainid.model.laws import ViscousLaw
    from chainid.records.simulate import TestSpec, simulate

    plan = [TestSpec(f"T{i}", w, 2.2, 0.2) for i, w in enumerate((1.0, 2.0, 3.0))]
    recs = simulate(plan, Lin(), ViscousLaw([300.0]), n_cycles=4, samples_per_cycle=100, ramp_rate=None)

    class NaNForce(LinearSpring):
        def force(self, x):
            return np.full(np.shape(x), np.nan)

    class Broken(LinearSpring):
        def force(self, x):
            raise ValueError("stand-in model refuses x")

    calls = []
    good = identify_records(recs, Lin(), mass_kg=0.0, progress=lambda i, n, t: calls.append((i, n, t)))
    assert calls == [(0, 3, "T0"), (1, 3, "T1"), (2, 3, "T2")]
    np.testing.assert_allclose([r.c_e for r in good], 300.0, rtol=1e-3)
    res = identify_records(recs, NaNForce(1e4))
    assert list(res) == []
    assert [x["reason"] for x in res.excluded] == ["damping estimate is not finite (c_e = nan N.s/mm)"] * 3
    res = identify_records(recs, Broken(1e4))
    assert [x["reason"] for x in res.excluded] == ["damping estimate failed: stand-in model refuses x"] * 3
    with pytest.raises(ValueError, match="test 'T0': damping estimate failed: stand-in model refuses x"):
        identify_records(recs, Broken(1e4), strict=True)
    for bad in (-1e-9, math.nan, math.inf, True):
        with pytest.raises(ValueError, match=r"mass_kg = .* is invalid: valid range >= 0 kg \(finite\)"):
            identify_records(recs, Lin(), mass_kg=bad)


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


def test_audit_data_finding_f_is_eq21_and_d_flags_a_negative_damping():
    """On tests that follow an Eq. 21 law exactly, finding (f) reports the polynomial law's own leave-one-out error,
    which is ~0 (every other law misses the law's curvature by far more: > 1 N·s/mm here), and its summary quotes
    it; finding (d) flags a fitted c_e <= 0 over the tested box as unphysical (c = 100 ω² − 400 ω + 350 is −50 at
    ω = 2 inside the box) and is silent for a positive one (the law of the previous test: 2755 at ω = 1.5, A = 0.2 by hand).
    Bugs caught: (f) quoting another law's error, the unphysical note inverted or dropped."""
    from chainid.damping.audit_data import audit_results

    rep = audit_results(_exact_law_tests((100.0, -300.0, 2000.0, -500.0, 3000.0)), Lin())
    f = {x["id"]: x for x in rep["findings"]}
    loo = f["f"]["numbers"]["polynomial_loo_rmse"]
    assert f["f"]["numbers"]["best_law"] == "polynomial" and loo < 1e-6
    others = [r["loo_rmse"] for r in rep["ranking"] if r["law"] != "polynomial"]
    assert others and min(others) > 1.0
    assert f"Eq. 21 (polynomial) {loo:.4g} N s/mm against {loo:.4g}." in f["f"]["summary"]
    assert "unphysical" not in f["d"]["summary"] 
    assert f["d"]["numbers"]["min_c_e_fit_in_range"] == pytest.approx(2755.0, abs=1e-6)
    rep = audit_results(_exact_law_tests((100.0, -400.0, 0.0, 0.0, 350.0)), Lin())
    d = {x["id"]: x for x in rep["findings"]}["d"]
    assert d["numbers"]["min_c_e_fit_in_range"] == pytest.approx(-50.0, abs=1e-6)
    assert "minimum over the tested range is -50 N s/mm <= 0: unphysical." in d["summary"]
