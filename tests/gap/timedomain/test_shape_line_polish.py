"""The one-parameter polish of a shape parameter's grid (``chainid.gap.timedomain.search._line``): Brent's bounded
search between the grid neighbours of each of the best grid values, in log scale for a geometric grid.  A minimum
between a grid value and the one below it, or the one above it, is found to the search's tolerance."""
from __future__ import annotations

import math

import pytest

from chainid.gap.timedomain.search import _line

GRID = [0.001, 0.01, 0.1, 1.0]  # a geometric grid of hysteresis.x_h [mm]


def _cost(at):
    return lambda p: (math.log(p["hysteresis.x_h"]) - math.log(at)) ** 2


@pytest.mark.parametrize("at", [0.04, 0.3, 0.002])
def test_a_minimum_on_either_side_of_the_best_grid_value_is_found(at):
    cost = _cost(at)
    ranked = sorted(GRID, key=lambda v: cost({"hysteresis.x_h": v}))
    got, pinned = _line(("hysteresis.x_h", 0.0, 5.0), ranked, cost)
    assert got["hysteresis.x_h"] == pytest.approx(at, rel=1e-4) and pinned == []


def test_a_linear_grid_is_searched_between_its_neighbours_in_linear_scale():
    cost = lambda p: (p["friction.F_c"] - 37.0) ** 2  # noqa: E731
    ranked = sorted([0.0, 25.0, 50.0, 75.0, 100.0], key=lambda v: cost({"friction.F_c": v}))
    got, _ = _line(("friction.F_c", 0.0, 100.0), ranked, cost)
    assert got["friction.F_c"] == pytest.approx(37.0, abs=1e-3)


def test_the_best_grid_value_is_polished_downwards_too_when_the_value_below_it_ranks_low():
    """The minimum (0.05 mm) lies between the best grid value 0.1 and the one below it, 0.01, which a step in the
    cost (below 0.02 mm) ranks behind 1.0: only the best value's own bracket, down to its lower neighbour, holds it."""
    cost = lambda p: _cost(0.05)(p) + (10.0 if p["hysteresis.x_h"] < 0.02 else 0.0)  # noqa: E731
    ranked = sorted(GRID, key=lambda v: cost({"hysteresis.x_h": v}))
    assert ranked[:2] == [0.1, 1.0]
    got, _ = _line(("hysteresis.x_h", 0.0, 5.0), ranked, cost)
    assert got["hysteresis.x_h"] == pytest.approx(0.05, rel=1e-4)
