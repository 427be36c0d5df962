"""The ODE world's chirp test plans (chainid.gap.benchmark.odecases.draw_plan), against the module docstring:
1–3 sweeps per record with rests of 5–15 % of the record (n/fs seconds, not a whole number of seconds), and every
sweep at least 4 periods of its lowest frequency.  Units s, Hz."""
from __future__ import annotations

import numpy as np

from chainid.gap.benchmark.odecases import BASES, draw_base, draw_plan


def test_chirp_rests_are_five_to_fifteen_per_cent_of_the_record():
    """Every base, seeds 0–9 (308 chirp records of 0.8–40 s): the n_sweeps + 1 rests together take
    5–15 % of the record's n/fs seconds, n_sweeps is 1–3, and each sweep, (n/fs − (n_sweeps + 1)·rest)/n_sweeps s
    (hand, the layout of odeshapes.chirp), holds at least 4 periods of f_lo.  Bug caught (seed 27): the record's
    length ``n / fs`` → ``n // fs`` (whole seconds: the rests drawn from a shorter record: 4.76 % of it in the
    first failing record; a record under 1 s gets none)."""
    fracs = []
    for base in BASES:
        for seed in range(10):
            rng = np.random.default_rng(seed)
            b = draw_base(base, rng)
            for r in draw_plan(base, b, "chirp", rng):
                T = r["n"] / r["fs"]
                k = r["n_sweeps"]
                assert 1 <= k <= 3
                frac = (k + 1) * r["rest"] / T
                fracs.append(frac)
                assert 0.05 - 1e-12 <= frac <= 0.15 + 1e-12, (base, seed, r)
                sweep = (T - (k + 1) * r["rest"]) / k
                assert r["f_lo"] * sweep >= 4.0 - 1e-9, (base, seed, r)
    assert len(fracs) >= 300
