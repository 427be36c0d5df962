"""The phase-bin evaluation of an effect set is remembered per test of the problem, effect set and parameters: the
same numbers as a fresh evaluation, read-only (no caller can change what another gets), and never for a test object
that is not the problem's own (a transfer set's test of the same id)."""
from __future__ import annotations

import copy

import numpy as np
import pytest

from chainid.gap.harmonic.prepare import prepare_test
from chainid.gap.harmonic.problem import Problem
from chainid.model.base import ChainModel
from chainid.model.effects import parse_effect
from chainid.model.laws import PolynomialLaw
from chainid.records.simulate import grid_plan, simulate


@pytest.fixture(scope="module")
def prob():
    model = ChainModel()
    recs = simulate(grid_plan((1.0, 2.0), (0.1, 0.2), 2.0), model, PolynomialLaw([0.0, 0.0, 0.0, 0.0, 40.0]),
                    n_cycles=4, samples_per_cycle=128, noise_F=20.0, seed=2,
                    force_fn=parse_effect("friction:F_c=150", model))
    return Problem([prepare_test(r) for r in recs], model, [recs[-1].test], "auto")


def test_a_remembered_evaluation_equals_a_fresh_one_and_cannot_be_changed(prob):
    d = prob.train[0]
    p = {"friction.F_c": 150.0, "friction.x_s": 0.0}
    Fn, v = prob.parts(["friction"], p, d)
    Fn2, v2 = prob.parts(["friction"], p, d)
    assert Fn2 is Fn and v2 is v  # remembered
    fresh = Problem(prob.data, prob.model, [h.test for h in prob.hold], "auto")
    assert np.array_equal(fresh.parts(["friction"], p, d)[0], Fn)
    other = prob.parts(["friction"], {"friction.F_c": 100.0, "friction.x_s": 0.0}, d)[0]
    assert np.max(np.abs(other - Fn)) > 10.0  # another F_c: another evaluation
    with pytest.raises(ValueError, match="read-only"):
        Fn[0] = 0.0


def test_a_foreign_test_object_with_the_same_id_is_evaluated_not_remembered(prob):
    d = prob.train[1]
    p = {"friction.F_c": 150.0, "friction.x_s": 0.0}
    twin = copy.copy(d)
    twin.Fbar = d.Fbar  # the same id, another object (e.g. a transfer set's test)
    a = prob.parts(["friction"], p, twin)[0]
    b = prob.parts(["friction"], p, twin)[0]
    assert a is not b and np.array_equal(a, b)
