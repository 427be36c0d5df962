"""Pins of the audit's validation-case forward prediction (finding d) to the closed form (mutation survivors,
issue 20 §5).  Units: mm, N, s, kg."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.damping.audit import VALIDATION, audit


class Lin:
    name = "stand-in linear"
    mass_kg = 3.2

    def force(self, x):
        return 10000.0 * np.asarray(x, float)

    def stiffness(self, x):
        return np.full(np.shape(x), 10000.0)


def test_finding_d_forward_prediction_closed_form():
    """x = x0 + A sin ψ with ψ = ωt over one period: F = k x + m ẍ·1e-3 + c ẋ = k x0 + B sin ψ + C cos ψ with
    B = A(k − m ω²·1e-3), C = c ω A, so F_max,min = k x0 ± sqrt(B² + C²) (721 samples over the period: the sampled
    extreme misses by at most amp·(1 − cos(π/720)) < 1e-5·amp).
    Bugs caught: ẋ = ωA cos ψ garbled (ω/A), the prediction skipped when a model is given."""
    f = {x["id"]: x for x in audit(Lin())["findings"]}["d"]["numbers"]
    w = 2 * math.pi * VALIDATION["f_Hz"]
    A, x0, k, m = VALIDATION["A"], VALIDATION["x0"], 1e4, 3.2
    for key in ("omega_7", "omega_14pi"):
        c = f[f"c_e_{key}"]
        B, C = A * (k - m * w * w * 1e-3), c * w * A
        amp = math.hypot(B, C)
        assert f[f"F_max_N_{key}"] == pytest.approx(k * x0 + amp, abs=1e-5 * amp)
        assert f[f"F_min_N_{key}"] == pytest.approx(k * x0 - amp, abs=1e-5 * amp)
    assert f["F_k_range_N"] == pytest.approx([k * (x0 - A), k * (x0 + A)], rel=1e-9)
