"""The steady window reports the cycle-to-cycle scatter of amplitude *and* mean whether its tolerance is adaptive or
given: a record whose mean jitters by 1 % of the amplitude per cycle (the amplitude steady) reports 1 % either way."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.signal.steady import select_steady


def _record(seed: int = 2, cycles: int = 200, spc: int = 64):
    rng = np.random.default_rng(seed)
    w, A = 2 * math.pi, 1.0
    t = np.arange(cycles * spc) / (spc * 1.0)
    mean = np.repeat(5.0 + 0.01 * A * rng.standard_normal(cycles), spc)  # a new mean each cycle
    return t, mean + A * np.sin(w * t), w


@pytest.mark.parametrize("rel_tol", [None, 0.08])
def test_the_mean_jitter_is_in_the_scatter(rel_tol):
    t, x, w = _record()
    win = select_steady(t, x, w, 0.0, rel_tol=rel_tol)
    # sigma from second differences of the per-cycle means (MAD-based, ~200 cycles: ~12 % standard error)
    assert win.scatter == pytest.approx(0.01, rel=0.35)
