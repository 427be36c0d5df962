"""The ODE world's linear bases (chainid.gap.benchmark.odecases.draw_base) draw every property from the range its
module docstring states, over the whole range: 400 draws per base."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.gap.benchmark.odecases import draw_base

N = 400


def _draws(base: str) -> list[dict]:
    rng = np.random.default_rng(20261130)
    return [draw_base(base, rng) for _ in range(N)]


def _spans(values, lo, hi, tail=0.05):
    """All in [lo, hi], and both ends reached within ``tail`` of the width (400 uniform draws miss the last 5 % of
    a width with probability 0.95^400 ~ 1e-9)."""
    v = np.asarray(values, float)
    w = hi - lo
    return bool(v.min() >= lo and v.max() <= hi and v.min() < lo + tail * w and v.max() > hi - tail * w)


def test_the_resonant_shaker_spans_its_documented_ranges():
    """m 1–5 kg, f_n 20–60 Hz, k = m (2π f_n)² 1e-3 N/mm, ζ 0.02–0.08 (c = 2 ζ m ω_n 1e-3 N·s/mm), rest position
    x_ref −1–1 mm (both signs), preload F0/k 0.5–2 mm, RMS 0.2–1 mm, band 0.5–2 f_n, fs 2000 or 5000 Hz."""
    d = _draws("resonant")
    assert _spans([b["m"] for b in d], 1.0, 5.0) and _spans([b["f_n"] for b in d], 20.0, 60.0)
    assert _spans([b["zeta"] for b in d], 0.02, 0.08)
    assert _spans([b["x_ref"] for b in d], -1.0, 1.0)
    assert _spans([b["F0"] / b["k"] for b in d], 0.5, 2.0) and _spans([b["A"] for b in d], 0.2, 1.0)
    for b in d:
        wn = 2 * math.pi * b["f_n"]
        assert b["k"] == pytest.approx(b["m"] * wn**2 * 1e-3, rel=1e-12)
        assert b["c"] == pytest.approx(2 * b["zeta"] * b["m"] * wn * 1e-3, rel=1e-12)
        assert (b["f_lo"], b["f_hi"]) == pytest.approx((0.5 * b["f_n"], 2.0 * b["f_n"]), rel=1e-12)
    assert {b["fs"] for b in d} == {2000.0, 5000.0}


def test_the_damper_and_the_stiff_mount_span_their_documented_ranges():
    """damper: k 2–10 N/mm, c·2π·f_lo from 6 k to 12 k, x0 −2–2 mm, RMS 1–4 mm, band 4–20 Hz, fs 500/1000/2000 Hz;
    stiff: k 50–500 N/mm about x0 = 5 mm, loss c·ω_c/k 2–6 % at the band centre (1–15 Hz), fs 500/1000 Hz."""
    d = _draws("damper")
    assert _spans([b["k"] for b in d], 2.0, 10.0) and _spans([b["x0"] for b in d], -2.0, 2.0)
    assert _spans([b["c"] * 2 * math.pi * b["f_lo"] / b["k"] for b in d], 6.0, 12.0)
    assert _spans([b["A"] for b in d], 1.0, 4.0) and {(b["f_lo"], b["f_hi"]) for b in d} == {(4.0, 20.0)}
    assert {b["fs"] for b in d} == {500.0, 1000.0, 2000.0}
    s = _draws("stiff")
    assert _spans([b["k"] for b in s], 50.0, 500.0) and {b["x0"] for b in s} == {5.0}
    assert _spans([b["c"] * 2 * math.pi * 8.0 / b["k"] for b in s], 0.02, 0.06)
    assert {b["fs"] for b in s} == {500.0, 1000.0}


def test_the_sine_tests_of_a_displacement_driven_base_have_its_rms_amplitude():
    """The harmonic plan of the damper and the stiff mount: 6–8 sine tests whose RMS A_sine/√2 is the base's RMS
    amplitude A times 0.6–1.4 (a sine of amplitude a has RMS a/√2), over 40 plans."""
    from chainid.gap.benchmark.odecases import draw_plan

    rng = np.random.default_rng(41)
    ratios = []
    for base in ("damper", "stiff"):
        for _ in range(20):
            b = draw_base(base, rng)
            plan = draw_plan(base, b, "harmonic", rng)
            assert 6 <= len(plan) <= 8
            ratios += [p["amp"] / math.sqrt(2) / b["A"] for p in plan]
    assert _spans(ratios, 0.6, 1.4)
