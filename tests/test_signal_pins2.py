"""More pins of chainid.signal to closed forms, hand numbers and the documented contract (issue 20 §5,
own-seed mutation survivors 810– and the weak spots found by reading the modules).

Units: mm, s, rad/s.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.signal.harmonic import (HarmonicEstimate, _fft_peak_omega, _nls_harmonic, _search_stride,
                                     estimate_harmonic, linear_harmonic, shift_window)
from chainid.signal.steady import (MIN_TRIPLES, SteadyWindow, _count_within, _plateau, _scatter,
                                   _select_with_tol, _t_text, select_steady)


def _stats(amps, sd=0.0, nn=8):
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
    win = _select_with_tol(t, _stats(amps), 0.03, False, None)
    assert win.plateau_A == 10.0 and win.cycles_kept == [6] and (win.t_start, win.t_end) == (6.0, 7.0)
    assert _select_with_tol(t, _stats(amps), 0.03, True, None).cycles_kept == []
    st = list(_stats(amps))
    st[3] = np.full(7, np.inf)  # every cycle incomplete-like: infinite drift, none steady
    win = _select_with_tol(t, tuple(st), 0.03, False, None)
    assert win.cycles_kept == [] and win.t_start == win.t_end == 0.0


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


def test_segment_lstsq_by_hand():
    """Two segments, regressors (1, u), two targets: segment 0 holds y = 2 + 3u exactly (β = 2, 3; RSS 0);
    segment 1 holds y = (0, 1, 5) at u = (0, 1, 2): the least-squares line by hand is −1/2 + 5/2·u with RSS
    (1/2)² + (1)² + (1/2)² = 1.5.  A segment marked invalid gets β = 0, so its RSS is Σ y²."""
    from chainid.signal.cycles import segment_lstsq

    seg = np.array([0, 0, 0, 1, 1, 1])
    u = np.array([0.0, 1.0, 2.0, 0.0, 1.0, 2.0])
    y = np.array([2.0, 5.0, 8.0, 0.0, 1.0, 5.0])
    beta, rss = segment_lstsq(seg, 2, (np.ones(6), u), (y, 2 * y), rss=True)
    assert beta.shape == (2, 2, 2) and rss.shape == (2, 2)
    np.testing.assert_allclose(beta[:, :, 0], [[2.0, 3.0], [-0.5, 2.5]], atol=1e-12)
    np.testing.assert_allclose(beta[:, :, 1], [[4.0, 6.0], [-1.0, 5.0]], atol=1e-12)
    np.testing.assert_allclose(rss, [[0.0, 0.0], [1.5, 6.0]], atol=1e-12)
    beta, rss = segment_lstsq(seg, 2, (np.ones(6), u), (y,), valid=np.array([True, False]), rss=True)
    np.testing.assert_allclose(beta[1, :, 0], [0.0, 0.0])
    assert rss[1, 0] == pytest.approx(0.0 + 1.0 + 25.0)
    b2, none = segment_lstsq(seg, 2, (np.ones(6), u), (y,))
    assert none is None and np.allclose(b2[0, :, 0], [2.0, 3.0])
