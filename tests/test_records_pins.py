"""Pins of chainid.records helpers to hand numbers (survivors of the mutation run, issue 20 §5).
Units: s, mm."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.records.simulate import _envelope
from chainid.records.validate import _spanned_cycles


def test_taper_envelope_and_slope_by_hand():
    """Linear taper of 1 period (T = 1 s) in and out of 6 periods: e = 0.5, de/dτ = +1 at τ = 0.5; e = 1, 0 at 3;
    e = 0.5, −1 at 5.5.  With 1.5 periods the ramps overlap: at τ = 0.9 the ramp down rules (e = 0.6, slope −1).
    Bugs caught: the ramp-up's condition (τ < T_t) or its tie rule (up <= down) changed."""
    e, de = _envelope(np.array([0.5, 3.0, 5.5]), 1.0, 6, 1.0)
    np.testing.assert_allclose(e, [0.5, 1.0, 0.5], rtol=1e-15)
    np.testing.assert_allclose(de, [1.0, 0.0, -1.0], rtol=1e-15)
    e, de = _envelope(np.array([0.2, 0.75, 0.9]), 1.0, 1.5, 1.0)
    np.testing.assert_allclose(e, [0.2, 0.75, 0.6], rtol=1e-12)
    np.testing.assert_allclose(de, [1.0, 1.0, -1.0], rtol=1e-15)  # at 0.75 up = down: the ramp up (tie rule)
    e, de = _envelope(np.array([0.0, 1.0]), 1.0, 6, 0.0)
    assert e.tolist() == [1.0, 1.0] and de.tolist() == [0.0, 0.0]


def test_spanned_cycles_of_a_pure_sine():
    """x = 3 + sin(2π·0.75·u) over the record: 0.75 periods spanned, R² = 1 (R² = 1 − SS_res/SS_tot with the
    squared deviations).  Bug caught: SS_tot not squared."""
    t = np.linspace(0.0, 2.0, 400)
    u = t / 2.0
    c, r2 = _spanned_cycles(t, 3.0 + np.sin(2 * math.pi * 0.75 * u))
    assert c == pytest.approx(0.75, abs=1e-9) and r2 == pytest.approx(1.0, abs=1e-9)


def test_estimate_memory_by_hand():
    """Two tests of 6 cycles × 200 samples (no ramp): 1200 samples each; kept 24 B each, peak 200 B for the larger:
    2·1200·24 + 1200·200 = 297 600 B; an empty plan needs 0.  Bug caught: the empty-plan guard inverted."""
    from chainid.records.simulate import TestSpec, estimate_memory

    plan = [TestSpec("a", 2.0, 2.0, 0.2), TestSpec("b", 5.0, 2.0, 0.2)]  # (id, omega rad/s, x0 mm, A mm)
    assert estimate_memory(plan, n_cycles=6, samples_per_cycle=200) == pytest.approx(297_600.0, rel=1e-12)
    assert estimate_memory([]) == 0.0


def test_under_one_cycle_message_and_condition():
    """Half a period of a clean sine (R² ≈ 1, c = 0.5) is refused, naming 0.5 period(s) and the period 2·span;
    white noise (no oscillation: R² small) is left to the other checks.  Bugs caught: 'and' made 'or', the
    period span/c garbled."""
    from chainid.records.record import Record
    from chainid.records.validate import _raise_if_under_one_cycle

    t = np.linspace(0.0, 1.0, 200)
    rec = Record("h", t, np.sin(math.pi * t), np.zeros_like(t))
    with pytest.raises(ValueError, match=r"about 0\.5 period\(s\).*period ~2 s, record 1 s"):
        _raise_if_under_one_cycle(rec)
    noise = np.random.default_rng(1).standard_normal(200)
    _raise_if_under_one_cycle(Record("n", t, noise, np.zeros_like(t)))  # no raise
    _raise_if_under_one_cycle(Record("two", t, np.sin(4 * math.pi * t), np.zeros_like(t)))  # 2 periods: no raise
