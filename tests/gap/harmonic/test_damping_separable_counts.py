"""The plan's distinct frequencies and amplitudes (chainid.gap.harmonic.bin_fits.damping_separable) are counted to
0.1 % of the largest: values closer than that are one level."""
from __future__ import annotations

from types import SimpleNamespace

from chainid.gap.harmonic.bin_fits import damping_separable


def test_frequencies_within_a_tenth_of_a_percent_count_once():
    """ω = 0.5, 0.5004, 1 rad/s over ω_max = 1: 0.5 and 0.5004 round to 0.500 at 3 decimals: 2 distinct."""
    plan = [(0.5, 0.1), (0.5004, 0.2), (1.0, 0.3), (0.5, 0.3), (0.5004, 0.1), (1.0, 0.2), (1.0, 0.1)]
    ok, msg = damping_separable([SimpleNamespace(omega=w, A=a) for w, a in plan])
    assert not ok
    assert msg.startswith("the training plan has 7 tests at 2 distinct frequencies and 3 distinct amplitudes")
