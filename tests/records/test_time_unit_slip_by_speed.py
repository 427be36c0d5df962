"""A time unit slip that only the speed reveals: a 0.1 Hz test of amplitude 10 mm, sampled at 100 Hz, read with
t declared in ms.  Read so, it is a 100 Hz test (inside the plausible band), its speed 2π·100·10 = 6283 mm/s over
the 5 m/s a rig drives a specimen, while its acceleration (2π·100)²·10 mm/s² = 403 g stays under the 1000 g
check: the speed alone must name the slip.  Read in seconds, it draws no warning.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.records.plausible import sampling_warnings
from chainid.records.record import Record


def _test(scale_t: float) -> Record:
    t = np.arange(6000) * 0.01  # s: 100 Hz sampling, 6 cycles of 0.1 Hz
    x = 12.0 + 10.0 * np.sin(2 * math.pi * 0.1 * t)
    return Record("V", t * scale_t, x, 5000.0 + 100.0 * x)


def test_the_speed_alone_names_a_slip_to_ms():
    assert sampling_warnings([_test(1.0)]) == []
    (msg,) = sampling_warnings([_test(1e-3)])
    v = float(msg.split("x moves at about ")[1].split(" mm/s")[0])
    g = float(msg.split(" mm/s and ")[1].split(" g ")[0])
    amp = 0.5 * (np.percentile(_test(1.0).x, 99.0) - np.percentile(_test(1.0).x, 1.0))  # as the check measures it
    assert amp == pytest.approx(10.0, rel=0.01)
    assert v == pytest.approx(2 * math.pi * 100.0 * amp, rel=0.01)  # by hand: 6283 mm/s with A = 10 mm
    assert g == pytest.approx((2 * math.pi * 100.0) ** 2 * amp / 9806.65, rel=0.02)  # 403 g: under 1000 g
    assert g < 1000.0 and v > 5000.0 and "--units t=ms" in msg
