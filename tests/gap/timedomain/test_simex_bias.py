"""The displacement-noise bias by SIMEX (chainid.gap.timedomain.simex) against the attenuation of a regression
slope in closed form, and on Coulomb friction diagnosed with noise in x."""

from __future__ import annotations

import warnings
from types import SimpleNamespace

import numpy as np
import pytest

import recovery_cases as rc
from chainid.gap.core.resample import widen
from chainid.gap.timedomain import simex
from chainid.records.record import Record

FS, N, BETA = 200.0, 40000, 5.0


def _smooth(seed: int) -> np.ndarray:
    """A band-limited motion [mm]: 12 sines of random phase at 0.3–2 Hz, unit RMS."""
    rng = np.random.default_rng(seed)
    t = np.arange(N) / FS
    x = sum(np.sin(2 * np.pi * f * t + rng.uniform(0, 2 * np.pi)) for f in rng.uniform(0.3, 2.0, 12))
    return x / np.std(x)


def _line_problem(records: list[Record]) -> SimpleNamespace:
    """F = b·x fitted by least squares on the measured x (no intercept): a regressor with noise."""
    x = np.concatenate([r.x for r in records])
    F = np.concatenate([r.F for r in records])
    b = float(x @ F / (x @ x))
    return SimpleNamespace(fit=lambda names, start, polish_only: SimpleNamespace(params={"b": b}))


def test_record_sigma_x_is_the_white_noise_added_to_a_smooth_motion():
    xi = _smooth(1)
    u = np.random.default_rng(2).normal(0.0, 0.02, N)
    t = np.arange(N) / FS
    # the robust scale of what the low-pass removes, over the share of white noise it removes: 0.02 mm
    assert simex.record_sigma_x(t, xi + u) == pytest.approx(0.02, rel=0.03)


def test_shift_of_a_regression_slope_is_its_closed_form_attenuation():
    # x = ξ + u, var(u) = σ²: the least-squares slope tends to β·S/(S + σ²), S = mean(ξ²).  SIMEX adds σ² more:
    # the shift θ(1) − θ(0) is β·S/(S + 2σ²) − β·S/(S + σ²) (the noise here is 5 % of the motion's RMS; at 10 %
    # the noise floor hides the band's top and no σ_x is measured)
    t = np.arange(N) / FS
    recs, S, sig = [], [], 0.05
    for i in range(3):
        xi = _smooth(10 + i)
        u = np.random.default_rng(20 + i).normal(0.0, sig, N)
        recs.append(Record(f"r{i}", t, xi + u, BETA * xi))
        S.append(np.mean(xi**2))
    S = float(np.mean(S))
    closed = BETA * S / (S + 2 * sig**2) - BETA * S / (S + sig**2)
    start = SimpleNamespace(names=["b"], params={"b": _line_problem(recs).fit(["b"], None, True).params["b"]})
    shifts, why = simex.simex_shifts(recs, [start], _line_problem, seed=3)
    assert why is None
    # the added noise's own scatter of the slope, over 2 draws of 120 000 samples: ≈ 4 % of the shift (1 sd)
    assert shifts[0]["b"] == pytest.approx(closed, rel=0.12)
    assert closed == pytest.approx(-0.0124, abs=0.0005)  # the size of what is checked: 0.25 % of β


def test_records_without_displacement_noise_are_skipped_and_say_so():
    # white x: its band reaches the Nyquist frequency, so it is not smoothed and no σ_x can be measured
    rng = np.random.default_rng(4)
    t = np.arange(4000) / FS
    recs = [Record("r0", t, rng.normal(0.0, 1.0, t.size), rng.normal(0.0, 1.0, t.size))]
    cand = SimpleNamespace(names=["b"], params={"b": 1.0})
    shifts, why = simex.simex_shifts(recs, [cand], _line_problem)
    assert shifts == [{}]
    assert "no measurable displacement noise" in why


def test_noisier_adds_noise_of_each_records_own_sigma_to_x_only():
    t = np.arange(N) / FS
    recs = [Record("a", t, np.zeros(N), np.ones(N)), Record("b", t, np.zeros(N), np.ones(N))]
    out = simex.noisier(recs, [0.1, 0.5], np.random.default_rng(5), lam=4.0)
    assert np.std(out[0].x) == pytest.approx(0.2, rel=0.02) and np.std(out[1].x) == pytest.approx(1.0, rel=0.02)
    assert np.array_equal(out[0].F, recs[0].F) and np.array_equal(out[0].t, t)


@pytest.mark.parametrize("seed", [1, 2])
def test_friction_interval_under_displacement_noise_takes_in_the_truth_its_resampling_misses(seed):
    # Coulomb friction F_c = 3 N on the linear device with 5 % displacement noise: the noise biases F_c high
    # (4.1 and 4.5 N), every resample alike, so the resampling's interval misses 3 N; adding the noise once more
    # moves F_c up again, and the interval widened by that shift takes 3 N in
    from chainid.gap.diagnose import diagnose

    recs = rc.linear_random(lambda mo, t: 3.0 * np.sign(mo(t)[1]), n=2000, band=(0.5, 4.0), seed=seed, sigma_x=0.05)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = diagnose(recs, ["r4"], None, quiet=True, effects=["friction"], max_combo=1, resamples=20, seed=seed)
    row = res["stability"]["steps"][-1]
    lo_p, hi_p = row["params_ci90_percentile"]["friction.F_c"]
    lo, hi = res["steps"][-1]["params_ci90"]["friction.F_c"]
    assert lo_p > 3.0 and row["bias_x"]["friction.F_c"] > 0
    assert lo <= 3.0 <= hi
    # at 5 % noise the band's top of some records is hidden and their σ_x not measured: the result says which
    none = [r.test for r in recs if simex.record_sigma_x(r.t, r.x) == 0.0]
    assert res["stability"]["displacement_noise"]["skipped"] == (
        f"no measurable displacement noise in {', '.join(none)}: no noise added there" if none else None)


def test_widen_by_the_noise_bias_keeps_it_apart_from_the_sampling_bias():
    stab = {"steps": [{"params_ci90": {"friction.F_c": [4.0, 5.0]}}]}
    widen(stab, [{"friction.F_c": 0.0}], "bias_dt")
    widen(stab, [{"friction.F_c": 1.5}], "bias_x")
    assert stab["steps"][0]["params_ci90"]["friction.F_c"] == pytest.approx([2.5, 5.0])
    assert stab["steps"][0]["bias_x"] == {"friction.F_c": 1.5}


def test_a_widened_edge_stops_at_the_parameters_bound():
    # x_s >= 0: a bias of +0.2 would take [0.01, 0.05] down to −0.19; the edge stops at the bound 0
    stab = {"steps": [{"params_ci90": {"friction.x_s": [0.01, 0.05], "friction.F_c": [4.0, 5.0]}}]}
    widen(stab, [{"friction.x_s": 0.2, "friction.F_c": 1.5}], "bias_x",
          [{"friction.x_s": (0.0, 0.5), "friction.F_c": (0.0, 1e6)}])
    assert stab["steps"][0]["params_ci90"] == {"friction.x_s": [0.0, 0.05], "friction.F_c": [2.5, 5.0]}


def _noisy_record(test: str, seed: int, n: int = 8000) -> Record:
    """A smooth unit-RMS motion with 0.02 mm of white displacement noise (σ_x measurable)."""
    t = np.arange(n) / FS
    x = _smooth(seed)[:n] + np.random.default_rng(seed + 100).normal(0.0, 0.02, n)
    return Record(test, t, x, BETA * x)


def test_the_added_noise_is_the_seeded_draw_of_each_records_own_sigma():
    """The first draw's added noise is exactly numpy's default_rng(seed).normal(0, √λ·σ_x, n) per record in
    order (λ = 1, σ_x of each record by :func:`simex.record_sigma_x`): the shifts are reproducible from the seed."""
    recs = [_noisy_record("a", 1), _noisy_record("b", 2)]
    sig = [simex.record_sigma_x(r.t, r.x) for r in recs]
    assert all(s > 0.0 for s in sig)
    seen = []

    def build(rs):
        seen.append([r.x for r in rs])
        return SimpleNamespace(fit=lambda names, start, polish_only: SimpleNamespace(params={}))

    simex.simex_shifts(recs, [SimpleNamespace(names=[], params={})], build, seed=7)
    rng = np.random.default_rng(7)
    assert len(seen) == simex.DRAWS == 2 and simex.LAMBDA == 1.0
    for r, s, x in zip(recs, sig, seen[0]):
        np.testing.assert_allclose(x - r.x, rng.normal(0.0, s, r.x.size), rtol=0, atol=1e-12)


def test_the_shift_is_the_mean_over_draws_of_parameters_refitted_in_every_draw():
    """Draw 1 refits b = 1.5 and c = 2, draw 2 only b = 2.5; the step has b = c = 1: the shift of b is
    mean(0.5, 1.5) = 1.0, c is refitted in one draw of 2 and has none."""
    fits = iter([{"p.b": 1.5, "p.c": 2.0}, {"p.b": 2.5}])

    def build(rs):
        params = next(fits)
        return SimpleNamespace(fit=lambda names, start, polish_only: SimpleNamespace(params=params))

    step = SimpleNamespace(names=["p"], params={"p.b": 1.0, "p.c": 1.0})
    shifts, why = simex.simex_shifts([_noisy_record("a", 3)], [step], build)
    assert why is None
    assert shifts == [{"p.b": pytest.approx(1.0, rel=1e-12)}]


def test_a_record_without_displacement_noise_gets_none_and_is_named():
    """One record with σ_x (smooth motion plus noise) and one of white x (not smoothed: σ_x = 0): the second keeps
    its x in every draw, and the reason names it."""
    t = np.arange(8000) / FS
    white = Record("w", t, np.random.default_rng(9).normal(0.0, 1.0, t.size), np.zeros(t.size))
    assert simex.record_sigma_x(white.t, white.x) == 0.0
    seen = []

    def build(rs):
        seen.append(rs[1].x)
        return SimpleNamespace(fit=lambda names, start, polish_only: SimpleNamespace(params={}))

    shifts, why = simex.simex_shifts([_noisy_record("a", 4), white], [SimpleNamespace(names=[], params={})], build)
    assert why == "no measurable displacement noise in w: no noise added there"
    assert all(np.array_equal(x, white.x) for x in seen) and len(seen) == 2


@pytest.mark.parametrize("exc", [ValueError("bad"), ZeroDivisionError("zero"), FloatingPointError("fp"),
                                 RuntimeError("no convergence"), np.linalg.LinAlgError("singular")])
def test_a_failed_refit_with_added_noise_gives_no_shift_and_says_why(exc):
    """A refit that raises a value, arithmetic, runtime or linear-algebra error: no shift for any step, and the
    reason quotes it."""
    def build(rs):
        raise exc

    steps = [SimpleNamespace(names=[], params={}), SimpleNamespace(names=["p"], params={"p.b": 1.0})]
    shifts, why = simex.simex_shifts([_noisy_record("a", 5)], steps, build)
    assert shifts == [{}, {}]
    assert why == f"the records with added displacement noise could not be refitted ({exc})"
