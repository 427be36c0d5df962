"""Steady-cycle selection on messy records (issue 10 item 4): adaptive tolerance, longest usable window.

Synthetic versions of real cases, seeded numpy; each asserts the kept window against the
known steady part and the estimates (omega, A, x0) against the truth, with stated tolerances.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.signal.harmonic import estimate_harmonic
from chainid.records.files import Record, try_analyse
from chainid.signal.steady import TOL_FLOOR, TOL_MAX, _scatter, select_steady, steady_tolerance


def _rec(t, x, F0=20000.0, k=1000.0, test="T"):
    return Record(test, t, x, F0 + k * (x - np.mean(x)))


def _jittered_shaker(seed=0, f=18.0, fs=10_000.0, periods=161, A=1.0, x0=5.0, jitter=0.02, noise=2e-3):
    """Shaker record: amplitude set anew every period, A_k = A (1 + jitter * N(0,1)), switched at the
    upward zero crossing of sin (x = x0 there, so x stays continuous)."""
    rng = np.random.default_rng(seed)
    w = 2 * math.pi * f
    t = np.arange(int(round(periods / f * fs))) / fs
    Ak = A * (1 + jitter * rng.standard_normal(periods + 1))
    env = Ak[np.floor(t * f + 1e-9).astype(int)]
    x = x0 + env * np.sin(w * t) + rng.normal(0, noise, t.size)
    return t, x, w


def test_scatter_of_iid_jitter_is_measured():
    """sigma from second differences: 1.4826 MAD(d)/sqrt(6) estimates the jitter SD (here 2 %)."""
    rng = np.random.default_rng(1)
    amps = 1.0 + 0.02 * rng.standard_normal(4000)
    means = np.full(4000, 5.0)
    # MAD-based SD estimate from 4000 samples: standard error ~ 1.65 sigma / sqrt(n) ~ 2.6 % relative
    assert _scatter(amps, means) == pytest.approx(0.02, rel=0.08)
    # a linear taper adds nothing (second differences cancel it)
    taper = amps * np.linspace(0.9, 1.1, 4000)
    assert _scatter(taper, means) == pytest.approx(0.02, rel=0.1)


def test_steady_tolerance_floor_and_cap():
    assert steady_tolerance(0.001) == TOL_FLOOR == 0.03
    assert steady_tolerance(0.02) == pytest.approx(0.08)
    assert steady_tolerance(1.0) == TOL_MAX == 0.15
    assert steady_tolerance(float("nan")) == TOL_FLOOR


def test_shaker_record_wandering_amplitude_kept_adaptive():
    """161 periods at 18 Hz, 10 kHz sampling, amplitude wandering 2 % per cycle (issue 10 case).

    At a fixed 3 % the run breaks at every ~1.5-sigma cycle; the adaptive tolerance (4 x 2 % = 8 %)
    keeps (nearly) every cycle: at least 150 of the 160 whole cycles after the first.
    (Measured here: scatter 1.63 %, tolerance 6.5 %, 160 cycles kept; fixed 3 %: 33.)
    A is the mean of the per-cycle amplitudes: its error ~ 2 % / sqrt(150) ~ 0.16 %, asserted 1 %.
    """
    t, x, w = _jittered_shaker()
    fixed = estimate_harmonic(t, x, rel_tol=0.03)
    est = estimate_harmonic(t, x)  # adaptive
    win = est.window
    assert win.requested_tol is None
    assert win.scatter == pytest.approx(0.02, rel=0.3)
    assert win.rel_tol == pytest.approx(4 * win.scatter)
    assert win.n_cycles >= 150
    assert fixed.window.n_cycles < 60  # the old fixed 3 % rejects most of the record
    assert est.omega == pytest.approx(w, rel=1e-4)
    assert est.A == pytest.approx(1.0, rel=0.01)
    assert est.x0 == pytest.approx(5.0, abs=0.005)
    assert "adaptive" in win.statement() and "scatter" in win.statement()


def test_taper_that_never_holds_3_percent_gets_longest_usable_window():
    """2 Hz test (400 Hz sampling) that tapers in over 2 cycles, sags 4 % per cycle on its plateau
    (1.00, 0.96, 0.92, 0.88, 0.84 of 1 mm) and tapers out: no two cycles running agree within 3 %.

    A fixed 3 % finds no steady cycle (the issue's failing case); the adaptive selection widens
    (x1.5 steps, at most 15 %) to the first tolerance that keeps a window, and says so.  Checked
    independently: the window lies inside the plateau cycles 2..6, and A equals the mean of the
    amplitudes of the kept cycles within 0.5 % (the amplitude switches at upward zero crossings, so
    each whole cycle has one amplitude).  (Measured: cycles 3-4 at 4.5 %, A = 0.940 mm.)
    """
    f, fs = 2.0, 400.0
    w = 2 * math.pi * f
    T = 1 / f
    Ak = np.array([0.3, 0.65, 1.0, 0.96, 0.92, 0.88, 0.84, 0.6, 0.3])
    t = np.arange(int(Ak.size * T * fs)) / fs
    env = Ak[np.floor(t / T + 1e-9).astype(int)]
    rng = np.random.default_rng(4)
    x = 3.0 + env * np.sin(w * t) + rng.normal(0, 1e-3, t.size)
    fixed = select_steady(t, x, w, 0.0, rel_tol=0.03)
    assert fixed.n_cycles == 0
    est, why = try_analyse(_rec(t, x))
    assert est is not None, why
    win = est.window
    assert win.n_cycles >= 1
    assert 0.03 < win.rel_tol <= TOL_MAX and "widened" in win.reason and "widened" in why
    k0, k1 = round(win.t_start / T), round(win.t_end / T)
    assert win.t_start == pytest.approx(k0 * T, abs=0.01 * T) and win.t_end == pytest.approx(k1 * T, abs=0.01 * T)
    assert 2 <= k0 and k1 <= 7
    assert est.A == pytest.approx(float(np.mean(Ak[k0:k1])), rel=0.005)
    assert est.omega == pytest.approx(w, rel=1e-3)
    assert est.x0 == pytest.approx(3.0, abs=0.01)


def test_drifting_mean_keeps_window_where_mean_holds():
    """Mean drifts linearly by 0.5 % of A per cycle over 40 cycles: the kept window's own mean
    error is bounded by the tolerance (3 % of A) and x0 equals the drifted mean at the window centre
    within 0.002 mm (the fit of a constant to a linear drift returns its centre value exactly)."""
    f, fs, n_per, A = 5.0, 1000.0, 40, 1.0
    w = 2 * math.pi * f
    t = np.arange(int(n_per / f * fs)) / fs
    drift = 0.005 * A * f * t  # mm
    rng = np.random.default_rng(7)
    x = 2.0 + drift + A * np.sin(w * t) + rng.normal(0, 1e-3, t.size)
    est = estimate_harmonic(t, x)
    win = est.window
    assert win.n_cycles >= 8  # 3 % of A / 0.5 % per cycle -> a run of ~12 cycles (first dropped)
    tc = 0.5 * (win.t_start + win.t_end)
    assert est.x0 == pytest.approx(2.0 + 0.005 * A * f * tc, abs=0.002)
    assert est.A == pytest.approx(A, rel=0.002)
    assert est.omega == pytest.approx(w, rel=1e-3)
    span_mean = 0.005 * A * f * (win.t_end - win.t_start)
    assert span_mean <= 2 * (win.rel_tol * A) + 0.01


def test_ringing_at_reversals_and_late_start():
    """A lead-in of 4 s standing still (the actuator lags the record start), then 20 cycles at 1 Hz with
    a decaying 25 Hz ring after each reversal (10 % of A).  The ring is not the fundamental: omega and A
    within 0.2 %, the window starts after the lead-in plus the first (dropped) cycle."""
    fs, f, A = 2000.0, 1.0, 2.0
    w = 2 * math.pi * f
    t = np.arange(int(24 * fs)) / fs
    tl = np.clip(t - 4.0, 0, None)
    on = t >= 4.0
    x = 10.0 + np.where(on, A * np.sin(w * tl), 0.0)
    # ring: after each reversal (phase pi/2 + k pi) a 25 Hz decaying oscillation
    t_rev = (0.25 + 0.5 * np.floor((tl * 2) - 0.5)) / 1.0
    since = tl - t_rev
    ring = np.where(on & (since >= 0), 0.1 * A * np.exp(-since / 0.03) * np.sin(2 * math.pi * 25 * since), 0.0)
    rng = np.random.default_rng(2)
    x = x + ring + rng.normal(0, 2e-3, t.size)
    est, why = try_analyse(_rec(t, x))
    assert est is not None, why
    assert est.omega == pytest.approx(w, rel=2e-3)
    assert est.A == pytest.approx(A, rel=2e-3)
    assert est.x0 == pytest.approx(10.0, abs=0.01)
    assert est.window.t_start >= 5.0 - 1e-6
    assert est.window.n_cycles >= 17


def test_clean_record_unchanged_by_adaptive_tolerance():
    """Clean record: the adaptive tolerance is the 3 % floor and the window equals the fixed-3 % one."""
    w = 3.0
    t = np.arange(0, 12 * 2 * math.pi / w, 0.01)
    x = 2.2 + 0.25 * np.sin(w * t) + np.random.default_rng(0).normal(0, 1e-3, t.size)
    a = estimate_harmonic(t, x)
    b = estimate_harmonic(t, x, rel_tol=0.03)
    assert a.window.rel_tol == 0.03 and a.window.cycles_kept == b.window.cycles_kept
    assert (a.omega, a.A, a.x0) == (b.omega, b.A, b.x0)
    assert "floor" in a.window.reason


def test_try_analyse_reason_and_data_errors():
    t = np.linspace(0, 2.0, 400)  # 2 s at 0.5 Hz: one period only
    x = 2.0 + 0.3 * np.sin(math.pi * t)
    est, why = try_analyse(_rec(t, x))
    assert est is None and "fewer than 2 full cycles" in why and not why.startswith("test")
    bad = _rec(t, x, F0=0.0)  # swings about zero (no mean tension) and dips below it: refused with a chain
    with pytest.raises(ValueError, match="force goes compressive"):
        try_analyse(bad)
    est, why = try_analyse(bad, allow_compression=True)
    assert est is None
    with pytest.raises(ValueError, match="steady_tol"):
        try_analyse(_rec(t, x), steady_tol=3.0)


def test_cycle_stats_match_per_cycle_lstsq():
    """The batched O(N) per-cycle fits equal an independent per-cycle numpy.linalg.lstsq on
    [1, t - tc, sin psi, cos psi] (to 1e-9 mm), on a record with a ramp, taper and noise."""
    from chainid.signal.steady import _cycle_stats

    rng = np.random.default_rng(5)
    w, theta = 7.0, 0.4
    T = 2 * math.pi / w
    t = np.sort(rng.uniform(0, 12 * T, 3000))  # non-uniform sampling
    x = 1.0 + 0.05 * t + (0.3 + 0.02 * t) * np.sin(w * t + theta) + rng.normal(0, 1e-3, t.size)
    bounds, amps, means, drifts, sds, n_in = _cycle_stats(t, x, w, theta)
    assert len(bounds) - 1 == amps.size >= 10
    for i in range(amps.size):
        m = (t >= bounds[i] - 1e-9 * T) & (t < bounds[i + 1] - 1e-9 * T)
        assert n_in[i] == m.sum()
        if amps[i] == 0:
            continue
        tc = 0.5 * (bounds[i] + bounds[i + 1])
        X = np.column_stack([np.ones(m.sum()), t[m] - tc, np.sin(w * t[m] + theta), np.cos(w * t[m] + theta)])
        (c0, slope, a, b), *_ = np.linalg.lstsq(X, x[m], rcond=None)
        res = x[m] - X @ np.array([c0, slope, a, b])
        assert amps[i] == pytest.approx(math.hypot(a, b), abs=1e-9)
        assert means[i] == pytest.approx(c0, abs=1e-9)
        assert drifts[i] == pytest.approx(abs(slope) * T, abs=1e-9)
        assert sds[i] == pytest.approx(float(np.std(res)), abs=1e-9)


def test_long_record_decimated_search_is_accurate():
    """A 400k-sample record takes the decimated candidate search (stride > 1); the final fit uses
    every sample.  Noise 2 um over ~390k kept samples: omega within 1e-6 relative, A and x0 within
    1e-4 mm (standard errors ~ 5e-6 mm)."""
    from chainid.signal.harmonic import _search_stride

    f, fs, n = 18.0, 10_000.0, 400_000
    w = 2 * math.pi * f
    t = np.arange(n) / fs
    x = 5.0 + 1.0 * np.sin(w * t + 0.3) + np.random.default_rng(6).normal(0, 2e-3, n)
    assert _search_stride(t, w) > 1
    est = estimate_harmonic(t, x)
    assert est.omega == pytest.approx(w, rel=1e-6)
    assert est.A == pytest.approx(1.0, abs=1e-4)
    assert est.x0 == pytest.approx(5.0, abs=1e-4)
    assert est.window.n_cycles >= 715  # 720 periods, the first and the partial last ones dropped
