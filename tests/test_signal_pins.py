"""Pins of chainid.signal to closed forms and hand numbers (survivors of the mutation run, issue 20 §5).

Units: mm, s, rad/s.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.signal.harmonic import HarmonicEstimate
from chainid.signal.steady import TOL_MAX, _select_with_tol, select_steady


def test_harmonic_estimate_kinematics_closed_form():
    """x = x0 + A sin(ωt + θ), ẋ = ωA cos(ωt + θ), ẍ = −ω²A sin(ωt + θ), period 2π/ω (ω = 2: π)."""
    h = HarmonicEstimate(omega=2.0, x0=1.0, A=3.0, theta=0.5, noise=0.0)
    t = np.array([0.0, 0.3, 1.1])
    np.testing.assert_allclose(h.x(t), 1.0 + 3.0 * np.sin(2.0 * t + 0.5), rtol=1e-15)
    np.testing.assert_allclose(h.xdot(t), 6.0 * np.cos(2.0 * t + 0.5), rtol=1e-15)
    np.testing.assert_allclose(h.xddot(t), -12.0 * np.sin(2.0 * t + 0.5), rtol=1e-15)
    assert h.period == pytest.approx(math.pi, rel=1e-15)


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


# --- seed-22 mutation survivors (issue 20 §5) ------------------------------------------------------------------
def test_fft_peak_removes_a_linear_trend_first():
    """x = 100·t + sin(2π·5 t) over 10 s (a ramp of 1000 mm under a 1 mm oscillation): the documented linear
    trend removal leaves the 5 Hz line as the peak (within 0.1 %).  Bug caught: the least-squares line's centre
    ``tu − mid`` → ``tu + mid`` (an uncentred regressor leaves most of the ramp: its leakage wins)."""
    from chainid.signal.harmonic import _fft_peak_omega

    t = np.linspace(0.0, 10.0, 2001)
    assert _fft_peak_omega(t, 100.0 * t + np.sin(2 * np.pi * 5.0 * t)) == pytest.approx(2 * np.pi * 5.0, rel=1e-3)
    t = t + 3.0  # the same on a record that does not start at 0
    assert _fft_peak_omega(t, 100.0 * t + np.sin(2 * np.pi * 5.0 * t)) == pytest.approx(2 * np.pi * 5.0, rel=1e-3)


def test_fft_peak_ignores_lines_below_one_and_a_half_cycles():
    """x = 2 sin(2π·0.1 t) + sin(2π·0.8 t) over 10 s: one cycle of the larger line, eight of the smaller.  Bins
    below 1.5 cycles in the record (0.15 Hz) are ignored, so the peak is the 0.8 Hz line (within 0.5 %).  Bug
    caught: the cut ``1.5 / span`` → ``1.5 − span`` (negative for a 10 s record: nothing ignored)."""
    from chainid.signal.harmonic import _fft_peak_omega

    t = np.linspace(0.0, 10.0, 2001)
    x = 2.0 * np.sin(2 * np.pi * 0.1 * t) + np.sin(2 * np.pi * 0.8 * t)
    assert _fft_peak_omega(t, x) == pytest.approx(2 * np.pi * 0.8, rel=5e-3)


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
