"""Ranking of damping laws by leave-one-out RMSE: equal errors rank the law with fewer parameters first.

The stand-in laws below have stated leave-one-out errors (what the ranking reads), so the expected order is the
rule itself, written out by hand; a real set of tests with a constant c_e (fitted exactly by every law with a
constant term: their errors are round-off) must rank the one-parameter viscous law first.
"""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from chainid.model.laws import CombinedLaw, PolynomialLaw, ViscousLaw, rank_laws

W = np.array([10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0])
A = np.array([0.1, 0.2, 0.3, 0.1, 0.2, 0.3, 0.25])


class StandIn:
    """A law whose fit has a given leave-one-out RMSE [N·s/mm] (or fails: None)."""

    def __init__(self, name: str, n_params: int, loo: float | None):
        self.name, self.n_params, self.loo = name, n_params, loo
        self.param_names = tuple(f"p{i}" for i in range(n_params))
        self.fit_ = None

    def formula(self) -> str:
        return self.name

    def fit(self, omega, A, c, x0=None):
        if self.loo is None:
            raise ValueError("cannot be fitted")
        self.fit_ = SimpleNamespace(params=[0.0] * self.n_params, stderr=[0.0] * self.n_params, rmse=self.loo,
                                    loo_rmse=self.loo)
        return self


def _order(laws, c=None):
    c = np.full(W.size, 100.0) if c is None else c
    return [r["law"] for r in rank_laws(W, A, c, laws=laws)]


def test_equal_errors_fewer_parameters_first():
    laws = [StandIn("five", 5, 0.5), StandIn("two", 2, 0.5), StandIn("one", 1, 0.5)]
    assert _order(laws) == ["one", "two", "five"]


def test_errors_equal_to_round_off_are_equal():
    # the 5-parameter law is ahead by 1e-12 relative: round-off, not a better law
    laws = [StandIn("five", 5, 0.5 * (1 - 1e-12)), StandIn("one", 1, 0.5)]
    assert _order(laws) == ["one", "five"]


def test_a_real_difference_is_kept():
    laws = [StandIn("five", 5, 0.4), StandIn("one", 1, 0.5)]
    assert _order(laws) == ["five", "one"]
    laws = [StandIn("five", 5, 0.5 * (1 - 1e-6)), StandIn("one", 1, 0.5)]
    assert _order(laws) == ["five", "one"]


def test_laws_that_cannot_be_fitted_come_last_fewer_parameters_first():
    laws = [StandIn("bad5", 5, None), StandIn("bad1", 1, None), StandIn("good", 3, 1.0)]
    rows = rank_laws(W, A, np.full(W.size, 100.0), laws=laws)
    assert [r["law"] for r in rows] == ["good", "bad1", "bad5"]
    assert rows[1]["loo_rmse"] == math.inf and "cannot be fitted" in rows[1]["error"]


@pytest.mark.parametrize("c0", [100.0, 2834.4, 0.3])
def test_constant_damping_ranks_the_viscous_law_first(c0):
    # c_e ≡ c0 is fitted exactly by viscous (1 parameter), viscous+Coulomb (2) and Eq. 21 (5): a tie
    order = _order([PolynomialLaw(), CombinedLaw(), ViscousLaw()], np.full(W.size, c0))
    assert order == ["viscous", "viscous+coulomb", "polynomial"]


def test_equal_errors_that_straddle_a_rounding_boundary_are_equal():
    # 1.0000000049 and 1.0000000051 differ by 2e-10 relative (within the 1e-9 tie), but rounded to nine significant
    # digits they are 1.00000000 and 1.00000001: a tie judged on rounded values ranks the five-parameter law first
    laws = [StandIn("five", 5, 1.0000000049), StandIn("one", 1, 1.0000000051)]
    assert _order(laws) == ["one", "five"]


def test_a_failed_fit_ranks_last_and_ties_do_not_chain_past_the_tolerance():
    # 0.5, 0.5·(1 + 0.6e-9), 0.5·(1 + 1.2e-9): the third is 1.2e-9 from the group's smallest error, not a tie
    laws = [StandIn("failed", 1, None), StandIn("six", 6, 0.5 * (1 + 1.2e-9)), StandIn("four", 4, 0.5),
            StandIn("three", 3, 0.5 * (1 + 0.6e-9))]
    assert _order(laws) == ["three", "four", "six", "failed"]
