"""The benchmark's seeds: runs at different ``--seed`` draw disjoint seeds (independent replicates), and ``--seed 0``
keeps the seeds its published runs used (chainid.gap.benchmark.seeds)."""

from __future__ import annotations

import pytest

from chainid.gap.benchmark.grid import grid
from chainid.gap.benchmark.odefamilies import world_cases
from chainid.gap.benchmark.seeds import run_base


def _seeds(seed: int) -> list[int]:
    """Every seed a run draws from: its cases' seeds and the small offsets the cases add of their own (+1, +7 in the
    time grid's builders), and the time grid's level streams (base + 99 + k)."""
    cases = grid(seed=seed) + world_cases(False, seed)
    own = [c["seed"] + d for c in cases for d in (0, 1, 7)]
    return own + [run_base(seed) + 99 + k for k in range(6)]


def test_runs_at_different_seeds_share_no_seed_in_any_world():
    runs = [set(_seeds(s)) for s in (0, 1, 2)]
    assert all(len(runs[i] & runs[j]) == 0 for i in range(3) for j in range(i + 1, 3))


def test_every_seed_a_run_draws_lies_inside_its_own_block():
    """A run's seeds, its cases' own offsets (+1, +7) included, lie in [S·SEED_STRIDE, (S + 1)·SEED_STRIDE)."""
    from chainid.gap.benchmark.seeds import SEED_STRIDE

    for s in (0, 3):
        seeds = _seeds(s)
        assert min(seeds) >= s * SEED_STRIDE and max(seeds) < (s + 1) * SEED_STRIDE


def test_seed_zero_keeps_the_published_runs_seeds():
    """The README's runs at --seed 0 (harmonic 1, 2, …; time 100000 + 1000·k + i; ODE 200000 + crc32 mod 10⁶)."""
    g = grid(seed=0)
    harm = [c["seed"] for c in g if c["excitation"] == "harmonic"]
    assert harm == list(range(1, len(harm) + 1))
    assert [c["seed"] for c in g if c["excitation"] == "random"][:3] == [100000, 100001, 100002]
    assert all(200000 <= c["seed"] < 1_200_000 for c in world_cases(False, 0))


def test_a_later_run_draws_the_same_cases_with_other_seeds():
    """Everything but the seed is the grid's: a later run replicates each case with fresh noise."""
    a, b = grid(seed=0), grid(seed=1)
    assert len(a) == len(b)
    strip = [({k: v for k, v in x.items() if k != "seed"}, {k: v for k, v in y.items() if k != "seed"})
             for x, y in zip(a, b) if x["excitation"] == "harmonic"]
    assert all(x == y for x, y in strip)


@pytest.mark.parametrize("bad", [-1, 1.5, True, "2"])
def test_a_seed_that_is_no_non_negative_integer_is_refused_naming_it(bad):
    with pytest.raises((ValueError, TypeError), match="seed"):
        run_base(bad)
