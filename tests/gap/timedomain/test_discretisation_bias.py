"""The discretisation bias of the time route (:mod:`chainid.gap.timedomain.discretisation`) and the widening of the
resampled intervals by it (:func:`chainid.gap.core.resample.widen`).

References:

* Richardson's extrapolation on an estimate biased as θ(Δt) = θ₀ + b·Δt² (a closed form): the shift is b·Δt²
  exactly, and θ − shift = θ₀.
* Coulomb friction F_c = 2 N on the linear device, nearly noise-free records (σ_x = 1e-7 mm, σ_F = 1e-4 N) sampled
  at 200 Hz, band 0.5–4 Hz: the force sampled at instants is fitted at instants, so no sampling bias is left
  (measured: |error| <= 0.0004 % at Δt, 0.0018 % at 2Δt, over four realisations; 0.08–0.12 % at Δt while samples
  within a third of a step of a reversal were given the stick force 0), and the extrapolation invents none.
"""
from __future__ import annotations

import warnings

import numpy as np
import pytest

import recovery_cases as rc
from chainid.gap.core.resample import widen
from chainid.gap.timedomain.discretisation import MIN_PER_PERIOD, decimated, richardson_shifts, too_coarse
from chainid.gap.timedomain.route import build_problem
from chainid.records import Record

F_C = 2.0


def _build(rs):
    return build_problem(rs, ["r4"], 0, None, None)


def test_richardson_shift_of_a_second_order_bias_is_exact():
    class P:  # an estimate θ(Δt) = 1 + 0.3·Δt² of the records' sampling interval
        def __init__(self, recs):
            self.dt = float(recs[0].t[1] - recs[0].t[0])
            self.tdata = [type("D", (), {"test": "a", "fs": 1.0 / self.dt, "f_band": 1.0})()]

        def fit(self, names, start=None, polish_only=False):
            return type("C", (), {"params": {"p.theta": 1.0 + 0.3 * self.dt**2}})()

    t = np.arange(400) * 0.01
    recs = [Record("a", t, np.sin(t), np.cos(t))]
    prob = P(recs)
    step = type("S", (), {"names": ["p"], "params": {"p.theta": 1.0 + 0.3 * 0.01**2}})()
    shifts, why = richardson_shifts(recs, prob, [step], P)
    assert why is None
    # (θ(2Δt) − θ(Δt))/(2² − 1) = 0.3·(4 − 1)·Δt²/3 = 0.3·Δt²
    assert shifts[0]["p.theta"] == pytest.approx(0.3 * 0.01**2, rel=1e-9)
    assert step.params["p.theta"] - shifts[0]["p.theta"] == pytest.approx(1.0, rel=1e-12)


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(4))
def test_coulomb_friction_sampled_at_instants_has_no_sampling_bias_to_remove(seed):
    recs = rc.linear_random(lambda mo, t: F_C * np.sign(mo(t)[1]), n=2000, band=(0.5, 4.0), seed=seed,
                            sigma_x=1e-7, sigma_F=1e-4)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        prob = _build(recs)
        cand = prob.fit(["friction"])
        shifts, why = richardson_shifts(recs, prob, [cand], _build)
    assert why is None
    assert abs(cand.params["friction.F_c"] - F_C) < 2e-5 * F_C  # 0.002 %
    assert abs(shifts[0]["friction.F_c"]) < 2e-5 * F_C
    assert abs(cand.params["friction.F_c"] - shifts[0]["friction.F_c"] - F_C) < 2e-5 * F_C


def test_decimation_keeps_every_other_sample_of_every_channel_and_the_covariates():
    t = np.arange(10) * 0.01
    r = Record("a", t, 2 * t, 3 * t, channels={"p": 4 * t}, covariates={"i_A": 1.5})
    (d,) = decimated([r])
    assert d.t.tolist() == pytest.approx([0.0, 0.02, 0.04, 0.06, 0.08])
    assert d.x.tolist() == pytest.approx([0.0, 0.04, 0.08, 0.12, 0.16])
    assert d.F.tolist() == pytest.approx([0.0, 0.06, 0.12, 0.18, 0.24])
    assert d.channels["p"].tolist() == pytest.approx([0.0, 0.08, 0.16, 0.24, 0.32])
    assert d.covariates == {"i_A": 1.5}
    assert r.t.size == 10  # the input is not changed


def test_a_record_sampled_near_its_band_is_not_decimated():
    # 200 Hz, band top 4 Hz: 25 samples per period after decimation (enough); 60 Hz: 200/2/60 = 1.67 (too few)
    class D:
        def __init__(self, test, fs, fb):
            self.test, self.fs, self.f_band = test, fs, fb

    class P:
        tdata = [D("ok", 200.0, 4.0), D("fast", 200.0, 60.0)]

    why = too_coarse(P())
    assert why is not None and "fast" in why and "1.67" in why and str(MIN_PER_PERIOD) in why
    P.tdata = [D("ok", 200.0, 4.0)]
    assert too_coarse(P()) is None


def test_widening_takes_in_the_shifted_interval_and_nothing_more():
    stab = {"steps": [{"effect": "baseline", "params_ci90": {"spring.k": [9.0, 11.0]}},
                      {"effect": "friction", "params_ci90": {"friction.F_c": [1.99, 2.01], "damping.c": [0.1, 0.3]}}]}
    shifts = [{"spring.k": 0.5}, {"friction.F_c": -0.03, "damping.c": 0.01}]
    widen(stab, shifts)
    # spring.k: [9, 11] ∪ [8.5, 10.5] = [8.5, 11]; F_c: [1.99, 2.01] ∪ [2.02, 2.04] = [1.99, 2.04];
    # c: [0.1, 0.3] ∪ [0.09, 0.29] = [0.09, 0.3]
    assert stab["steps"][0]["params_ci90"]["spring.k"] == pytest.approx([8.5, 11.0])
    assert stab["steps"][1]["params_ci90"]["friction.F_c"] == pytest.approx([1.99, 2.04])
    assert stab["steps"][1]["params_ci90"]["damping.c"] == pytest.approx([0.09, 0.3])
    assert stab["steps"][1]["bias_dt"] == {"friction.F_c": -0.03, "damping.c": 0.01}
    assert stab["steps"][1]["params_ci90_percentile"]["friction.F_c"] == [1.99, 2.01]


def test_widening_without_a_bias_leaves_the_interval():
    stab = {"steps": [{"effect": "baseline", "params_ci90": {"spring.k": [9.0, 11.0]}}]}
    widen(stab, [{}])
    assert stab["steps"][0]["params_ci90"]["spring.k"] == [9.0, 11.0]


def test_two_widenings_take_in_the_sum_of_biases_of_one_sign_and_each_of_opposite_signs():
    # same sign: [1, 2] shifted by −0.5 then by −0.25 reaches 2 + 0.75 (the biases add); the percentile interval is
    # the one before the first widening
    stab = {"steps": [{"params_ci90": {"a": [1.0, 2.0], "b": [1.0, 2.0]}}]}
    widen(stab, [{"a": -0.5, "b": -0.5}], "bias_dt")
    widen(stab, [{"a": -0.25, "b": 0.25}], "bias_x")
    row = stab["steps"][0]
    assert row["params_ci90"]["a"] == pytest.approx([1.0, 2.75])
    # opposite signs: [1, 2.5] after the first, then [0.75, 2.5]: each bias alone is taken in
    assert row["params_ci90"]["b"] == pytest.approx([0.75, 2.5])
    assert row["params_ci90_percentile"] == {"a": [1.0, 2.0], "b": [1.0, 2.0]}
    assert row["bias_dt"] == {"a": -0.5, "b": -0.5} and row["bias_x"] == {"a": -0.25, "b": 0.25}


class _Rate:
    def __init__(self, test, fs, fb):
        self.test, self.fs, self.f_band = test, fs, fb


def test_exactly_the_fewest_samples_per_period_after_decimation_is_enough():
    """160 Hz with a 10 Hz band top: 160/(2·10) = 8 = MIN_PER_PERIOD samples per period after decimating by 2, which
    is enough (the rule is "fewer than 8"); by 4 it is 4 per period, too few, and the message says by 4."""
    P = type("P", (), {"tdata": [_Rate("edge", 160.0, 10.0)]})
    assert MIN_PER_PERIOD == 8
    assert too_coarse(P()) is None
    why = too_coarse(P(), q=4)
    assert why == ("test edge: 4 samples per period of its band top (10 Hz) after decimating by 4; at least 8 are "
                   "needed")


@pytest.mark.parametrize("exc", [ValueError("too short"), np.linalg.LinAlgError("singular")])
def test_a_decimated_problem_that_cannot_be_built_gives_no_shift_and_says_why(exc):
    """The builder raising ValueError (too few samples) or LinAlgError (a singular fit) on the decimated records:
    no shift for any step, and the reason quotes the error."""
    def build(rs):
        raise exc

    P = type("P", (), {"tdata": [_Rate("a", 200.0, 4.0)]})
    steps = [type("S", (), {"names": [], "params": {}})(), type("S", (), {"names": ["p"], "params": {"p.a": 1.0}})()]
    t = np.arange(40) * 0.005
    shifts, why = richardson_shifts([Record("a", t, np.sin(t), np.cos(t))], P(), steps, build)
    assert shifts == [{}, {}]
    assert why == f"the decimated records could not be refitted ({exc})"


def test_refit_shifts_skip_parameters_not_finite_in_either_fit():
    """θ_refit − θ per parameter (2.5 − 2 = 0.5), leaving out one the refit lacks, one NaN in the refit and one
    infinite in the step; the refit starts from the step's own parameters and only polishes."""
    from chainid.gap.timedomain.discretisation import refit_shifts

    seen = []

    class P:
        def fit(self, names, start=None, polish_only=False):
            seen.append((list(names), dict(start), polish_only))
            return type("C", (), {"params": {"a.x": 2.5, "a.y": float("nan"), "a.w": 1.0}})()

    step = type("S", (), {"names": ["a"], "params": {"a.x": 2.0, "a.y": 1.0, "a.z": 3.0, "a.w": float("inf")}})()
    assert refit_shifts(P(), [step]) == [{"a.x": 0.5}]
    assert seen == [(["a"], step.params, True)]
