"""Pins for the survivors of the blind mutation run seed 26 on chainid.gap (benchmarks/mutation_survivors_seed26.md)."""

from __future__ import annotations

import numpy as np


def test_the_benchmark_seed_changes_the_effect_levels_of_every_excitation() -> None:
    """``benchmark-gap --seed`` is the seed of the benchmark's random effects: two seeds draw different effect
    levels in every non-harmonic excitation (the levels come from a generator seeded by the seed and the
    excitation), and one seed draws the same levels again."""
    from chainid.gap.benchmark.nonharmonic import EXCITATIONS, time_grid

    def levels(seed: int) -> dict[str, list[float]]:
        out: dict[str, list[float]] = {}
        for c in time_grid(seed, False, EXCITATIONS):
            out.setdefault(c["excitation"], []).extend(c["levels"])
        return out

    a, b = levels(0), levels(1)
    assert set(a) == set(EXCITATIONS)
    for e in EXCITATIONS:
        assert len(a[e]) == len(b[e]) > 10
        assert not np.allclose(a[e], b[e]), e
    assert levels(0) == a


def test_a_constant_force_has_the_documented_noise_floor_not_zero() -> None:
    """A harmonic test whose force does not vary at all has no scatter to measure: its σ is the floor
    1e-6·std(F) + 1e-9 N = 1e-9 N (chainid/gap/harmonic/prepare.py), never 0 (every dB over the noise divides by it)."""
    from chainid.gap.harmonic.prepare import prepare_test
    from chainid.records.record import Record

    t = np.arange(8 * 256) / 256 * np.pi  # ω = 2 rad/s, 8 periods of 256 samples
    x = 2.0 + 0.2 * np.sin(2.0 * t)
    d = prepare_test(Record("flat", t, x, np.full(t.size, 5000.0)))
    assert d.sigma == 1e-9
