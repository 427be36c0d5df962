"""The force noise of a steady harmonic test (chainid.gap.harmonic.cyclenoise): the cycles' scatter about their
synchronous average, not the force's shape within a bin.  Units s, mm, N, rad."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.gap.harmonic.cyclenoise import bin_noise, cycle_noise

Q = 16


def _phase(t: np.ndarray, omega: float, theta: float, B: int) -> tuple[np.ndarray, np.ndarray]:
    psi = np.mod(omega * t + theta, 2 * math.pi)
    return psi, np.minimum((psi / (2 * math.pi) * B).astype(np.int64), B - 1)


def _friction(psi: np.ndarray, F_c: float = 300.0, delta: float = 0.02) -> np.ndarray:
    """Friction with a presliding travel on x = 5 + 2 sin ψ [N]: F_c·sgn(ẋ)·(1 − 2·exp(−s/δ)), s [mm] the travel
    since the last reversal, δ = 0.02 mm; it turns over about 0.3 rad after each reversal, three bins of 64."""
    s = np.where(np.cos(psi) >= 0, 2.0 * (np.sin(psi) + 1.0), 2.0 * (1.0 - np.sin(psi)))
    return F_c * np.sign(np.cos(psi)) * (1.0 - 2.0 * np.exp(-s / delta))


def _coulomb_test(sigma: float, seed: int, spc: int = 256, cycles: int = 8) -> tuple[np.ndarray, ...]:
    """x = 5 + 2 sin ψ at 1 Hz sampled ``spc`` times a cycle; F = 400·x + friction (:func:`_friction`) + white noise
    of SD σ [N]."""
    omega, theta = 2 * math.pi, math.pi / spc  # samples half a step off the reversals
    t = np.arange(cycles * spc) / spc
    psi, bins = _phase(t, omega, theta, 64)
    noise = sigma * np.random.default_rng(seed).standard_normal(t.size)
    F = 400.0 * (5.0 + 2.0 * np.sin(psi)) + _friction(psi) + noise
    return t, F, psi, bins, noise


def test_cycle_noise_reads_the_added_noise_under_a_coulomb_step():
    """A 600 N turn-over of friction after each reversal and 1 N of white noise, sampled 256 times a cycle over
    8 cycles (commensurate): σ within 6 % of 1 N (about 1700 degrees of freedom: 3.5 standard errors), where the
    straight line per bin reads the turn-over's curvature as noise and gives more than twice that."""
    t, F, psi, bins, _ = _coulomb_test(1.0, seed=3)
    assert cycle_noise(t, F, psi, bins, 64, Q) == pytest.approx(1.0, rel=0.06)
    assert bin_noise(t, F, psi, bins, 64) > 2.0


def test_cycle_noise_is_a_least_squares_fit_with_cell_means_and_bin_slopes():
    """Phases not commensurate with the sampling (random times over 30 cycles), F smooth in ψ plus a drift and
    noise: σ² = Σ RSS_b / Σ (n_b − rank_b), RSS_b of numpy.linalg.lstsq on one column per occupied cell of the bin
    plus ψ and t (the code uses running moments), bins with no degree of freedom left out."""
    rng = np.random.default_rng(11)
    B = 8
    t = np.sort(rng.uniform(0.0, 30.0, 6000))
    psi, bins = _phase(t, 2 * math.pi, 0.3, B)
    F = 50.0 * np.sin(psi) ** 3 + 0.8 * t + rng.normal(0.0, 0.5, t.size)
    cell = np.minimum((psi / (2 * math.pi) * B * Q).astype(np.int64), B * Q - 1)
    ref = _lstsq_sigma(t, F, bins, [*(lambda m, c=c: (cell[m] == c).astype(float) for c in np.unique(cell)),
                                    lambda m: psi[m], lambda m: t[m]])
    assert cycle_noise(t, F, psi, bins, B, Q) == pytest.approx(ref, rel=1e-9)


def test_cycle_noise_is_blind_to_a_linear_drift_over_the_record():
    """F + 0.05 N/s · t (a slow drift over the 8 cycles) leaves σ unchanged to round-off: the drift lies in the
    time slope each bin removes."""
    t, F, psi, bins, _ = _coulomb_test(1.0, seed=4)
    assert cycle_noise(t, F + 0.05 * t, psi, bins, 64, Q) == pytest.approx(cycle_noise(t, F, psi, bins, 64, Q),
                                                                             rel=1e-9)


def _lstsq_sigma(t: np.ndarray, F: np.ndarray, group: np.ndarray, columns) -> float:
    """σ by numpy.linalg.lstsq per group on the given columns (a list of per-sample arrays or functions of the
    group's mask), the degrees of freedom n − rank with numpy's own rank."""
    rss = dof = 0.0
    for g in np.unique(group):
        m = group == g
        X = np.column_stack([c(m) for c in columns])
        rank = np.linalg.matrix_rank(X)
        if m.sum() - rank <= 0:
            continue
        r = F[m] - X @ np.linalg.lstsq(X, F[m], rcond=None)[0]
        rss, dof = rss + float(r @ r), dof + m.sum() - rank
    return math.sqrt(rss / dof)


def test_one_cycle_falls_back_to_the_bin_scatter_which_reads_a_straight_line_in_time():
    """One cycle of 512 samples (8 a bin): nothing repeats from cycle to cycle, and σ is :func:`bin_noise`'s, whose
    phase is time itself within a bin: σ = numpy.linalg.lstsq's on (1, t) per bin to 10⁻⁹, the phase's round-off
    left over spending neither a slope nor a degree of freedom."""
    t, F, psi, bins, _ = _coulomb_test(1.0, seed=5, spc=512, cycles=1)
    F = F - _friction(psi) - 400.0 * (5.0 + 2.0 * np.sin(psi)) + 3.0 * t  # noise and a drift: a line in t per bin
    ref = _lstsq_sigma(t, F, bins, [lambda m: np.ones(m.sum()), lambda m: t[m]])
    assert cycle_noise(t, F, psi, bins, 64, Q) == bin_noise(t, F, psi, bins, 64)
    assert bin_noise(t, F, psi, bins, 64) == pytest.approx(ref, rel=1e-9)


def test_a_phase_that_drifts_with_time_alone_spends_nothing_on_its_round_off():
    """Commensurate sampling read with ω off by 10⁻⁶ (ψ moves with t alone inside a cell): σ = numpy.linalg.lstsq's
    on one column per cell and t per bin to 10⁻⁹, the phase column adding no rank there either."""
    t, F, psi, bins, _ = _coulomb_test(1.0, seed=7)
    psi, bins = _phase(t, 2 * math.pi * (1 + 1e-6), math.pi / 256, 64)
    cell = np.minimum((psi / (2 * math.pi) * 64 * Q).astype(np.int64), 64 * Q - 1)
    cells = np.unique(cell)
    ref = _lstsq_sigma(t, F, bins, [*(lambda m, c=c: (cell[m] == c).astype(float) for c in cells),
                                    lambda m: t[m]])
    assert cycle_noise(t, F, psi, bins, 64, Q) == pytest.approx(ref, rel=1e-9)


def test_prepare_test_sigma_is_the_added_noise_under_friction():
    """A record through :func:`prepare_test` (the phase estimated from x): x = 5 + 2 sin(2π t + π/256), F = 400·x +
    friction (:func:`_friction`) + noise of SD 2 N, 256 samples a cycle over 10 cycles; σ = 2 N within 5 % (about
    2200 degrees of freedom, so one standard error of σ is 1.5 %)."""
    from chainid.gap.harmonic.prepare import prepare_test
    from chainid.records.record import Record

    t = np.arange(10 * 256) / 256.0
    psi = 2 * math.pi * t + math.pi / 256
    x = 5.0 + 2.0 * np.sin(psi)
    F = 400.0 * x + _friction(psi) + 2.0 * np.random.default_rng(6).standard_normal(t.size)
    assert prepare_test(Record("C", t, x, F)).sigma == pytest.approx(2.0, rel=0.05)
