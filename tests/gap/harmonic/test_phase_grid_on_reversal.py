"""A phase point that sits on a reversal has ẋ = 0 (:func:`chainid.gap.harmonic.prepare.on_reversal`).

A sine sampled 64 times a cycle puts two samples exactly on its turning points, where a sliding contact's force is
set-valued (midpoint 0).  The grid's ẋ comes from the estimated phase, so at those points it is the estimate's
error (here 1e-4 rad of phase), and a friction evaluated on it is a full ±F off.  Closed forms: ẋ = Aω·cos ψ.
"""
from __future__ import annotations

import math

import numpy as np

from chainid.gap.harmonic.prepare import on_reversal
from chainid.model.operators import coulomb_sign

A, W = 1.0, 2.0 * math.pi


def _grid(offset_steps: float, phase_error: float = 1e-4) -> np.ndarray:
    psi = 2 * math.pi * (np.arange(64) + offset_steps) / 64 + phase_error
    return A * W * np.cos(psi)


def test_the_samples_on_the_turning_points_take_zero_velocity():
    xd = _grid(0.0)
    out = on_reversal(xd)
    assert np.flatnonzero(out == 0.0).tolist() == [16, 48]  # ψ = π/2 and 3π/2
    keep = np.ones(64, bool)
    keep[[16, 48]] = False
    assert np.array_equal(out[keep], xd[keep])
    # the friction's sign there is the midpoint, elsewhere the sign of the true velocity cos ψ
    s = coulomb_sign(out, True)
    assert s[16] == 0.0 and s[48] == 0.0
    assert np.array_equal(s[keep], np.sign(np.cos(2 * math.pi * np.arange(64) / 64))[keep])


def test_a_grid_between_the_turning_points_keeps_every_velocity():
    """Offset by a quarter of a step, the nearest samples are 0.025 rad from a turning point: still sliding."""
    xd = _grid(0.25)
    assert np.array_equal(on_reversal(xd), xd)


def test_a_point_within_one_percent_of_a_step_is_on_the_reversal_and_two_percent_is_not():
    """The share is REVERSAL_SHARE = 1 % of the neighbours' |ẋ| (about 1 % of a phase step here)."""
    step = 2 * math.pi / 64
    assert on_reversal(_grid(0.0, 0.008 * step))[16] == 0.0
    assert on_reversal(_grid(0.0, 0.02 * step))[16] != 0.0
