"""Steady-cycle selection (chainid.signal.steady): per-cycle fits, the drift and noise allowances, the adaptive
tolerance with its floor and cap, whole cycles at the boundaries, and messy records (tapers, wandering amplitude,
ringing, a late start) whose kept window and estimates (ω, A, x0) are checked against the known truth.
Units s, mm."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.records.files import Record, try_analyse
from chainid.signal.harmonic import estimate_harmonic
from chainid.signal.steady import (
    MIN_TRIPLES,
    TOL_FLOOR,
    TOL_MAX,
    SteadyWindow,
    _count_within,
    _plateau,
    _scatter,
    _select_with_tol,
    _t_text,
    select_steady,
    steady_tolerance,
)


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


@pytest.mark.slow
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


def test_a_mean_ramp_longer_than_the_hold_keeps_the_holds_cycles():
    """The mean load ramps 0 → 20 mm over the first 24 s of a 40 s record (1 Hz, A = 1 mm), then holds: the 16
    hold cycles (24–40 s) agree with each other and no two ramp cycles do, so the window is the hold less its first
    cycle, 25–40 s (15 cycles), x0 = 25 mm and A = 1 mm.  (The median of every cycle's mean sat mid-ramp, 17.9 mm,
    and no window was kept.)"""
    fs, T = 200.0, 40.0
    t = np.arange(0.0, T, 1 / fs)
    ramp = np.where(t < 24.0, 20.0 * t / 24.0, 20.0)
    x = 5.0 + ramp + np.sin(2 * math.pi * t) + np.random.default_rng(0).normal(0.0, 0.002, t.size)
    est = estimate_harmonic(t, x)
    assert est.window.n_cycles == 15
    assert est.window.t_start == pytest.approx(25.0, abs=0.01) and est.window.t_end == pytest.approx(40.0, abs=0.01)
    assert est.x0 == pytest.approx(25.0, abs=0.002) and est.A == pytest.approx(1.0, rel=0.002)


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


@pytest.mark.slow
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


def _stats(amps, drifts=None, sd=0.0, nn=8):
    n = len(amps)
    return (list(np.arange(n + 1, dtype=float)), np.array(amps, float), np.zeros(n),
            np.array(drifts if drifts is not None else np.zeros(n), float), np.full(n, sd), np.full(n, nn))


def test_drift_tolerance_scales_with_the_plateau():
    """Plateau 2 mm, tol 5 %: a cycle may drift 0.05·2 = 0.1 mm; 0.08 mm passes, 0.12 mm does not (no noise).
    Bug caught: tol·plateau replaced (tol % plateau = 0.05 would refuse 0.08)."""
    t = np.arange(8.0)
    win = _select_with_tol(t, _stats([2.0] * 7, [0, 0, 0, 0.08, 0, 0, 0]), 0.05, False, None)
    assert win.n_cycles == 7
    win = _select_with_tol(t, _stats([2.0] * 7, [0, 0, 0, 0.12, 0, 0, 0]), 0.05, False, None)
    assert win.n_cycles == 3 and win.cycles_kept == [0, 1, 2]  # the longest run, first on a tie
    win = _select_with_tol(t, _stats([2.0] * 7, [0, 0, 0, 0.12, 0, 0, 0]), 0.05, False, 0.1)  # drift_tol 10 %
    assert win.n_cycles == 7


def test_amplitude_noise_allowance_four_standard_errors():
    """Residual SD 0.1 mm over 8 samples: amplitude allowance 4·0.1·sqrt(2/8) = 0.2 mm on top of tol·plateau =
    0.01·2 = 0.02 mm; a cycle 0.21 mm off passes, 0.23 mm off does not.
    Bugs caught: sqrt(2/n) changed (2 % n gives sqrt(2): 0.57 mm), the factor 4."""
    t = np.arange(8.0)
    amps = [2.0, 2.0, 2.0, 2.21, 2.0, 2.0, 2.0]
    assert _select_with_tol(t, _stats(amps, sd=0.1), 0.01, False, float("inf")).n_cycles == 7
    amps[3] = 2.23
    assert _select_with_tol(t, _stats(amps, sd=0.1), 0.01, False, float("inf")).n_cycles == 3


def test_adaptive_tolerance_capped_says_so():
    """Cycle amplitudes jittering with SD 6 % (clipped to ±20 %): 4 × scatter ≈ 24 % is above the cap, so the tolerance is TOL_MAX = 15 % and
    the reason names the cap as '15 %'.  Bug caught: the reason's number (100·TOL_MAX) garbled."""
    w = 2 * math.pi
    rng = np.random.default_rng(0)
    amps = 1.0 + np.clip(0.06 * rng.standard_normal(20), -0.2, 0.2)
    t = np.linspace(0.0, 20.0, 20 * 64, endpoint=False)
    x = amps[np.minimum((t).astype(int), 19)] * np.sin(w * t)
    win = select_steady(t, x, w, 0.0, rel_tol=None)
    assert win.scatter * 4 > TOL_MAX and win.rel_tol >= TOL_MAX
    assert f"cap {100 * TOL_MAX:g} % (" in win.reason and "cap 15 %" in win.reason


def test_mean_and_drift_noise_allowances_four_standard_errors():
    """Residual SD 0.1 mm over 8 samples, tol 1 % of a 2 mm plateau (0.02 mm), drift tolerance 0: a cycle's mean may
    stray 0.02 + 4·0.1/sqrt(8) = 0.1614 mm from the others' and it may drift 4·0.1·sqrt(12/8) = 0.4899 mm (the SE
    of a fitted trend over n samples, by hand).  Bugs caught: the factor 4 of either allowance, 12 or 1/√n."""
    t = np.arange(8.0)

    def kept(means=None, drifts=None):
        st = list(_stats([2.0] * 7, drifts, sd=0.1))
        if means is not None:
            st[2] = np.array(means, float)
        return _select_with_tol(t, tuple(st), 0.01, False, 0.0).n_cycles

    assert kept(drifts=[0, 0, 0, 0.48, 0, 0, 0]) == 7
    assert kept(drifts=[0, 0, 0, 0.50, 0, 0, 0]) == 3
    assert kept(means=[0, 0, 0, 0.155, 0, 0, 0]) == 7
    assert kept(means=[0, 0, 0, 0.168, 0, 0, 0]) == 3


def test_adaptive_tolerance_at_the_floor_says_so():
    """A clean sine (noise 0.1 % of the amplitude): 4 × the cycle-to-cycle scatter is far below the 3 % floor,
    so the tolerance is the floor and the reason says 'floor 3 % (… is smaller)'.  Bug caught: the reason's
    number ``100 * TOL_FLOOR`` → ``100 - TOL_FLOOR`` (99.97 %)."""
    w = 2 * math.pi
    rng = np.random.default_rng(1)
    t = np.linspace(0.0, 12.0, 12 * 64, endpoint=False)
    x = 5.0 + 2.0 * np.sin(w * t) + 0.002 * rng.standard_normal(t.size)
    win = select_steady(t, x, w, 0.0, rel_tol=None)
    assert 4 * win.scatter < 0.03 and win.rel_tol == pytest.approx(0.03, rel=1e-12)
    assert win.reason.startswith("tolerance from the record: floor 3 % (4 x cycle-to-cycle scatter ")
    assert win.reason.endswith(" % is smaller)")


# --- own-seed (701) mutation survivors -------------------------------------------------------------------------
def test_drift_bound_is_inclusive():
    """A cycle whose drift equals the bound tol·plateau (+ the 1e-12 slack the code adds for rounding) is kept:
    the bound is inclusive, as the mean's.  Bug caught: ``drifts <= bound`` → ``<``."""
    t = np.arange(8.0)
    bound = 0.05 * 2.0 + 1e-12
    win = _select_with_tol(t, _stats([2.0] * 7, [0, 0, 0, bound, 0, 0, 0]), 0.05, False, None)
    assert win.n_cycles == 7
    win = _select_with_tol(t, _stats([2.0] * 7, [0, 0, 0, 0.1 + 1e-9, 0, 0, 0]), 0.05, False, None)
    assert win.n_cycles == 3


@pytest.mark.parametrize("T,dt,off,whole", [(10.0, 0.01, 5e-4, 6), (10.0, 0.01, 0.05, 5),
                                            (0.1, 1e-3, 5e-4, 6), (0.1, 1e-3, 0.05, 5)])
def test_a_sample_within_a_thousandth_step_of_a_boundary_is_on_it(T, dt, off, whole):
    """Six periods sampled from t = 0, with the first boundary ``off`` sampling steps before the first sample:
    within 1e-3 of a step (5e-4) the first sample is on the boundary and the record holds 6 whole cycles; at
    0.05 steps it is not (5), for a period of 10 s as for 0.1 s.  Bug caught: the tolerance in cycles
    ``eps_t / T`` → ``eps_t * T`` (right only for T = 1 s)."""
    w = 2 * math.pi / T
    t = np.arange(0, round(6 * T / dt) + 1) * dt
    theta = w * off * dt
    win = select_steady(t, 3.0 + np.sin(w * t + theta), w, theta, rel_tol=0.03, drop_first=False)
    assert win.n_cycles_total == whole


def test_scatter_is_the_robust_sd_of_second_differences_over_the_plateau():
    """Cycle amplitudes 2 mm ± 1 % and means ± 0.5 % of it (15 cycles): the scatter is the larger of
    1.4826·MAD(d)/√6 / plateau over amplitudes and means, d the second differences (the docstring's formula,
    computed here with numpy's median; plateau = the median amplitude).  Bug caught: ``/ ref`` → ``** ref``."""
    from chainid.signal.steady import _scatter

    rng = np.random.default_rng(3)
    amps = 2.0 + 0.02 * rng.standard_normal(15)
    means = 0.5 + 0.01 * rng.standard_normal(15)

    def robust(v):
        d = v[2:] - 2 * v[1:-1] + v[:-2]
        return 1.4826 * np.median(np.abs(d - np.median(d))) / math.sqrt(6.0)

    expected = max(robust(amps), robust(means)) / np.median(amps)
    assert 0.003 < expected < 0.03
    assert _scatter(amps, means) == pytest.approx(expected, rel=1e-12)


def test_adaptive_tolerance_widens_by_half_until_a_cycle_is_kept():
    """Eight cycles of amplitude 1.00, 1.05, …, 1.35 mm (a clean staircase: the second differences vanish, the
    tolerance starts at the 3 % floor).  At 3 % no two neighbours agree (5/1.35 = 3.7 % at best), the single-cycle
    run loses its first cycle and none is kept; ×1.5 gives 4.5 %, where 1.25, 1.30, 1.35 agree with 1.30 (within
    0.0585 mm): plateau 1.30 mm, run 5–7, cycles 6 and 7 kept after the first is dropped.  The reason says so."""
    w = 2 * math.pi
    amps = 1.0 + 0.05 * np.arange(8)
    t = np.linspace(0.0, 8.0, 8 * 64, endpoint=False)
    x = 3.0 + amps[np.minimum(t.astype(int), 7)] * np.sin(w * t)
    win = select_steady(t, x, w, 0.0, rel_tol=None)
    assert win.n_cycles_start == 0 and win.cycles_kept == [6, 7]
    assert win.rel_tol == pytest.approx(0.045, rel=1e-12) and win.plateau_A == pytest.approx(1.30, rel=1e-9)
    assert win.reason.startswith("widened to 4.5 %: no steady cycle within 3 % (floor 3 % (4 x cycle-to-cycle "
                                 "scatter ")
    assert win.t_start == pytest.approx(6.0, abs=1e-9) and win.t_end == pytest.approx(8.0, abs=1e-9)


def _stats_without_drift(amps, sd=0.0, nn=8):
    n = len(amps)
    return (list(np.arange(n + 1, dtype=float)), np.array(amps, float), np.zeros(n), np.zeros(n),
            np.full(n, sd), np.full(n, nn))


# --- seed 810 survivors --------------------------------------------------------------------------------------
@pytest.mark.parametrize("tol", [None, 0.03])
def test_a_record_shorter_than_one_cycle_has_no_cycle_and_no_scatter(tol):
    """Half a period of a 1 Hz sine: no whole cycle, so no plateau, scatter NaN (the docstring) and no window;
    the window starts and ends at the first sample.  Bug caught: ``_plateau``'s ``amps.size == 0`` guard →
    ``< 0`` (numpy's max of an empty array raises)."""
    t = np.linspace(0.0, 0.5, 64)
    win = select_steady(t, 3.0 + np.sin(2 * np.pi * t), 2 * np.pi, 0.0, rel_tol=tol)
    assert win.n_cycles_total == 0 and win.cycles_kept == [] and math.isnan(win.scatter)
    assert win.t_start == win.t_end == 0.0
    assert _plateau(np.zeros(0), 0.03) == 0.0 and _plateau(np.zeros(4), 0.03) == 0.0


def test_a_run_of_one_cycle_is_kept_without_drop_first():
    """Seven cycles of amplitudes 1, 2, 3, 4.5, 6, 8, 10 mm: at 3 % each agrees with nobody but itself; the
    plateau (ties → the larger) is 10 mm, only cycle 6 is steady: a run of one cycle, kept as [6] with
    drop_first=False and dropped (nothing kept) with drop_first=True.  With no steady
    cycle at all nothing is kept.  Bug caught: the longest run's start value ``(0, 0)`` → ``(-1, 0)`` (a one-cycle
    run no longer beats the empty start, and the empty window becomes cycle −1)."""
    t = np.arange(8.0)
    amps = [1.0, 2.0, 3.0, 4.5, 6.0, 8.0, 10.0]
    win = _select_with_tol(t, _stats_without_drift(amps), 0.03, False, None)
    assert win.plateau_A == 10.0 and win.cycles_kept == [6] and (win.t_start, win.t_end) == (6.0, 7.0)
    assert _select_with_tol(t, _stats_without_drift(amps), 0.03, True, None).cycles_kept == []
    st = list(_stats_without_drift(amps))
    st[3] = np.full(7, np.inf)  # every cycle incomplete-like: infinite drift, none steady
    win = _select_with_tol(t, tuple(st), 0.03, False, None)
    assert win.cycles_kept == [] and win.t_start == win.t_end == 0.0


# --- weak spots of steady.py -----------------------------------------------------------------------------------
def test_steady_window_texts_and_dict_by_hand():
    """``describe``, ``statement`` and ``to_dict`` of a hand-made window (the documented one-line forms)."""
    win = SteadyWindow(2.0, 10.0, [1, 2], 5, [1.0] * 5, [0.0] * 5, 1.0, 0.05)
    assert win.describe() == "cycles 1-2 of 5 (t = 2..10 s)"
    assert win.statement() == "cycles 1-2 of 5 (t = 2..10 s), 2 cycle(s) kept, tolerance 5 % (given)"
    assert win.to_dict() == {"t_start": 2.0, "t_end": 10.0, "cycles_kept": [1, 2], "n_cycles_total": 5,
                             "plateau_A": 1.0, "rel_tol": 0.05, "requested_tol": 0.03, "scatter": None,
                             "reason": ""}
    win = SteadyWindow(1700000002.0, 1700000010.0, [1, 2], 5, [1.0] * 5, [0.0] * 5, 1.0, 0.045,
                       requested_tol=None, scatter=0.01, reason="why")
    assert win.statement() == ("cycles 1-2 of 5 (t = 1700000002..1700000010 s), 2 cycle(s) kept, "
                               "tolerance 4.5 % (adaptive): why")
    assert win.to_dict()["scatter"] == 0.01
    assert SteadyWindow(0.0, 0.0, [], 0, [], [], 0.0, 0.03).describe() == "no steady cycles"


@pytest.mark.parametrize("a,b,expect", [(1000.25, 1010.25, ("1000.25", "1010.25")),  # span 10: hundredths
                                        (-4.123, 4.123, ("-4.123", "4.123")),  # span > |t|: 4 digits
                                        (2.0, 2.0, ("2", "2"))])  # empty window
def test_window_times_show_four_significant_digits_of_the_span(a, b, expect):
    """A window time is written to 4 significant digits of the window's span (the docstring of ``_t_text``):
    1000.25..1010.25 (span 10.00) to the hundredth, −4.123..4.123 (span 8.246) to the thousandth."""
    win = SteadyWindow(a, b, [0], 1, [1.0], [0.0], 1.0, 0.03)
    assert (_t_text(a, win), _t_text(b, win)) == expect


def test_count_within_and_plateau_by_hand():
    """Amplitudes 1, 1.02, 1.05, 0, 2 at 3 %: 1 ± 0.03 holds 1 and 1.02 (2); 1.02 ± 0.0306 holds all three (3);
    1.05 ± 0.0315 holds 1.02 and 1.05 (2); 0 counts nothing; 2 itself (1).  The plateau is the amplitude most
    agree with, ties to the larger: [1, 1, 2, 2] → 2; [1, 1, 1, 2, 2] → 1; the median of its neighbours:
    [1, 1.02, 1.05] → 1.02."""
    assert _count_within(np.array([1.0, 1.02, 1.05, 0.0, 2.0]), 0.03).tolist() == [2, 3, 2, 0, 1]
    assert _plateau(np.array([1.0, 1.0, 2.0, 2.0]), 0.03) == 2.0
    assert _plateau(np.array([1.0, 1.0, 1.0, 2.0, 2.0]), 0.03) == 1.0
    assert _plateau(np.array([1.0, 1.02, 1.05]), 0.03) == 1.02
    # cycles at or below the floor are no candidates
    assert _plateau(np.array([1.0, 1.0, 1.0, 2.0, 2.0]), 0.03, floor=1.0) == 2.0
    # an amplitude exactly at the edge is near (inclusive): 1 and 1.25 at 25 % → counts 2 and 1, plateau
    # median(1, 1.25) = 1.125
    assert _plateau(np.array([1.0, 1.25]), 0.25) == pytest.approx(1.125, rel=1e-15)


def test_scatter_needs_five_triples_of_plateau_cycles():
    """``MIN_TRIPLES`` = 5 second differences (7 consecutive plateau cycles): 6 cycles → NaN, 7 → a number; a
    cycle more than 2·15 % = 30 % off the plateau is no candidate (it breaks the triples it is in)."""
    assert MIN_TRIPLES == 5
    rng = np.random.default_rng(0)
    a = 2.0 + 0.02 * rng.standard_normal(7)
    assert math.isnan(_scatter(a[:6], np.zeros(6)))
    assert math.isfinite(_scatter(a, np.zeros(7)))
    b = a.copy()
    b[3] = 2.0 * 1.31  # cycle 3 is in 3 of the 5 triples (0-2, …, 4-6): 2 are left
    assert math.isnan(_scatter(b, np.zeros(7)))
    b[3] = 2.0 * 1.29  # within 30 %: still a candidate
    assert math.isfinite(_scatter(b, np.zeros(7)))


def test_select_steady_refuses_a_bad_omega_or_tolerance():
    """ω must be > 0 rad/s and a given tolerance in (0, 1): the messages name the value and the range."""
    t, x = np.arange(10.0), np.zeros(10)
    with pytest.raises(ValueError, match=r"omega = 0.0 rad/s is invalid: must be > 0"):
        select_steady(t, x, 0.0, 0.0)
    for tol in (0.0, 1.0, -0.1):
        with pytest.raises(ValueError, match=rf"rel_tol = {tol!r} is invalid: must be in \(0, 1\)"):
            select_steady(t, x, 1.0, 0.0, rel_tol=tol)
    assert select_steady(t, x, 1.0, 0.0, rel_tol=0.999).rel_tol == 0.999


def test_too_few_cycles_for_a_scatter_says_seven():
    """Five whole cycles of a clean sine, adaptive tolerance: the scatter needs 7 plateau cycles, so the reason
    is "floor 3 % (too few cycles to measure the scatter (< 7 on the plateau))"."""
    t = np.linspace(0.0, 5.0, 5 * 64, endpoint=False)
    win = select_steady(t, 3.0 + np.sin(2 * np.pi * t), 2 * np.pi, 0.0, rel_tol=None)
    assert win.reason == ("tolerance from the record: floor 3 % (too few cycles to measure the scatter "
                          "(< 7 on the plateau))")
    assert win.requested_tol is None and win.rel_tol == 0.03


def test_cycles_with_fewer_than_six_samples_are_incomplete():
    """Four samples per cycle: no cycle can be fitted (≥ 6 samples are needed): amplitude 0, mean NaN, none kept;
    eight samples per cycle: every cycle fitted with the sine's amplitude."""
    w = 2 * np.pi
    t = np.arange(0, 10 * 4) / 4.0 + 0.1
    win = select_steady(t, np.sin(w * t), w, 0.0, rel_tol=0.03)
    assert win.n_cycles_total >= 8 and all(a == 0.0 for a in win.cycle_amplitudes)
    assert all(math.isnan(m) for m in win.cycle_means) and win.cycles_kept == []
    t = np.arange(0, 10 * 8) / 8.0 + 0.1
    win = select_steady(t, np.sin(w * t), w, 0.0, rel_tol=0.03)
    assert win.cycle_amplitudes == pytest.approx([1.0] * win.n_cycles_total, abs=1e-12)


def test_a_cycle_is_whole_when_its_last_sample_one_step_before_the_boundary_is_there():
    """1 Hz sampled at 100 Hz from t = 0: a record ending at 2.99 s holds the last sample of cycle 2 (one step
    before the boundary at 3 s): 3 whole cycles; ending at 2.98 s, cycle 2 lacks its last sample: 2 (the rule
    of ``_cycle_stats``: "a cycle is whole if its last sample (one step before the boundary) is present")."""
    w = 2 * np.pi
    for last, whole in ((299, 3), (298, 2)):
        t = np.arange(last + 1) * 0.01
        assert select_steady(t, 3 + np.sin(w * t), w, 0.0, rel_tol=0.03, drop_first=False).n_cycles_total == whole


def test_a_cycle_that_misses_samples_at_its_start_is_incomplete():
    """Four cycles of 1 Hz at 100 Hz; one sample missing at the start of cycle 1 (a step of jitter) leaves it
    whole (amplitude 1); three missing (a gap) make it incomplete: amplitude 0 and mean NaN (the docstring's
    values for an incomplete cycle), while the other cycles keep amplitude 1."""
    w = 2 * np.pi
    t = np.arange(400) * 0.01
    for k, amp1 in ((1, 1.0), (3, 0.0)):
        m = np.ones(400, bool)
        m[100:100 + k] = False
        win = select_steady(t[m], 3 + np.sin(w * t[m]), w, 0.0, rel_tol=0.03, drop_first=False)
        assert win.n_cycles_total == 4
        assert win.cycle_amplitudes == pytest.approx([1.0, amp1, 1.0, 1.0], abs=1e-9)
        assert math.isnan(win.cycle_means[1]) == (amp1 == 0.0)


def test_widening_stops_at_the_fifteen_per_cent_cap():
    """Eight cycles of amplitude 1.14^k mm (k = 0..7: 14 % steps, no second differences' scatter): 3, 4.5,
    6.75 and 10.125 % hold no two neighbours; the next widening, 15.19 %, is capped at TOL_MAX = 15 %, where
    a_{k±1} agree with a_k: plateau a_6 = 1.14⁶ = 2.195 mm (ties → the larger), run 5–7, cycles 6 and 7 kept."""
    w = 2 * np.pi
    amps = 1.14 ** np.arange(8)
    t = np.linspace(0.0, 8.0, 8 * 64, endpoint=False)
    win = select_steady(t, 3.0 + amps[np.minimum(t.astype(int), 7)] * np.sin(w * t), w, 0.0, rel_tol=None)
    assert win.rel_tol == 0.15 and win.cycles_kept == [6, 7] and win.n_cycles_start == 0
    assert win.plateau_A == pytest.approx(1.14**6, rel=1e-9)
    assert win.reason.startswith("widened to 15 %: no steady cycle within 3 % (floor 3 % (too few cycles")


def test_amplitude_floor_is_four_standard_errors_of_the_median_residual():
    """``_amp_floor``: 4·median(residual SD)·sqrt(2/n) per cycle (NaN residuals ignored, n at least 1): median
    of 0.1, 0.3, 0.1 mm is 0.1 mm: n = 8 → 0.2 mm, n = 2 → 0.4 mm, n = 0 → 4·0.1·√2 mm; no finite residual → 0."""
    from chainid.signal.steady import _amp_floor

    got = _amp_floor(np.array([0.1, np.nan, 0.3, 0.1]), np.array([8, 8, 2, 0]))
    assert got == pytest.approx([0.2, 0.2, 0.4, 0.4 * math.sqrt(2.0)], rel=1e-12)
    assert _amp_floor(np.array([np.nan, np.nan]), np.array([8, 8])).tolist() == [0.0, 0.0]


def test_adaptive_reason_states_the_scatter_in_per_cent():
    """Cycle amplitudes jittering by 1 % (20 cycles): the reason states the measured scatter as a percentage,
    "4 x cycle-to-cycle scatter S %" with S = 100 × ``win.scatter`` (the robust SD of second differences,
    pinned to its formula by test_scatter_is_the_robust_sd_of_second_differences_over_the_plateau), between 0.5 and
    2 % here.  Bug caught: ``100 * scatter`` → ``100 // scatter`` in the text."""
    w = 2 * np.pi
    rng = np.random.default_rng(4)
    amps = 2.0 * (1.0 + 0.01 * rng.standard_normal(20))
    t = np.linspace(0.0, 20.0, 20 * 64, endpoint=False)
    win = select_steady(t, 1.0 + amps[np.minimum(t.astype(int), 19)] * np.sin(w * t), w, 0.0, rel_tol=None)
    assert 0.005 < win.scatter < 0.02
    assert f"4 x cycle-to-cycle scatter {100 * win.scatter:.3g} %" in win.reason
