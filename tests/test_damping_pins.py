"""Pins of the audit's validation-case forward prediction (finding d) to the closed form (mutation survivors,
issue 20 §5).  Units: mm, N, s, kg."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.damping.audit import VALIDATION, audit
from stand_ins import LinearSpring


def Lin():
    """The closed-form spring of these tests: F = 10000·x."""
    return LinearSpring(10000.0)


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


def test_damping_surface_grid_spans_the_tests_with_10pct_margin(tmp_path):
    """The surface is evaluated on ω from ω_min − 10 % of the span to ω_max + 10 % (and A alike): tests at
    ω = 10, 20, 30 rad/s and A = 0.2, 0.4 mm give ω 8…32 and A 0.18…0.42.  Bugs caught: the margins garbled."""
    from types import SimpleNamespace

    from chainid.damping.plots import plot_damping_surface

    seen = {}

    class Law:
        name = "spy"

        def predict(self, w, A, x0):
            seen.update(w=(w.min(), w.max()), A=(A.min(), A.max()))
            return np.zeros_like(w)

    res = [SimpleNamespace(test=f"T{i}", omega=w, A=A, c_e=1.0, x0=2.0)
           for i, (w, A) in enumerate([(10.0, 0.2), (20.0, 0.4), (30.0, 0.2)])]
    plot_damping_surface(res, Law(), tmp_path / "s.png")
    assert seen["w"] == pytest.approx((8.0, 32.0), rel=1e-12)
    assert seen["A"] == pytest.approx((0.18, 0.42), rel=1e-12)


def test_finding_c_half_swing_of_a_linear_spring():
    """k = 1e4 N/mm: half the swing of F_k over x0 ± A is k·A, its value at x0 is k·x0 (EQ27's x0, A).
    Bug caught: 0.5·(F₊ − F₋) garbled."""
    from chainid.damping.audit import EQ27

    f = {x["id"]: x for x in audit(Lin())["findings"]}["c"]["numbers"]
    assert f["F_k_swing_half_N"] == pytest.approx(1e4 * EQ27["A"], rel=1e-12)
    assert f["F_k_at_x0_N"] == pytest.approx(1e4 * EQ27["x0"], rel=1e-12)
    assert f["k_e_range_x0_pm_A_N_per_mm"] == [1e4, 1e4]
