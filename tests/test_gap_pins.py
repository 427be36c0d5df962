"""Pins of the gap layer's small rules to hand-computed numbers (issue 20 §5): each test fails under the
single-point bug named in its docstring (checked by mutating the code by hand once).

Units: N, s, mm.
"""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from chainid.gap.core import stationarity
from chainid.gap.harmonic.route import jackknife as _jackknife
from chainid.gap.harmonic.problem import Candidate, Problem
from chainid.gap.core.selection import TIE, pick as _pick
from chainid.model.operators import coulomb_sign
from stand_ins import localise_viscous_excess


# ---------------------------------------------------------------- stationarity
def _cycles(n=12):
    t = np.arange(n, dtype=float)  # one cycle per second
    xm = 0.02 * t + 0.05 * np.sin(1.3 * t)  # the shaker's mean wanders (not collinear with t)
    xa = 2.0 + 0.01 * t + 0.04 * np.cos(0.7 * t)  # and so does its amplitude
    return t, xm, xa


def test_trend_follows_the_shakers_mean_and_amplitude_not_time():
    """A force that only follows the shaker's mean (F = 100 + 30·x_m) and amplitude (a = 50·x_a) has no trend.
    Bugs caught: the covariate column dropped, or x_m / x_a swapped between the mean and the harmonics."""
    t, xm, xa = _cycles()
    cy = {"t": t, "mean": 100.0 + 30.0 * xm, "a": 50.0 * xa, "b": 3.0 + 0.0 * t, "xm": xm, "xa": xa,
          "n": np.full(t.size, 64.0)}
    res = stationarity.check([SimpleNamespace(test="T1", sigma=0.01, cycles=cy)])
    row = res["tests"][0]
    for q in ("mean", "a", "b"):
        assert abs(row[q]["slope_N_per_s"]) < 1e-9, q
    assert res["stationary"] is True
    # the same force against time alone has the slope of 30·x_m's line in t: clearly a trend without the covariate
    sl, se, _ = stationarity.trend(t, cy["mean"])
    assert abs(sl) > 0.3 and abs(sl) / se > stationarity.Z_TREND


def test_trend_noise_floor_closed_form():
    """An exact line has zero scatter: its standard error is the floor σ_c/sqrt(Σ(t−t̄)²) (closed form), its change
    |slope|·span.  Bugs caught: the floor ignored (se → 1e-300), floor not squared, span from the wrong end."""
    t = np.arange(10, dtype=float)  # Σ(t − 4.5)² = 82.5
    sl, se, chg = stationarity.trend(t, 0.1 * t, sd_floor=0.5)
    assert sl == pytest.approx(0.1, rel=1e-12)
    assert se == pytest.approx(0.5 / math.sqrt(82.5), rel=1e-9)
    assert chg == pytest.approx(0.9, rel=1e-12)


def test_check_floor_per_quantity():
    """The per-cycle floor is σ·sqrt(1/n) for the mean and σ·sqrt(2/n) for a harmonic amplitude (white noise), so
    exact lines of slope s give z = s·sqrt(82.5)/floor.  Bug caught: 1 and 2 swapped or the same for both."""
    t = np.arange(10, dtype=float)
    x0 = np.zeros(10)
    cy = {"t": t, "mean": 0.2 * t, "a": 0.2 * t, "b": 0.0 * t, "xm": x0, "xa": x0, "n": np.full(10, 50.0)}
    row = stationarity.check([SimpleNamespace(test="T", sigma=1.0, cycles=cy)])["tests"][0]
    assert row["mean"]["z"] == pytest.approx(0.2 * math.sqrt(82.5) / math.sqrt(1 / 50), rel=1e-9)
    assert row["a"]["z"] == pytest.approx(0.2 * math.sqrt(82.5) / math.sqrt(2 / 50), rel=1e-9)


def test_too_few_cycles_not_checked():
    t = np.arange(stationarity.MIN_CYCLES - 1, dtype=float)
    cy = {"t": t, "mean": t, "a": t, "b": t, "xm": t, "xa": t, "n": np.ones_like(t)}
    assert stationarity.check([SimpleNamespace(test="T", sigma=1.0, cycles=cy)])["stationary"] is None
    t4 = np.arange(stationarity.MIN_CYCLES, dtype=float)
    cy4 = {k: np.arange(stationarity.MIN_CYCLES, dtype=float) for k in ("t", "mean", "a", "b", "xm", "xa")}
    assert stationarity.check([SimpleNamespace(test="T", sigma=1.0, cycles=cy4)])["stationary"] is not None
    assert t4.size == stationarity.MIN_CYCLES


# ---------------------------------------------------------------- jack-knife
def test_jackknife_of_a_mean_is_the_standard_error():
    """Leave-one-out refits of a mean: the jack-knife SD sqrt((n−1)/n·Σ(θ_i − θ̄)²) equals s/sqrt(n) exactly
    (s the sample SD, ddof 1).  Bugs caught: factor (n−1)/n replaced by 1/n, n/(n−1) or dropped."""
    vals = np.array([1.0, 2.0, 4.0, 8.0, 16.0])
    tr = [SimpleNamespace(v=v) for v in vals]

    def fit(names, train_only, start, polish_only):
        return SimpleNamespace(params={"p": float(np.mean([d.v for d in train_only])), "law.0": 99.0})

    prob = SimpleNamespace(train=tr, fit=fit)
    cand = Candidate(name="x", params={"p": 0.0, "law.0": 1.0}, n_params=1)
    sd = _jackknife(prob, cand)
    assert set(sd) == {"p"}  # the damping-law coefficients are not jack-knifed
    assert sd["p"] == pytest.approx(np.std(vals, ddof=1) / math.sqrt(vals.size), rel=1e-12)


# ---------------------------------------------------------------- dB over noise, BIC
def _d(test, nbins, sigma, count):
    return SimpleNamespace(test=test, counts=np.full(nbins, float(count)), sigma=sigma)


def test_noise_db_uses_the_requested_split():
    """Hold: residual 1 N in 2 bins of 2 samples at σ = 2 N: r² = 1, floor σ²/n = 2 → −3.0103 dB; train: residual
    3 N, σ = 1, 4 samples: 9 / 0.25 → +15.563 dB.  Bug caught: the split ignored / swapped."""
    hold, train = _d("H", 2, 2.0, 2), _d("T", 3, 1.0, 4)
    fake = SimpleNamespace(hold=[hold], train=[train])
    fake.n_cells = lambda split: Problem.n_cells(fake, split)
    ev = {"res": {"H": np.ones(2), "T": np.full(3, 3.0)}}
    assert Problem.noise_db(fake, ev, "hold") == pytest.approx((1.0, 2.0, 10 * math.log10(0.5)), rel=1e-12)
    assert Problem.noise_db(fake, ev, "train") == pytest.approx((9.0, 0.25, 10 * math.log10(36.0)), rel=1e-12)


def test_diagnose_baseline_db_is_on_the_holdout(monkeypatch):
    """The baseline's dB over noise (``baseline.db_over_noise``) is that of the held-out tests, whose residuals here
    are made larger than the training tests' (a 60 N offset only in the held-out test's force), so the two splits
    give clearly different dB.  Bug caught: computed on the training tests."""
    from chainid.gap.benchmark.grid import grid3x3_plan
    from chainid.gap.diagnose import diagnose
    from chainid.model.base import ChainModel
    from chainid.model.laws import PolynomialLaw
    from chainid.records.simulate import simulate

    calls = []
    orig = Problem.noise_db

    def spy(self, ev, split="hold"):
        out = orig(self, ev, split)
        calls.append((split, out[2]))
        return out

    monkeypatch.setattr(Problem, "noise_db", spy)
    recs = simulate(grid3x3_plan(prefix=""), ChainModel(), PolynomialLaw([0.5, 1.0, 100.0, 20.0, 50.0]),
                    n_cycles=6, samples_per_cycle=64, noise_F=20.0, seed=2)
    recs = [r if r.test != "7" else type(r)(r.test, r.t, r.x, r.F + 60.0) for r in recs]
    res = diagnose(recs, ["7"], ChainModel(), uncertainty=False, max_combo=1, quiet=True)
    db = res["baseline"]["db_over_noise"]
    hold = [v for s, v in calls if s == "hold"]
    train = [v for s, v in calls if s == "train"]
    assert db == hold[0]  # the first dB computed for the baseline, on the held-out test
    assert min(abs(db - v) for v in train) > 3.0  # every training-split dB is far from it


def test_bic_sample_size_is_the_training_bins():
    """BIC = χ² + k·ln(n_b) with n_b the training bins (64 + 64 = 128; the held-out 32 not counted) and k the
    effect's plus the law's parameters.  Bugs caught: n_b over hold or all bins, the law's parameters left out."""
    train = [_d("A", 64, 1.0, 4), _d("B", 64, 1.0, 4)]
    hold = [_d("H", 32, 1.0, 4)]
    ev = {"law_params": [0.1, 0.2], "nrmse_train": 0.1, "nrmse_loto": 0.2, "nrmse_holdout": 0.3, "chi2": 50.0,
          "loto_num": {}, "per_test": {}, "res": {"A": np.zeros(64), "B": np.zeros(64), "H": np.zeros(32)}}
    fake = SimpleNamespace(train=train, hold=hold, laws_for=lambda names: ["viscous"],
                           evaluate=lambda names, params, law: ev)
    fake.noise_db = lambda e, split="hold": Problem.noise_db(fake, e, split)
    fake.n_cells = lambda split="train": Problem.n_cells(fake, split)
    cand = Candidate(name="friction", params={"friction.F_c": 1.0}, n_params=1)
    out = Problem.score(fake, cand, ["friction"], 0.5)
    assert out.bic == pytest.approx(50.0 + 3 * math.log(128), rel=1e-12)


# ---------------------------------------------------------------- near-tie order
def _c(name, loto, at_bound, n_params, bic):
    c = Candidate(name=name, params={}, n_params=n_params)
    c.nrmse_loto, c.at_bound, c.bic = loto, list(at_bound), bic
    return c


def test_near_tie_order_pinned_then_count_then_bic():
    """Within TIE of the best LOTO: fewer pinned parameters first, then fewer parameters, then BIC.
    Bugs caught: the key's order changed, the tie band ignored or widened to everything."""
    a = _c("a", 1.0, ["a.p"], 1, 0.0)  # best LOTO but pinned at a bound
    b = _c("b", 1.0 + 0.5 * TIE, [], 3, 100.0)  # within the tie band, nothing pinned
    far = _c("far", 1.0 + 3 * TIE, [], 1, -1e9)  # outside the band: never chosen
    chosen, ties = _pick([a, b, far])
    assert chosen is b and ties == [a]
    d = _c("d", 1.0, [], 2, 50.0)
    e = _c("e", 1.0 + 0.9 * TIE, [], 1, 100.0)
    assert _pick([d, e])[0] is e  # fewer parameters beats a better BIC
    f = _c("f", 1.0, [], 1, 10.0)
    g = _c("g", 1.0 + 0.9 * TIE, [], 1, 5.0)
    assert _pick([f, g])[0] is g  # then BIC
    h = _c("h", 1.0, [], 2, 50.0)
    i = _c("i", 1.0 + 1.01 * TIE, [], 1, 1.0)
    assert _pick([h, i])[0] is h  # just outside the band: the LOTO winner


# ---------------------------------------------------------------- Coulomb sign at a turning point
def test_coulomb_sign_turning_point_rule():
    """A sample between neighbours of opposite sign and slower than half of the slower neighbour is the turning
    point: sign 0.  Hand: [2, 1, 0.4, −1, −2] → [1, 1, 0, −1, −1]; 0.5 is not < 0.5·1 → stays 1.
    Bugs caught: < made <=, 0.5 changed, min made max, neighbours' sign test dropped, periodic wrap ignored."""
    assert coulomb_sign([2, 1, 0.4, -1, -2], periodic=False).tolist() == [1, 1, 0, -1, -1]
    assert coulomb_sign([2, 1, 0.5, -1, -2], periodic=False).tolist() == [1, 1, 1, -1, -1]
    assert coulomb_sign([2, 3, 0.45, -0.95, -2], periodic=False).tolist() == [1, 1, 0, -1, -1]  # min(3, .95)
    assert coulomb_sign([2, 3, 0.7, -1.3, -2], periodic=False).tolist() == [1, 1, 1, -1, -1]  # 0.7 > 0.5·1.3
    assert coulomb_sign([2, 1, 0.1, 1, 2], periodic=False).tolist() == [1, 1, 1, 1, 1]  # same signs: no reversal
    assert coulomb_sign([0.1, 1, 2, -1], periodic=True).tolist() == [0, 1, 1, -1]
    assert coulomb_sign([0.1, 1, 2, -1], periodic=False).tolist() == [1, 1, 1, -1]


# ---------------------------------------------------------------- within-bin noise, local spectral peak
def test_bin_noise_removes_a_local_linear_trend_in_phase_and_time():
    """F exactly linear in phase and time inside every bin (a slope and a drift): the pooled scatter is 0; pure
    white noise of SD 2 N gives 2 N within a few %.  Bug caught: the 2×2 normal-equation solution garbled."""
    from chainid.gap.harmonic.prepare import _bin_noise

    rng = np.random.default_rng(5)
    B = 16
    t = np.sort(rng.uniform(0.0, 10.0, 4000))
    psi = np.mod(2 * math.pi * 1.3 * t + 0.1 * rng.standard_normal(t.size), 2 * math.pi)
    bins = np.minimum((psi / (2 * math.pi) * B).astype(np.int64), B - 1)
    F = 100.0 + 7.0 * psi + 3.0 * t
    assert _bin_noise(t, F, psi, bins, B) < 1e-5  # N: round-off of the moment sums (F ~ 140 N)
    noise = 2.0 * rng.standard_normal(t.size)
    assert _bin_noise(t, F + noise, psi, bins, B) == pytest.approx(2.0, rel=0.05)


def test_local_peak_over_the_octave_median():
    """A flat power spectrum with one line 50× higher at 40 Hz: the peak is found at 40 Hz with height 50 (the
    median within ± one octave is the flat level).  Bug caught: the octave window's upper edge garbled."""
    from chainid.gap.timedomain.where import OCT, _local_peak

    f = np.arange(1.0, 201.0)
    P = np.ones_like(f)
    P[39] = 50.0
    fk, h = _local_peak(f, P, 5.0)
    assert fk == 40.0 and h == pytest.approx(50.0, rel=1e-12)
    assert OCT == 2.0
    P2 = np.ones_like(f)
    P2[f >= 75] = 100.0  # a broad raised band: 66 of the 106 bins of 70 Hz's octave 35..140 Hz
    P2[69] = 60.0  # a line at 70 Hz below the band's level: no narrow peak (ratio 0.6)
    fk2, h2 = _local_peak(f, P2, 5.0)
    assert h2 == pytest.approx(1.0, rel=1e-12)  # the flat parts' ratio 1 is the best anywhere


def test_at_noise_floor_chi2_band():
    """Within 5 standard deviations of a χ² mean: ratio < 1 + 5·sqrt(2/n) = 1.5 for n = 200 bins (systematic part
    well above half σ, so only the ratio decides).  Bug caught: 2/n made an integer division (threshold 1)."""
    from chainid.gap.core.selection import at_noise_floor

    assert at_noise_floor(1.4, 1.0, 0.1, 200) is True
    assert at_noise_floor(1.6, 1.0, 0.1, 200) is False
    assert at_noise_floor(4.0, 1.0, 4.0, 200) is True  # excess sqrt(3) = 1.73 < 0.5·4


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


# ---------------------------------------------------------------- where the baseline misses
def test_localise_energy_error_per_cycle_is_the_loop_integral():
    """r = C cos ψ over x = x0 + A sin ψ: the residual's work per cycle ∮ r dx = ∫ C cos ψ · A cos ψ dψ = π·A·C
    (C = 30 N, A = 0.2/0.3/0.4 mm: 18.85/28.27/37.70 N·mm).  Bugs caught: a factor lost (the code had π·A·mean,
    half the integral), A dropped."""
    data, found = localise_viscous_excess()
    per_test = {f["test"]: f["energy_error_Nmm"] for f in found if f.get("kind") == "test"}
    for d in data:
        assert per_test[d.test] == pytest.approx(math.pi * d.A * 30.0, rel=1e-9)


def test_localise_multi_valued_residual_by_hand():
    """At ψ and π − ψ x is the same and ẋ opposite: r − r(mirror) = 2C cos ψ, RMS/2 = C/√2 = 21.21 N.
    Bug caught: the difference not squared."""
    _, found = localise_viscous_excess()
    surf = [f for f in found if f.get("kind") == "surface"]
    assert len(surf) == 1 and surf[0]["multi_valued_N"] == pytest.approx(30.0 / math.sqrt(2), rel=1e-9)


def test_delay_signature_reads_a_pure_lag():
    """The data are the model's force delayed by τ = 2 ms: harmonic k turns by −kωτ, so δ_k/k against ω has slope
    −τ through the origin: τ read back exactly (harmonics 2 and 3, ω = 10, 20, 30 rad/s).
    Bug caught: the harmonic's phase grid k·ψ garbled."""
    from chainid.gap.harmonic.where import delay_signature

    B, tau = 64, 0.002
    psi = (np.arange(B) + 0.5) * 2 * math.pi / B

    def force(shift):
        return 500 * np.sin(psi - shift) + 100 * np.sin(2 * (psi - shift)) + 50 * np.cos(3 * (psi - shift))

    data, model = [], {}
    for i, w in enumerate((10.0, 20.0, 30.0)):
        data.append(SimpleNamespace(test=f"T{i}", omega=w, sigma=0.1, counts=np.full(B, 10.0),
                                    Fbar=force(w * tau)))
        model[f"T{i}"] = force(0.0)
    sig = delay_signature(data, model)
    assert sig["n_points"] == 6
    assert sig["tau_harmonics_s"] == pytest.approx(tau, rel=1e-9)
    assert sig["phase1_slope_s"] == pytest.approx(-tau, rel=1e-9)


def test_benchmark_summary_counts_a_case_at_the_snr_threshold():
    """Single-effect cases with residual ≥ SNR_MIN × noise are scored: one at exactly SNR_MIN (right), one
    below it (wrong, not scored), one above (wrong): rate 1/2 = "50.0 %" in the text.
    Bugs caught: >= made != or >, the percentage garbled."""
    from chainid.gap.benchmark.report import SNR_MIN, format_summary, summarise

    def row(snr, verdict):
        return {"family": "single", "truth": ["friction"], "verdict": verdict, "snr": snr, "shrinkage": 0.5,
                "seconds": 1.0, "chain": "c", "plan": "p", "noise": 1.0, "seed": 0, "levels": {}}

    rows = [row(SNR_MIN, "friction"), row(0.5 * SNR_MIN, "hysteresis"), row(2 * SNR_MIN, "backlash")]
    s = summarise(rows)
    assert s["single_n"] == 2 and s["single_right_rate"] == 0.5
    assert "single effects, right verdict (residual >= 3x noise): 50.0 % of 2" in format_summary(s)
