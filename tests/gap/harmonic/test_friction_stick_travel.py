"""A friction whose elastic stick travel is a fraction of a per cent of the stroke is fitted with that travel.

Below about 1e-4 of the stroke the library's friction is pure Coulomb sliding, whose cost is flat in the stick
travel x_s, so a fit started at a longer travel slides there and the sliding force comes out low (on a chain of
the ODE world: F_c 66 N for 100 N).  The truth here is simulated apart from the library: a Jenkins element (a
spring F_c/x_s in series with a Coulomb slider) as the stop operator y ← clip(y, x − x_s, x + x_s) on a path 16
times finer than the samples, force F_c·(x − y)/x_s.
"""
from __future__ import annotations

import warnings

import numpy as np
import pytest

import recovery_cases as rc
import sim_devices as sd
from chainid.gap.diagnose import diagnose
from chainid.model.base import ChainModel

pytestmark = pytest.mark.slow

F_C, X_S = 100.0, 0.001  # N, mm: the stick travel is 0.33 % of the largest amplitude
OVER = 16
#: (frequency [Hz], amplitude [mm]) of the steady sines about x0 = 2 mm on the paper's chain
PAIRS = ((0.5, 0.15), (0.5, 0.3), (1.0, 0.2), (1.0, 0.3), (2.0, 0.15), (2.0, 0.3))
CHAIN = ChainModel()


def _jenkins(x_fine: np.ndarray) -> np.ndarray:
    """F_c·(x − y)/x_s with the slider y following x at a distance of at most x_s (starting relaxed at x)."""
    y = np.empty_like(x_fine)
    y[0] = x_fine[0]
    for i in range(1, x_fine.size):
        y[i] = min(max(y[i - 1], x_fine[i] - X_S), x_fine[i] + X_S)
    return F_C * (x_fine - y) / X_S


def _force(mo: sd.MotionFn, t: np.ndarray, f: float, A: float) -> np.ndarray:
    x, xd, _ = mo(t)
    _, xf, _ = sd.fine_path(mo, t, OVER)
    return np.asarray(CHAIN.force(x), float) + rc.C_CHAIN * xd + _jenkins(xf)[::OVER]


def test_a_stick_travel_of_a_few_micrometres_is_fitted_with_its_sliding_force():
    recs = rc.harmonic_set(_force, PAIRS, x0=rc.X0_CHAIN, sigma_x=rc.SX_CHAIN, sigma_F=rc.SF_CHAIN, seed=3)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = diagnose(recs, ["h2", "h5"], CHAIN, quiet=True, effects=["friction"], max_combo=1, uncertainty=False)
    assert res["verdict"] == "friction", res.get("chain_text")
    p = res["steps"][-1]["params"]
    # F_c within 2 % and x_s within 10 % (the noise σ_F = 5 N is 5 % of F_c on each sample; 6 tests × 512)
    assert p["friction.F_c"] == pytest.approx(F_C, rel=0.02), p
    assert p["friction.x_s"] == pytest.approx(X_S, rel=0.10), p


@pytest.mark.xfail(strict=True, reason="the same tests sampled half a step off the reversals (phase π/64): x_s comes "
                   "back 6.0e-5 mm for 1e-3 (F_c 99.8 N, 8.2 dB over the noise on the held-out tests), as it did "
                   "before the noise σ was read from the cycles' scatter (8.2 dB): the fit stays in the sliding "
                   "basin of the module docstring; why the samples' phase decides it is not known")
def test_a_stick_travel_sampled_off_the_reversals_is_fitted_with_its_sliding_force():
    import math

    recs = rc.harmonic_set(_force, PAIRS, x0=rc.X0_CHAIN, sigma_x=rc.SX_CHAIN, sigma_F=rc.SF_CHAIN, seed=3,
                           phase=math.pi / 64)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = diagnose(recs, ["h2", "h5"], CHAIN, quiet=True, effects=["friction"], max_combo=1, uncertainty=False)
    assert res["steps"][-1]["params"]["friction.x_s"] == pytest.approx(X_S, rel=0.10)
