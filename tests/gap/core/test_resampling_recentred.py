"""The resampled 90 % intervals are centred on the reported estimate (:func:`chainid.gap.core.resample.resample`).

A route's refit on a resample polishes from the diagnosis' estimate and need not end where the diagnosis' own fit
did.  Stub hooks whose refit lands 0.5 above the estimate on the data as they are, and moves by 0.1 per extra copy
of the first unit: the interval must be the percentiles of 1.0 + 0.1·(m₀ − 1) (computed here from the same draws),
which contain the estimate 1.0; the uncentred refits (1.5 + ...) would not.
"""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from chainid.gap.core.resample import resample

N_UNITS = 5


class Hooks:
    @staticmethod
    def draw(prob, rng):
        return rng.multinomial(N_UNITS, np.full(N_UNITS, 1.0 / N_UNITS)).astype(float)

    @staticmethod
    def identity(prob):
        return np.ones(N_UNITS)

    @staticmethod
    def rescore(prob, cand, mult):
        return {}, 0.0, True  # at the noise floor: the replayed chain is empty

    @staticmethod
    def refit(prob, cand, mult):
        return {"a": 1.5 + 0.1 * (mult[0] - 1.0)}


def test_percentile_interval_is_shifted_onto_the_estimate():
    step = SimpleNamespace(names=(), params={"a": 1.0}, at_bound=(), n_params=1, bic=0.0)
    out = resample(None, Hooks, {"_cache": {}, "path": [step]}, [step], n=100, seed=3, workers=1)
    rng = np.random.default_rng(3)
    m0 = np.array([Hooks.draw(None, rng)[0] for _ in range(100)])
    lo, hi = np.percentile(1.0 + 0.1 * (m0 - 1.0), [5, 95])
    assert out["steps"][0]["params_ci90"]["a"] == pytest.approx([lo, hi], abs=1e-12)
    assert lo <= 1.0 <= hi
    assert not (lo + 0.5 <= 1.0 <= hi + 0.5)  # the refits as they come would miss the estimate


class HeldOutHooks(Hooks):
    """Two of the five units are held out: the data as they are draw three."""

    @staticmethod
    def identity(prob):
        return np.array([1.0, 0.0, 1.0, 0.0, 1.0])


def test_resampling_reports_the_training_units_it_draws():
    step = SimpleNamespace(names=(), params={"a": 1.0}, at_bound=(), n_params=1, bic=0.0)
    out = resample(None, HeldOutHooks, {"_cache": {}, "path": [step]}, [step], n=20, seed=3, workers=1)
    assert out["units"] == 3  # held-out units (multiplicity 0) are not training units
