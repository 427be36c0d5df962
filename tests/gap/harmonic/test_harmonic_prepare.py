"""Harmonic tests prepared for the diagnosis (chainid.gap.harmonic.prepare): phase bins and their noise, cycle
statistics, the Fourier series of x, the second plateau, times from the record's first sample.  Units s, mm, N."""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from chainid.gap.harmonic.prepare import other_plateau


# ---------------------------------------------------------------- prepare.other_plateau
def test_second_plateau_named_with_its_distance_from_the_steady_mean():
    """A whole cycle at the plateau amplitude about a mean more than half that amplitude away is a second steady
    state; the message gives its index, amplitude, mean and distance |8 − 5| = 3 mm (by hand).  Ramp cycles
    (amplitude 40 % off) and cycles within half an amplitude of the mean do not count."""
    win = SimpleNamespace(cycle_amplitudes=[1.2, 2.0, 2.0, 2.0, 2.0, 2.1, 1.9], cycle_means=[9.0, 5.0, 5.1, 4.9, 5.0,
                          5.9, 8.0], cycles_kept=[1, 2, 3, 4], plateau_A=2.0)
    msg = other_plateau(win)
    # cycle 0 is a ramp (1.2/2 − 1 = −40 %), cycle 5 is 0.9 mm < 1 mm (half the amplitude) from the mean 5.0
    assert msg.startswith("not one steady harmonic test: cycle 6 oscillates at the plateau amplitude (1.9 mm)")
    assert "about x = 8 mm, 3 mm from the steady window's mean" in msg
    win.cycle_means = [9.0, 5.0, 5.1, 4.9, 5.0, 5.9, 5.8]
    assert other_plateau(win) == ""


# ---------------------------------------------------------------- prepare.fourier_x / phase_grid
def test_fourier_x_reproduces_a_two_harmonic_motion_and_its_derivatives():
    """x = 2 + 0.3 sin ψ + 0.05 cos 3ψ, ψ = 5t + 0.2 (inside the 5-harmonic basis): x, ẋ = 1.5 cos ψ − 0.75 sin 3ψ,
    ẍ = −7.5 sin ψ − 11.25 cos 3ψ, exact to round-off at any t."""
    from chainid.gap.harmonic.prepare import fourier_x

    t = np.linspace(0.0, 3.0, 700)
    ps = 5 * t + 0.2
    f = fourier_x(t, 2 + 0.3 * np.sin(ps) + 0.05 * np.cos(3 * ps), 5.0, 0.2)
    ts = np.array([-1.0, 0.37, 10.0])
    p = 5 * ts + 0.2
    x, xd, xdd = f(ts)
    np.testing.assert_allclose(x, 2 + 0.3 * np.sin(p) + 0.05 * np.cos(3 * p), rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(xd, 1.5 * np.cos(p) - 0.75 * np.sin(3 * p), rtol=1e-9, atol=1e-10)
    np.testing.assert_allclose(xdd, -7.5 * np.sin(p) - 11.25 * np.cos(3 * p), rtol=1e-9, atol=1e-9)


def test_phase_grid_commensurate_sampling_is_one_point_per_phase():
    """64 samples per cycle over 3 cycles, 8 bins: the grid has the 64 distinct phases (weight 3 each, 24 per bin) at
    t = (ψ − θ)/ω in [0, T), and a grid mean of any function of ψ equals the samples' bin mean exactly."""
    from chainid.gap.harmonic.prepare import phase_grid

    w, th, B = 2 * math.pi, math.pi / 64, 8  # phases half a sample off the bin edges
    t = np.arange(3 * 64) / 64.0
    psi = np.mod(w * t + th, 2 * math.pi)
    g = phase_grid(psi, B, th, w, lambda ts: (np.sin(w * ts), np.cos(w * ts), -np.sin(w * ts)))
    np.testing.assert_allclose(g["t"], np.arange(64) / 64.0, atol=1e-12)
    # cells may split one phase by round-off (ψ mod 2π): the weights still count every sample in its own bin
    assert np.bincount(g["bin"], weights=g["w"]).tolist() == [24.0] * 8
    assert np.bincount(g["map"], weights=g["w"]).tolist() == [3.0] * 64
    np.testing.assert_allclose(g["x"], np.sin(w * g["t"]), atol=1e-12)
    bins = np.minimum((psi / (2 * math.pi) * B).astype(int), B - 1)
    counts = np.bincount(bins, minlength=B).astype(float)
    binmean = np.bincount(bins, weights=np.sin(w * t) ** 3, minlength=B) / counts  # x(t) = sin(ωt) sampled
    gridmean = np.bincount(g["bin"], weights=g["w"] * (g["x"] ** 3)[g["map"]], minlength=B) / counts
    np.testing.assert_allclose(gridmean, binmean, atol=1e-12)


def test_prepare_test_bins_and_noise_of_a_clean_record():
    """x = 2 + 0.3 sin(2π t + π/40) sampled 40 times a cycle over 12 cycles, F = 1000·(x − 0.5) + white noise σ = 2 N:
    ω = 2π, A = 0.3, x0 = 2; B = max(8, min(n_bins, 4·(40 // 8))) = 20 bins (8 with n_bins = 8) of equal counts;
    the bin means are F at the bins' mean x within the noise; σ = 2 N within 15 %."""
    from chainid.gap.harmonic.prepare import prepare_test
    from chainid.records.record import Record

    t = np.arange(12 * 40) / 40.0
    x = 2.0 + 0.3 * np.sin(2 * math.pi * t + math.pi / 40)  # samples half a step off the bin edges
    F = 1000.0 * (x - 0.5) + 2.0 * np.random.default_rng(9).normal(size=t.size)
    d = prepare_test(Record("P", t, x, F))
    assert d.test == "P" and d.counts.size == 20 and np.ptp(d.counts) == 0
    assert (d.omega, d.A, d.x0) == (pytest.approx(2 * math.pi, rel=1e-6), pytest.approx(0.3, rel=1e-6),
                                    pytest.approx(2.0, rel=1e-9))
    np.testing.assert_allclose(d.Fbar, 1000.0 * (d.binmean(d.x_meas) - 0.5), atol=4 * 2.0 / math.sqrt(d.counts[0]))
    assert d.sigma == pytest.approx(2.0, rel=0.15)
    assert d.t[0] >= 0 and np.all(np.diff(d.t) > 0)
    assert prepare_test(Record("P", t, x, F), n_bins=8).counts.size == 8


# ---------------------------------------------------------------- within-bin noise, local spectral peak
def test_bin_noise_removes_a_local_linear_trend_in_phase_and_time():
    """F exactly linear in phase and time inside every bin (a slope and a drift): the pooled scatter is 0; pure
    white noise of SD 2 N gives 2 N within a few %.  Bug caught: the 2×2 normal-equation solution garbled."""
    from chainid.gap.harmonic.cyclenoise import bin_noise as _bin_noise

    rng = np.random.default_rng(5)
    B = 16
    t = np.sort(rng.uniform(0.0, 10.0, 4000))
    psi = np.mod(2 * math.pi * 1.3 * t + 0.1 * rng.standard_normal(t.size), 2 * math.pi)
    bins = np.minimum((psi / (2 * math.pi) * B).astype(np.int64), B - 1)
    F = 100.0 + 7.0 * psi + 3.0 * t
    assert _bin_noise(t, F, psi, bins, B) < 1e-5  # N: round-off of the moment sums (F ~ 140 N)
    noise = 2.0 * rng.standard_normal(t.size)
    assert _bin_noise(t, F + noise, psi, bins, B) == pytest.approx(2.0, rel=0.05)


def test_cycle_stats_whole_cycles_by_hand():
    """F = 3 + 2 sin ψ + 0.5 cos ψ sampled over 6.5 cycles from ψ = 0.3: the first and last (partial) cycles are
    dropped, the 5 middle ones give mean 3, a = 2, b = 0.5 exactly.  Bug caught: no cycle marked whole."""
    from chainid.gap.harmonic.prepare import cycle_stats

    w = 2 * math.pi
    t = np.linspace(0.0, 6.5, 833)  # 128 samples per cycle
    psi = w * t + 0.3
    cy = cycle_stats(t, 3 + 2 * np.sin(psi) + 0.5 * np.cos(psi), w, 0.3)
    assert cy["t"].size == 5
    np.testing.assert_allclose(cy["mean"], 3.0, atol=1e-9)
    np.testing.assert_allclose(cy["a"], 2.0, atol=1e-9)
    np.testing.assert_allclose(cy["b"], 0.5, atol=1e-9)


def test_a_cycle_with_a_gap_in_its_samples_is_not_whole():
    """10 cycles of ψ = 2πt at 100 samples each, half of cycle 4's samples missing (a drop-out in the record):
    the whole cycles are 1..8 less cycle 4 (50 samples, under 0.9 × the median 100), their mean sample times
    1.495, 2.495, 3.495, 5.495, 6.495, 7.495, 8.495 s (by hand)."""
    from chainid.gap.harmonic.prepare import cycle_stats

    w = 2 * math.pi
    t = np.arange(1000) / 100.0
    keep = ~((t >= 4.0) & (t < 4.5))
    t = t[keep]
    cy = cycle_stats(t, 3 + 2 * np.sin(w * t), w, 0.0)
    np.testing.assert_allclose(cy["t"], [1.495, 2.495, 3.495, 5.495, 6.495, 7.495, 8.495], atol=1e-9)
    assert cy["n"].tolist() == [100.0] * 7


def test_prepared_time_is_from_the_records_first_sample():
    """``TestData.t`` is the time from the record's first sample and ``t + t_origin`` the record's own time
    (the docstring): a sine stamped from t = 1000 s gives t_origin = 1000 s, t inside [0, T], and
    x = x0 + A sin(ω t + θ) on the relative time."""
    from chainid.gap.harmonic.prepare import prepare_test
    from chainid.records.record import Record

    fs, f, n = 200.0, 2.0, 1600  # 8 s, 16 cycles
    tr = np.arange(n) / fs
    rng = np.random.default_rng(0)
    x = 2.0 + 0.3 * np.sin(2 * np.pi * f * tr + 0.4)
    F = 500.0 * x + 3.0 * 0.3 * 2 * np.pi * f * np.cos(2 * np.pi * f * tr + 0.4) + rng.normal(0, 0.5, n)
    rec = Record("T", tr + 1000.0, x, F)
    d = prepare_test(rec)
    assert d.t_origin == 1000.0
    assert 0.0 <= d.t[0] and d.t[-1] <= tr[-1] + 1e-9
    # every prepared sample is a record sample at its own time
    i = np.searchsorted(rec.t, d.t + d.t_origin)
    np.testing.assert_allclose(rec.t[i], d.t + d.t_origin, atol=1e-9)
    np.testing.assert_array_equal(rec.x[i], d.x_meas)
    np.testing.assert_allclose(d.x_meas, d.x0 + d.A * np.sin(d.omega * d.t + d.theta), atol=1e-3)
    assert d.omega == pytest.approx(2 * np.pi * f, rel=1e-4)


def _win(A, m, kept, plateau_A=1.0):
    return SimpleNamespace(cycle_amplitudes=list(A), cycle_means=list(m), cycles_kept=list(kept), plateau_A=plateau_A)


def test_other_plateau_rule_by_hand():
    """``other_plateau``: a whole cycle *outside* the steady window at the plateau's amplitude (within 25 %) about
    a mean more than half that amplitude from the kept cycles' median mean is a second steady state; ramp cycles
    (smaller amplitude), cycles at the same mean, and the kept cycles themselves do not count."""
    from chainid.gap.harmonic.prepare import other_plateau

    kept = [2, 3, 4, 5]
    A = [0.3, 0.6, 1.0, 1.0, 1.0, 1.0, 1.2]
    m = [5.0, 5.0, 5.0, 5.1, 4.9, 5.0, 5.0]
    assert other_plateau(_win(A, m, kept)) == ""  # a ramp-in, the plateau, one more cycle at its mean
    # cycle 6 at 1.2 A (within 25 %) about x = 5.6 (0.6 A away, > 0.5 A): another plateau
    msg = other_plateau(_win(A, m[:6] + [5.6], kept))
    assert msg == ("not one steady harmonic test: cycle 6 oscillates at the plateau amplitude (1.2 mm) about "
                   "x = 5.6 mm, 0.6 mm from the steady window's mean (a load step or another plateau)")
    assert other_plateau(_win(A, m[:6] + [5.45], kept)) == ""  # 0.45 A away: the same plateau
    assert other_plateau(_win(A[:6] + [1.3], m[:6] + [5.6], kept)) == ""  # 1.3 A: not the plateau's amplitude
    assert other_plateau(_win(A[:6] + [0.74], m[:6] + [4.0], kept)) == ""  # 0.74 A: a ramp cycle
    assert other_plateau(_win(A[:6] + [0.76], m[:6] + [4.0], kept)).startswith("not one steady harmonic test: "
                                                                                "cycle 6 ")
    # the first such cycle is named; a kept cycle far from the others' median is not "outside"
    assert "cycle 0 " in other_plateau(_win([1.0] + A[1:6] + [1.0], [3.0] + m[1:6] + [7.0], kept))
    assert other_plateau(_win(A[:6], m[:5] + [6.0], kept)) == ""
    # nothing to judge: no kept cycle, mismatched lists, no plateau amplitude
    assert other_plateau(_win(A, m[:6] + [5.6], [])) == ""
    assert other_plateau(_win(A, m[:6], kept)) == ""
    assert other_plateau(_win(A, m[:6] + [5.6], kept, plateau_A=0.0)) == ""
    assert other_plateau(_win(A, m[:6] + [5.6], kept + [9])) != ""  # an index beyond the cycles is ignored


def test_a_constant_force_has_the_documented_noise_floor_not_zero() -> None:
    """A harmonic test whose force does not vary at all has no scatter to measure: its σ is the floor
    1e-6·std(F) + 1e-9 N = 1e-9 N (chainid/gap/harmonic/prepare.py), never 0 (every dB over the noise divides by it)."""
    from chainid.gap.harmonic.prepare import prepare_test
    from chainid.records.record import Record

    t = np.arange(8 * 256) / 256 * np.pi  # ω = 2 rad/s, 8 periods of 256 samples
    x = 2.0 + 0.2 * np.sin(2.0 * t)
    d = prepare_test(Record("flat", t, x, np.full(t.size, 5000.0)))
    assert d.sigma == 1e-9


def test_bin_noise_is_the_pooled_scatter_after_a_per_bin_linear_fit():
    """σ = sqrt(Σ RSS_b / Σ(n_b − 3)) with RSS_b of a least-squares fit of F on (1, ψ, t) within each bin
    (computed here by numpy.linalg.lstsq per bin; the code uses running moments); bins with fewer than 5
    samples do not count; with none left, σ is the plain standard deviation of F."""
    from chainid.gap.harmonic.cyclenoise import bin_noise as _bin_noise

    rng = np.random.default_rng(5)
    B, n = 4, 200
    t = np.sort(rng.uniform(0, 10, n))
    psi = rng.uniform(0, 2 * np.pi, n)
    bins = np.minimum((psi / (2 * np.pi) * B).astype(int), B - 1)
    F = 3.0 * psi - 0.5 * t + rng.normal(0, 2.0, n)
    keep = np.ones(n, bool)
    keep[np.flatnonzero(bins == 3)[4:]] = False  # bin 3 keeps 4 samples: left out of the pool
    t, psi, bins, F = t[keep], psi[keep], bins[keep], F[keep]
    rss = dof = 0.0
    for b in range(B):
        m = bins == b
        if m.sum() < 5:
            continue
        X = np.column_stack([np.ones(m.sum()), psi[m], t[m]])
        r = F[m] - X @ np.linalg.lstsq(X, F[m], rcond=None)[0]
        rss += float(r @ r)
        dof += m.sum() - 3
    assert _bin_noise(t, F, psi, bins, B) == pytest.approx(math.sqrt(rss / dof), rel=1e-9)
    few = np.arange(8) % 4  # 2 samples per bin
    y = np.arange(8.0) ** 2
    assert _bin_noise(np.arange(8.0), y, np.linspace(0, 6, 8), few, 4) == pytest.approx(float(np.std(y)), rel=1e-12)
