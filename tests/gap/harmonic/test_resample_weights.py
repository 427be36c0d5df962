"""A resample's refit weights each drawn test by its multiplicity: the same least-squares problem as the test
repeated, so the same parameters, without evaluating a repeated test again."""
from __future__ import annotations

import numpy as np
import pytest

from chainid.gap.harmonic.prepare import prepare_test
from chainid.gap.harmonic.problem import Problem
from chainid.gap.harmonic.resampling import refit
from chainid.model.base import ChainModel
from chainid.model.effects import parse_effect
from chainid.model.laws import PolynomialLaw
from chainid.records.simulate import grid_plan, simulate


@pytest.fixture(scope="module")
def problem_and_fit():
    model = ChainModel()
    plan = grid_plan((1.0, 2.0, 4.0), (0.1, 0.2), 2.0)
    recs = simulate(plan, model, PolynomialLaw([0.0, 0.0, 0.0, 0.0, 40.0]), n_cycles=6, samples_per_cycle=128,
                    noise_F=20.0, seed=5, force_fn=parse_effect("friction:F_c=150", model))
    prob = Problem([prepare_test(r) for r in recs], model, [recs[-1].test], "auto")
    return prob, prob.fit(["friction"])


def test_weights_give_the_parameters_of_the_repeated_tests(problem_and_fit):
    prob, full = problem_and_fit
    mult = np.array([3.0, 0.0, 1.0, 0.0, 1.0])  # five training tests, a draw of five
    assert len(prob.train) == mult.size
    repeated = [d for d, m in zip(prob.train, mult) for _ in range(int(m))]
    want = prob.fit(full.names, train_only=repeated, start=full.params, polish_only=True).params
    got = refit(prob, full, mult)
    assert got.keys() == want.keys()
    for k in want:
        assert got[k] == pytest.approx(want[k], rel=1e-7, abs=1e-9), k
    assert got["friction.F_c"] != pytest.approx(full.params["friction.F_c"], rel=1e-9)  # the draw moved it


def test_weights_of_the_wrong_length_are_refused_and_the_problem_is_left_as_it_was(problem_and_fit):
    prob, full = problem_and_fit
    before = list(prob.train)
    with pytest.raises(ValueError, match="weights: 2 given for 5 tests"):
        prob.fit(full.names, start=full.params, polish_only=True, weights=[1.0, 2.0])
    assert prob.train == before


def test_a_resample_is_at_the_noise_floor_when_its_residual_is_the_noise():
    """Records of the chain with friction F_c = 20 N and noise σ = 20 N per sample: on the resample of every test
    once, the friction model's leave-one-test-out residual is the noise (at the floor: Σ r² of the phase bins
    against Σ σ²/n), the baseline's is not (it leaves the friction).  The floor is the noise variance of a bin's
    mean, σ²/n [N²]; read as σ³/n it would call the baseline's residual noise too."""
    from chainid.gap.harmonic.resampling import rescore

    model = ChainModel()
    plan = grid_plan((1.0, 2.0, 4.0), (0.1, 0.2), 2.0)
    recs = simulate(plan, model, PolynomialLaw([0.0, 0.0, 0.0, 0.0, 40.0]), n_cycles=6, samples_per_cycle=128,
                    noise_F=20.0, seed=5, force_fn=parse_effect("friction:F_c=20", model))
    prob = Problem([prepare_test(r) for r in recs], model, [recs[-1].test], "auto")
    mult = np.ones(len(prob.train))
    flags = {}
    for names in ([], ["friction"]):
        cand = prob.fit(names)
        prob.score(cand, names, 1.0)
        flags[tuple(names)] = rescore(prob, cand, mult)[2]
    assert flags == {(): False, ("friction",): True}
