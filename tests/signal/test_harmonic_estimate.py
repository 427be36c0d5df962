"""The harmonic estimate of a record (chainid.signal.harmonic): the FFT peak and its refinement, the candidate
search, the linear and nonlinear fits, phases in the record's own time.  Units s, mm, rad/s."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.signal.harmonic import (
    HarmonicEstimate,
    _fft_peak_omega,
    _nls_harmonic,
    _search_stride,
    estimate_harmonic,
    linear_harmonic,
    shift_window,
)
from chainid.signal.steady import SteadyWindow


def test_harmonic_estimate_kinematics_closed_form():
    """x = x0 + A sin(ωt + θ), ẋ = ωA cos(ωt + θ), ẍ = −ω²A sin(ωt + θ), period 2π/ω (ω = 2: π)."""
    h = HarmonicEstimate(omega=2.0, x0=1.0, A=3.0, theta=0.5, noise=0.0)
    t = np.array([0.0, 0.3, 1.1])
    np.testing.assert_allclose(h.x(t), 1.0 + 3.0 * np.sin(2.0 * t + 0.5), rtol=1e-15)
    np.testing.assert_allclose(h.xdot(t), 6.0 * np.cos(2.0 * t + 0.5), rtol=1e-15)
    np.testing.assert_allclose(h.xddot(t), -12.0 * np.sin(2.0 * t + 0.5), rtol=1e-15)
    assert h.period == pytest.approx(math.pi, rel=1e-15)


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


# --- weak spots of harmonic.py ---------------------------------------------------------------------------------
@pytest.mark.parametrize("f", [5.0, 5.013, 3.3])
def test_fft_peak_is_refined_between_bins_by_the_parabola(f):
    """A pure sine between FFT bins (2001 samples over 10 s, padded to 8192: bin 1/40.96 Hz): the parabolic
    interpolation of the log-magnitude (Hann window: a near-Gaussian peak) puts it within 2 % of a bin of the
    true frequency; the bin alone is up to half a bin off.  Bugs caught: the parabola's vertex, the bin width, the
    padding."""
    t = np.linspace(0.0, 10.0, 2001)
    bin_hz = 1.0 / (8192 * (t[1] - t[0]))
    w = _fft_peak_omega(t, np.sin(2 * np.pi * f * t + 0.3))
    assert abs(w / (2 * np.pi) - f) < 0.02 * bin_hz


def test_linear_harmonic_recovers_the_coefficients_exactly():
    """x = 1.5 + 2 sin(3t) − 0.5 cos(3t) at ω = 3: the [1, sin, cos] least squares returns (1.5, 2, −0.5)."""
    t = np.linspace(0.2, 7.0, 300)
    x0, a, b = linear_harmonic(t, 1.5 + 2.0 * np.sin(3.0 * t) - 0.5 * np.cos(3.0 * t), 3.0)
    assert (x0, a, b) == pytest.approx((1.5, 2.0, -0.5), abs=1e-12)


@pytest.mark.parametrize("w0", [3.95, -4.0])
def test_nls_harmonic_phase_in_absolute_time_and_positive_omega(w0):
    """x = 1.5 + 2 sin(4t + 0.7) on t ∈ [3, 8] (not centred on 0): the refinement from 3.95 rad/s, or from
    −4 rad/s (sin(−ωt) = −sin(ωt), normalised to ω > 0), returns ω = 4, x0 = 1.5, A = 2, θ = 0.7 referred to t = 0,
    and an RMS residual of 0."""
    t = np.linspace(3.0, 8.0, 800)
    w, x0, A, theta, rms = _nls_harmonic(t, 1.5 + 2.0 * np.sin(4.0 * t + 0.7), w0)
    assert (w, x0, A, theta) == pytest.approx((4.0, 1.5, 2.0, 0.7), abs=1e-9)
    assert rms < 1e-12


def test_search_stride_by_hand():
    """Records shorter than 2·20 000 samples are never decimated; longer ones keep ≥ 16 samples per period and
    ≥ 20 000 samples: stride = min(n // 20 000, samples per period // 16).  At 1 kHz: 100 000 samples of 1 Hz →
    min(5, 62) = 5; of 1000/48 Hz (48 samples per period) → min(5, 3) = 3; 39 999 samples → 1; 40 000 → 2."""
    t = np.arange(100_000) * 1e-3
    assert _search_stride(t, 2 * np.pi) == 5
    assert _search_stride(t, 2 * np.pi * 1000.0 / 48.0) == 3
    assert _search_stride(t[:39_999], 2 * np.pi) == 1
    assert _search_stride(t[:40_000], 2 * np.pi) == 2


def test_estimate_harmonic_needs_sixteen_samples():
    """Fewer than 16 samples: "only 15 samples; need at least 16" naming the test; 16 samples are analysed."""
    t = np.linspace(0.0, 1.0, 15)
    with pytest.raises(ValueError, match=r"test 'T7': only 15 samples; need at least 16"):
        estimate_harmonic(t, np.sin(6 * np.pi * t), test="T7")
    t = np.linspace(0.0, 1.0, 16)
    est = estimate_harmonic(t, np.sin(6 * np.pi * t))
    assert est.omega == pytest.approx(6 * np.pi, rel=1e-6)


def test_no_oscillation_is_refused_naming_the_test():
    """A record without motion (x ≡ 0: the velocity is exactly zero) has no FFT peak: "no harmonic oscillation
    found", naming the test."""
    with pytest.raises(ValueError, match=r"test 'Z': no harmonic oscillation found in x\(t\)"):
        estimate_harmonic(np.linspace(0.0, 5.0, 500), np.zeros(500), test="Z")


def test_harmonic_estimate_phase_and_window_in_the_records_own_time():
    """``phase`` is ω(t − t_origin) + θ; ``shift_window`` adds t_origin to both window ends (and returns the
    same window for t_origin = 0)."""
    h = HarmonicEstimate(omega=2.0, x0=0.0, A=1.0, theta=0.25, noise=0.0, t_origin=100.0)
    assert h.phase(np.array([100.0, 101.5])) == pytest.approx([0.25, 3.25], abs=1e-12)
    win = SteadyWindow(1.0, 4.0, [1, 2, 3], 5, [1.0] * 5, [0.0] * 5, 1.0, 0.03)
    assert shift_window(win, 0.0) is win
    s = shift_window(win, 100.0)
    assert (s.t_start, s.t_end, s.cycles_kept) == (101.0, 104.0, [1, 2, 3]) and (win.t_start, win.t_end) == (1.0, 4.0)


def test_estimate_harmonic_of_a_shifted_record_by_hand():
    """x = 5 + 2 sin(2π·2 (t − 1000) + 0.4), 12 s at 500 Hz from t = 1000 s: ω = 4π, A = 2, x0 = 5, θ = 0.4
    referred to the first sample (t_origin = 1000), window ends within the record's own time."""
    t = 1000.0 + np.arange(6000) / 500.0
    est = estimate_harmonic(t, 5.0 + 2.0 * np.sin(4 * np.pi * (t - 1000.0) + 0.4))
    assert est.t_origin == 1000.0
    assert (est.omega, est.A, est.x0, est.theta) == pytest.approx((4 * np.pi, 2.0, 5.0, 0.4), abs=1e-7)
    assert 1000.0 <= est.window.t_start < est.window.t_end <= t[-1]
    # 24 whole cycles from the first upward crossing after t = 1000; the first is dropped
    assert est.window.n_cycles_total == 23 and est.window.n_cycles == 22


# --- seed 811 survivors ----------------------------------------------------------------------------------------
def test_fft_peak_cut_is_one_and_a_half_cycles_of_the_records_own_span():
    """The low-bin cut is 1.5 cycles of the record's span, wherever the record starts: x = 2 sin(2π·0.1 t) +
    sin(2π·0.8 t) on t ∈ [10, 20] s (one cycle of the larger line) peaks at the 0.8 Hz line (within 0.5 %).  Bug
    caught: ``1.5 / (t_end − t_start)`` → ``1.5 / (t_end + t_start)`` (0.075 Hz from t = 10 s: the 0.1 Hz line
    is no longer cut and wins)."""
    t = np.linspace(10.0, 20.0, 2001)
    x = 2.0 * np.sin(2 * np.pi * 0.1 * t) + np.sin(2 * np.pi * 0.8 * t)
    assert _fft_peak_omega(t, x) == pytest.approx(2 * np.pi * 0.8, rel=5e-3)


def test_a_large_start_transient_does_not_hide_the_test_in_the_last_half():
    """First 10 s: a settling motion of 5 mm at 0.5 Hz; last 10 s: the test, 0.5 mm at 2 Hz about 3 mm.  The
    whole record's velocity peak is the transient's (15.7 vs 6.3 mm/s over equal spans); the candidates from the
    last half and third (the docstring's step 1) find 2 Hz, whose steady window (19 cycles after the first is
    dropped, from t = 10.5 s) beats the transient's 4.  Bug caught: the candidate segments ``t[0] + f·span`` →
    ``t[0] − f·span`` (every candidate from the whole record)."""
    t = np.arange(0.0, 20.0, 1 / 200.0)
    x = 3.0 + np.where(t < 10.0, 5.0 * np.sin(2 * np.pi * 0.5 * t), 0.5 * np.sin(2 * np.pi * 2.0 * (t - 10.0)))
    est = estimate_harmonic(t, x)
    assert est.omega == pytest.approx(4 * np.pi, rel=1e-9)
    assert (est.A, est.x0) == pytest.approx((0.5, 3.0), abs=1e-9)
    assert est.window.n_cycles == 19 and est.window.t_start == pytest.approx(10.5, abs=1e-9)


def test_fft_candidates_only_from_segments_of_sixteen_samples_or_more(monkeypatch):
    """The candidate search's FFT runs on the whole record, its last half and its last third, but only on a
    segment of ≥ 16 samples (the record's own minimum): a 40-sample record gives one candidate search (the half
    and the third hold 20 and 13 samples → whole and half only).  Bug caught: ``seg.sum() < 16`` → ``== 16``
    (a 13-sample third searched: on short noisy records a different candidate may win)."""
    import chainid.signal.harmonic as H

    sizes = []
    real = H._fft_peak_omega

    def spy(t, x):
        sizes.append(t.size)
        return real(t, x)

    monkeypatch.setattr(H, "_fft_peak_omega", spy)
    t = np.arange(40) / 10.0
    H.estimate_harmonic(t, 2.0 + np.sin(2 * np.pi * t))
    assert sizes == [40, 20]


def test_only_distinct_fft_peaks_become_candidates(monkeypatch):
    """"Distinct peaks are all tried" (the docstring's step 1): a clean 2 Hz sine gives the same peak (within 1 %)
    over the whole record, its last half and its last third, hence one candidate (one provisional window, the
    lenient selection with no drift limit); the transient record of
    test_a_large_start_transient_does_not_hide_the_test_in_the_last_half gives two (0.5 and 2 Hz)."""
    import chainid.signal.harmonic as H

    lenient = []
    real = H.select_steady

    def spy(*a, **k):
        if k.get("drift_tol") == math.inf:
            lenient.append(a[2])
        return real(*a, **k)

    monkeypatch.setattr(H, "select_steady", spy)
    t = np.arange(0.0, 20.0, 1 / 200.0)
    H.estimate_harmonic(t, 3.0 + 0.5 * np.sin(2 * np.pi * 2.0 * t))
    assert len(lenient) == 1 and lenient[0] == pytest.approx(4 * np.pi, rel=1e-3)
    lenient.clear()
    x = 3.0 + np.where(t < 10.0, 5.0 * np.sin(2 * np.pi * 0.5 * t), 0.5 * np.sin(2 * np.pi * 2.0 * (t - 10.0)))
    H.estimate_harmonic(t, x)
    assert sorted(w / (2 * np.pi) for w in lenient) == pytest.approx([0.5, 2.0], rel=0.02)
