"""The continuous-spectrum detection of chainid.gap.core.kinematics.signal_power against its stated levels: under
white noise the running mean of K = 32 periodogram bins is Gamma(K, μ/K); a run is seeded where it passes the
1 − 0.05/N quantile (1.88 μ for N = 2049 bins, scipy.stats.gamma.ppf), so a band of 3 μ is found and one of
1.2 μ (six of its standard deviations 0.21 μ below the seed) is not."""
from __future__ import annotations

import numpy as np
from scipy.stats import gamma

from chainid.gap.core.kinematics import SMOOTH_BINS, signal_power

N = 2049
BAND = slice(300, 500)  # in the lower half, outside the bins the floor is read from


def _found(level: float, seed: int) -> float:
    """Share of a 200-bin band at ``level`` × the noise's mean power that the detection keeps."""
    P = np.random.default_rng(seed).exponential(1.0, N)
    P[BAND] *= level
    floor = float(np.median(P[P.size // 2:]))
    return float(np.mean(signal_power(P, floor)[BAND] > 0.0))


def test_the_seed_level_is_the_bonferroni_quantile_of_the_running_mean():
    seed_level = gamma.ppf(1.0 - 0.05 / N, SMOOTH_BINS) / SMOOTH_BINS
    assert 1.85 < seed_level < 1.92
    assert all(_found(3.0, s) >= 0.9 for s in range(10))  # 3 μ: above the seed in every record
    assert sum(_found(1.2, s) > 0.0 for s in range(10)) <= 2  # 1.2 μ: under it
