"""A steady window whose displacement is not a sine goes to the time route (chainid.gap.harmonic.prepare.not_a_sine):
the RMS departure from the fitted sine, less the displacement noise, against 3 % of the amplitude."""
from __future__ import annotations

import math
import re

import numpy as np
import pytest

from chainid.gap.harmonic.prepare import SINE_DISTORTION_MAX, not_a_sine

W = 2 * math.pi  # 1 Hz
T = np.arange(4000) / 400.0  # 10 cycles, 400 samples each


def _tri(t: np.ndarray) -> np.ndarray:
    return 2 / math.pi * np.arcsin(np.sin(W * t))  # a unit triangle wave


def test_a_triangle_departs_by_its_closed_form_share():
    """Unit triangle: fundamental 8/π², RMS² 1/3, so the departure is √(1/3 − 32/π⁴)/(8/π²) = 8.57 % (± 0.05 %)."""
    msg = not_a_sine(T, _tri(T), W, 0.0, 0.0, 1.0)
    want = 100 * math.sqrt(1 / 3 - 32 / math.pi ** 4) / (8 / math.pi ** 2)
    got = float(re.search(r"by ([0-9.]+) % of the amplitude", msg).group(1))
    assert got == pytest.approx(want, abs=0.051)
    assert msg.endswith("(RMS; a sine test departs by at most 3 %, a triangle by 8.6 %): time-domain route")


@pytest.mark.parametrize("d, flagged", [(0.040, False), (0.045, True)])
def test_a_third_harmonic_is_flagged_above_three_percent(d, flagged):
    """sin + d·sin 3ψ departs by d/√2 of the amplitude: 2.83 % (kept) and 3.18 % (flagged, printed 3.2 %)."""
    assert SINE_DISTORTION_MAX == 0.03
    msg = not_a_sine(T, np.sin(W * T) + d * np.sin(3 * W * T), W, 0.0, 0.0, 1.0)
    assert (msg != "") is flagged
    if flagged:
        assert f"by {100 * d / math.sqrt(2):.1f} % of the amplitude" in msg


def test_white_displacement_noise_is_not_distortion():
    """σ = 0.05 mm on a 1 mm sine is 5 % RMS, but the noise estimated from the second differences (MAD/√6, ×1.4826)
    removes it: not flagged."""
    x = np.sin(W * T) + 0.05 * np.random.default_rng(1).normal(size=T.size)
    assert not_a_sine(T, x, W, 0.0, 0.0, 1.0) == ""


def test_distortion_under_the_noise_is_still_found():
    """A 3rd harmonic of 0.06 (departure 0.06/√2 = 4.24 %) under σ = 0.05 mm noise: the noise's share is removed, the
    distortion's is left and flagged (4.24 ± 0.25 %); a noise estimate too large (e.g. MAD/√2) would hide it."""
    x = np.sin(W * T) + 0.06 * np.sin(3 * W * T) + 0.05 * np.random.default_rng(2).normal(size=T.size)
    msg = not_a_sine(T, x, W, 0.0, 0.0, 1.0)
    got = float(re.search(r"by ([0-9.]+) % of the amplitude", msg).group(1))
    assert got == pytest.approx(100 * 0.06 / math.sqrt(2), abs=0.25)


def test_too_short_or_no_amplitude_is_not_judged():
    """Fewer than 16 samples, or A = 0: no verdict; 16 samples of a triangle over a cycle are judged."""
    t16 = np.arange(16) / 16.0
    assert not_a_sine(t16[:15], _tri(t16[:15]), W, 0.0, 0.0, 1.0) == ""
    assert not_a_sine(t16, _tri(t16), W, 0.0, 0.0, 1.0).startswith("not a sine test")
    assert not_a_sine(T, _tri(T), W, 0.0, 0.0, 0.0) == ""


def test_a_set_with_one_triangle_says_once_why_every_record_takes_the_time_route(capsys):
    """Three sine tests and one triangle test of a linear spring (F = 50 + 100·x N, 0.5 N of noise), 10 cycles of
    400 samples: the triangle is not a sine test, so the whole set takes the time-domain route, and stderr says so
    once, naming the triangle and its reason (a departure over 3 %), before the records' own lines."""
    import warnings

    from chainid.gap.diagnose import diagnose
    from chainid.records.record import Record

    rng = np.random.default_rng(4)
    recs = []
    for i, (amp, shape) in enumerate([(1.0, np.sin), (2.0, np.sin), (1.5, np.sin), (1.0, None)]):
        x = 3.0 + amp * (np.sin(W * T) if shape is not None else _tri(T))
        recs.append(Record(f"r{i}", T, x, 50.0 + 100.0 * x + 0.5 * rng.normal(size=T.size)))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = diagnose(recs, ["r1"], None, effects=["friction"], max_combo=1, uncertainty=False)
    assert res["route"] == "time"
    err = capsys.readouterr().err.splitlines()
    said = [ln for ln in err if "every record takes the time-domain route" in ln]
    assert len(said) == 1 and err.index(said[0]) < err.index("chainid diagnose: test r0: time-domain route")
    head = "time-domain route: test r3: not a sine test: the displacement departs from its fitted sine by "
    assert head in said[0]
    assert float(said[0].split(head)[1].split(" %")[0]) > 100 * SINE_DISTORTION_MAX
