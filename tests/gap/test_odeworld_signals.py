"""The ODE world's excitations and logger: multisine periodicity and lines, the noise taper, the chirps' rests and
direction, the channel lag found at τ by cross-correlation (both channels), the ADC step and the noise level, the
damping law's per-record c, the damping-dominated base, and a case rebuilt from its seed."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.gap.benchmark import odeshapes as sh
from chainid.gap.benchmark.odedevice import Device, Trace, run_displacement
from chainid.gap.benchmark.odemeasure import Logger, measure
from chainid.gap.benchmark.odeworld import build


def test_multisine_is_periodic_with_unit_rms_and_power_only_on_its_lines():
    s = sh.multisine(1000.0, 8000, 2.0, 40.0, 4, np.random.default_rng(1))
    idx = s.record_index
    y = s.y[idx]
    P = 2000  # samples per period: 8000 / 4
    np.testing.assert_allclose(y[P:], y[:-P], atol=1e-9)
    assert float(np.sqrt(np.mean(y[:P] ** 2))) == pytest.approx(1.0, abs=1e-9)
    Y = np.abs(np.fft.rfft(y[:P])) ** 2
    lines = np.round(np.array(s.info["lines_hz"]) * P / 1000.0).astype(int)
    assert np.all(np.abs(np.array(s.info["lines_hz"]) * P / 1000.0 - lines) < 1e-9)  # on the DFT bins
    off = np.ones(Y.size, bool)
    off[lines] = False
    assert Y[off].sum() < 1e-20 * Y.sum()
    assert lines.min() == 4 and lines.max() == 80  # 2 Hz and 40 Hz at 0.5 Hz resolution
    # the derivative is the analytic one: compare with a central difference on the fine grid
    h = s.t[1] - s.t[0]
    np.testing.assert_allclose((s.y[2:] - s.y[:-2]) / (2 * h), s.yd[1:-1], atol=2e-3 * np.abs(s.yd).max())


def test_noise_taper_is_the_raised_cosine_over_the_stated_time_and_the_rest_is_still():
    kw = dict(fs=500.0, n=5000, f_lo=1.0, f_hi=20.0)
    a = sh.filtered_noise(**kw, taper=1.0, rng=np.random.default_rng(5), rest=0.4)
    b = sh.filtered_noise(**kw, taper=0.01, rng=np.random.default_rng(5), rest=0.4)
    assert np.all(a.y[a.t < 0] == 0.0) and np.all(a.yd[a.t < 0] == 0.0)
    i0 = a.record_index[0]
    assert a.y[i0] == 0.0 and a.yd[i0] == 0.0
    m = (a.t > 0.02) & (a.t < 1.0) & (np.abs(b.y) > 0.1)
    np.testing.assert_allclose(a.y[m] / b.y[m], 0.5 * (1 - np.cos(np.pi * a.t[m] / 1.0)), rtol=1e-9)
    T = 10.0  # s
    m = (a.t > T - 1.0) & (a.t < T - 0.02) & (np.abs(b.y) > 0.1)
    np.testing.assert_allclose(a.y[m] / b.y[m], 0.5 * (1 - np.cos(np.pi * (T - a.t[m]) / 1.0)), rtol=1e-9)
    mid = (a.t > 1.0) & (a.t < T - 1.0)
    np.testing.assert_array_equal(a.y[mid], b.y[mid])


@pytest.mark.parametrize("down", [False, True])
def test_chirps_rest_between_sweeps_and_run_the_stated_way(down):
    f0, f1 = (5.0, 1.0) if down else (1.0, 5.0)
    s = sh.chirp(500.0, 10000, f0, f1, n_sweeps=2, rest=2.0)
    T_s = s.info["sweep_s"]
    assert T_s == pytest.approx((20.0 - 3 * 2.0) / 2)
    starts = s.info["starts_s"]
    assert starts == pytest.approx([2.0, 2.0 + T_s + 2.0])
    rest = (s.t < starts[0]) | ((s.t > starts[0] + T_s) & (s.t < starts[1])) | (s.t > starts[1] + T_s)
    assert np.all(s.y[rest] == 0.0) and np.all(s.yd[rest] == 0.0)
    sweep = (s.t > starts[0]) & (s.t < starts[0] + T_s)
    tt, y = s.t[sweep], s.y[sweep]
    zc = tt[np.flatnonzero(np.diff(np.sign(y)) != 0)]
    assert zc.size == pytest.approx(2 * 0.5 * (f0 + f1) * T_s, abs=3)  # 2·∫f dt of a linear sweep
    gaps = np.diff(zc)
    first, last = gaps[: gaps.size // 3].mean(), gaps[-gaps.size // 3:].mean()
    assert (first < last) if down else (first > last)


def _spring_trace(fs: float = 1000.0, n: int = 6000) -> tuple[sh.Shape, Trace]:
    s = sh.filtered_noise(fs, n, 2.0, 30.0, 0.3, np.random.default_rng(11), rest=0.1)
    dev = Device("linear", k=100.0, m=0.0, c=0.0)
    return s, run_displacement(dev, s.t, 0.5 * s.y, 0.5 * s.yd, 0.5 * s.ydd, 1.0 / fs)


def _xcorr_lag(x: np.ndarray, F: np.ndarray, fs: float) -> float:
    """Lag [s] of F behind x at the cross-correlation peak (parabola through the top three)."""
    x, F = x - x.mean(), F - F.mean()
    r = np.correlate(F, x, mode="full")
    k = int(np.argmax(r))
    d = 0.5 * (r[k - 1] - r[k + 1]) / (r[k - 1] - 2 * r[k] + r[k + 1])
    return (k - (x.size - 1) + d) / fs


@pytest.mark.parametrize("tau", [7.3e-3, -4.6e-3])
def test_channel_lag_is_found_at_tau_by_cross_correlation(tau):
    s, tr = _spring_trace()
    rec = measure("r1", s, tr, Logger(tau=tau), np.random.default_rng(0))
    assert _xcorr_lag(rec.x, rec.F, 1000.0) == pytest.approx(tau, abs=0.1e-3)  # within a tenth of a sample
    same = measure("r1", s, tr, Logger(), np.random.default_rng(0))
    np.testing.assert_allclose(same.F, 100.0 * same.x, rtol=1e-12)  # no lag: F = k·x sample by sample


def test_adc_steps_and_noise_level_are_as_stated():
    s, tr = _spring_trace()
    q = 0.37
    rec = measure("r1", s, tr, Logger(sigma_F=2.0, sigma_x=1e-3, q_F=q), np.random.default_rng(1))
    np.testing.assert_allclose(rec.F / q, np.round(rec.F / q), atol=1e-9)
    clean = tr.F[s.record_index]
    err = rec.F - clean
    # noise 2 N plus uniform rounding of variance q²/12; 6000 samples: the sample σ within 3 %
    assert float(err.std()) == pytest.approx(math.sqrt(4.0 + q * q / 12), rel=0.03)
    assert float((rec.x - tr.x[s.record_index]).std()) == pytest.approx(1e-3, rel=0.03)
    # zero-mean noise: the means within 4 standard errors of 0 (6000 samples)
    assert abs(float(err.mean())) < 4 * math.sqrt(4.0 + q * q / 12) / math.sqrt(6000)
    assert abs(float((rec.x - tr.x[s.record_index]).mean())) < 4 * 1e-3 / math.sqrt(6000)


def test_a_lag_before_the_fine_grid_holds_its_first_value_and_inside_follows_the_spline():
    from chainid.gap.benchmark.odemeasure import lagged

    t_fine = np.linspace(0.0, 1.0, 1001)
    y = np.sin(2 * math.pi * t_fine) + 2.0
    t = np.array([0.0, 0.005, 0.5, 1.0])
    got = lagged(t_fine, y, t, 0.01)  # y(t − 0.01): the first two fall before the grid
    assert got[0] == got[1] == 2.0
    assert got[2] == pytest.approx(math.sin(2 * math.pi * 0.49) + 2.0, abs=1e-9)  # a smooth spline: 1e-9
    assert lagged(t_fine, y, np.array([0.995]), -0.01)[0] == pytest.approx(y[-1], abs=1e-15)  # after its end


@pytest.mark.parametrize("f_hi, taper, ok", [(100.0, 1.5, True), (100.01, 1.5, False), (50.0, 1.5001, False)])
def test_filtered_noise_admits_a_band_up_to_a_tenth_of_the_rate_and_a_taper_up_to_a_quarter(f_hi, taper, ok):
    """fs = 1000 Hz, 6000 samples (T = 6 s): the band top may reach fs/10 = 100 Hz, the taper T/4 = 1.5 s."""
    rng = np.random.default_rng(3)
    if ok:
        assert sh.filtered_noise(1000.0, 6000, 2.0, f_hi, taper, rng).y.size > 0
    else:
        with pytest.raises(ValueError, match="fs/10 = 100 Hz and 0 < taper <= T/4 = 1.5 s"):
            sh.filtered_noise(1000.0, 6000, 2.0, f_hi, taper, rng)


def test_damping_law_gives_each_record_its_c_within_one_percent():
    case = {"family": "single", "base": "stiff", "excitation": "harmonic", "effects": {"damping_law": 1.0},
            "outside": {}, "covariate": None, "sign": 1.0, "seed": 21}
    recs, hold, truth = build(case, clean=True)  # noise-free: at 1 Hz the loss is 1 % of the spring force
    law = truth["damping_law"]
    c0, b_w, b_A = law["c"], law["b_w"], law["b_A"]
    assert truth["effects"]["damping_law"] == {"b_w": b_w, "b_A": b_A}
    cs = np.array([m["c"] for m in truth["records"]])
    assert np.max(np.abs(cs / c0 - 1)) <= 0.2 + 1e-12 and np.ptp(cs) / c0 > 0.1
    for r, m in zip(recs, truth["records"]):
        w = 2 * np.pi * m["f"]
        B = np.column_stack([np.ones_like(r.t), np.cos(w * r.t), np.sin(w * r.t)])  # not whole cycles: fit, not DFT
        (_, xc, xs), (_, Fc, Fs) = (np.linalg.lstsq(B, y, rcond=None)[0] for y in (r.x, r.F))
        X, F = xc - 1j * xs, Fc - 1j * Fs
        assert float(np.imag(F / X)) / w == pytest.approx(m["c"], rel=0.01)  # F̂/X̂ = k + iωc
        A_r = 0.5 * float(np.ptp(r.x))
        law_c = c0 + b_w * (w - law["omega_mean"]) + b_A * (A_r - law["A_mean"])
        assert m["c"] == pytest.approx(law_c, rel=1e-3)


def test_damper_base_is_damping_dominated():
    case = {"family": "control", "base": "damper", "excitation": "noise", "effects": {}, "outside": {},
            "covariate": None, "sign": 1.0, "seed": 4}
    recs, _, truth = build(case)
    k, c = truth["base"]["k"], truth["base"]["c"]
    for r in recs:
        v = np.gradient(r.x, r.t)
        assert c * float(np.std(v)) > 5 * k * float(np.std(r.x))


def test_resonant_base_has_its_natural_frequency_inside_the_band():
    case = {"family": "control", "base": "resonant", "excitation": "multisine", "effects": {}, "outside": {},
            "covariate": None, "sign": 1.0, "seed": 8}
    recs, _, truth = build(case)
    b = truth["base"]
    f_n = math.sqrt(b["k"] * 1e3 / b["m"]) / (2 * math.pi)  # m·ω²·1e-3 = k
    assert f_n == pytest.approx(b["f_n"], rel=1e-12)
    assert all(m["f_lo"] < f_n < m["f_hi"] for m in truth["records"])


def test_a_case_is_rebuilt_identically_from_its_seed():
    case = {"family": "single", "base": "chain14", "excitation": "chirp", "effects": {"friction": 1.0},
            "outside": {}, "covariate": None, "sign": 1.0, "seed": 5}
    a, ha, ta = build(case)
    b, hb, tb = build(case)
    assert ha == hb and ta["effects"] == tb["effects"]
    for ra, rb in zip(a, b):
        np.testing.assert_array_equal(ra.F, rb.F)
        np.testing.assert_array_equal(ra.x, rb.x)
    c, _, tc = build({**case, "seed": 6})
    assert tc["effects"] != ta["effects"] or c[0].F.size != a[0].F.size
    clean, hc, tcl = build(case, clean=True)  # the same case without the logger's noise and ADC steps
    assert hc == ha and tcl["records"] == ta["records"]
    for ra, rc, m in zip(a, clean, ta["records"]):
        d = ra.F - rc.F
        assert float(np.abs(d).max()) <= 6 * m["sigma_F"] + m["q_F"]
        assert float(d.std()) == pytest.approx(math.sqrt(m["sigma_F"] ** 2 + m["q_F"] ** 2 / 12), rel=0.1)


def test_table1_ranges_hold_the_papers_own_exponents():
    """The Table-1 world's exponent ranges are read from the paper's Table 1 (tests 1–5: ω = 1…10 rad/s at A = 0.25
    mm; tests 6–9 with test 3: A = 0.2…0.4 mm at ω = 6 rad/s): a log-log least-squares slope of each."""
    from chainid.gap.benchmark.odeworld import TABLE1_P, TABLE1_Q

    w, c_w = np.array([1, 4, 6, 8, 10.0]), np.array([5095.5, 3503.2, 2834.4, 2332.8, 1964.3])
    A, c_A = np.array([0.2, 0.25, 0.3, 0.35, 0.4]), np.array([2614.1, 2834.4, 2906.9, 3058.8, 3090.5])
    p = -np.polyfit(np.log(w), np.log(c_w), 1)[0]
    q = np.polyfit(np.log(A), np.log(c_A), 1)[0]
    assert TABLE1_P[0] < p < TABLE1_P[1] and TABLE1_Q[0] < q < TABLE1_Q[1]
    assert (p, q) == (pytest.approx(0.39, abs=0.01), pytest.approx(0.24, abs=0.01))  # as the module states


def test_table1_law_gives_each_record_its_power_law_c_and_is_curved():
    case = {"family": "single", "base": "stiff", "excitation": "harmonic", "effects": {"damping_law": 1.0},
            "outside": {}, "covariate": None, "sign": 1.0, "seed": 21, "law_form": "table1"}
    recs, _, truth = build(case, clean=True)
    law = truth["damping_law"]
    assert law["form"] == "table1" and truth["effects"]["damping_law"] == {}  # no linear coefficients to score
    cs = np.array([m["c"] for m in truth["records"]])
    w = np.array([2 * np.pi * m["f"] for m in truth["records"]])
    A = np.array([0.5 * float(np.ptp(r.x)) for r in recs])
    for r, m, w_r in zip(recs, truth["records"], w):  # each record's c, read back from its own F and x
        B = np.column_stack([np.ones_like(r.t), np.cos(w_r * r.t), np.sin(w_r * r.t)])
        (_, xc, xs), (_, Fc, Fs) = (np.linalg.lstsq(B, y, rcond=None)[0] for y in (r.x, r.F))
        assert float(np.imag((Fc - 1j * Fs) / (xc - 1j * xs))) / w_r == pytest.approx(m["c"], rel=0.01)
    want = law["c"] * (w / law["omega_mean"]) ** (-law["p"]) * (A / law["A_mean"]) ** law["q"]
    assert cs == pytest.approx(want, rel=1e-3)
    assert 0.25 <= law["p"] <= 0.55 and 0.10 <= law["q"] <= 0.35  # level 1: the ranges themselves
    # curved: a law linear in ω and A (the time route's form) leaves a residual that the power law does not
    B = np.column_stack([np.ones_like(w), w, A])
    lin = cs - B @ np.linalg.lstsq(B, cs, rcond=None)[0]
    assert float(np.max(np.abs(lin))) > 0.05 * law["c"]  # 16 % of c here, over a 10× band


def test_an_unknown_law_form_is_refused():
    case = {"family": "single", "base": "stiff", "excitation": "harmonic", "effects": {"damping_law": 1.0},
            "outside": {}, "covariate": None, "sign": 1.0, "seed": 21, "law_form": "cubic"}
    with pytest.raises(ValueError, match=r"law_form = 'cubic' is unknown; valid: linear, table1"):
        build(case)
