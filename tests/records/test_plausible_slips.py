"""Plausibility: a time unit slip caught from the record itself (the displacement's speed 2π·f·A), sampling gaps
(count and largest step over 5x the median), one grouped line for a slip in every one of 50 tests, and the rule that
tells non-chain data (a seal, a damper) from a chain's, derived from the chain catalogue."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.chain.spec import default_chain
from chainid.records.plausible import gap_warnings, not_a_chain, plausibility_warnings, sampling_warnings, \
    smallest_chain
from chainid.records.record import Record


def _seal(test="S", scale_t=1.0, n=7000, dt=0.01):
    """A seal stroke: 0.2 Hz, x from -4 to 38 mm (A = 21 mm), friction +-8 N."""
    t = np.arange(n) * dt
    x = 17.0 + 21.0 * np.sin(2 * math.pi * 0.2 * t)
    return Record(test, t * scale_t, x, 8.0 * np.sign(np.cos(2 * math.pi * 0.2 * t)) + 0.5)


def test_time_in_seconds_declared_ms_is_caught_by_the_speed():
    assert sampling_warnings([_seal()]) == []
    (msg,) = sampling_warnings([_seal(scale_t=1e-3)])  # 100 Hz sampling read as 100 kHz: under every rate check
    # by hand: f = 200 Hz, A = 21 mm (half the 1..99 % span, just under 21) -> v = 2 pi 200 21 = 26 389 mm/s
    v = float(msg.split("x moves at about ")[1].split(" mm/s")[0])
    assert 0.97 * 26389 < v <= 26389 * 1.0001
    assert msg.startswith("test 'S': x moves at about") and "--units t=ms" in msg


def test_a_slow_small_chain_test_declared_ms_is_caught_by_the_acceleration():
    t = np.arange(4000) * 0.01  # 100 Hz, 0.95 Hz motion of 0.3 mm: 1.8 m/s (under 5), 1090 g once read as ms
    x = 1.906 + 0.3 * np.sin(2 * math.pi * 0.95 * t)
    assert sampling_warnings([Record("c", t, x, 1e4 + x)]) == []
    (msg,) = sampling_warnings([Record("c", t / 1000.0, x, 1e4 + x)])
    g = float(msg.split(" mm/s and ")[1].split(" g ")[0])
    assert g == pytest.approx((2 * math.pi * 950.0) ** 2 * 0.3 / 9806.65, rel=0.01)  # by hand: 1090 g
    assert "1000 g" in msg and "--units t=ms" in msg
    slower = 1.906 + 0.3 * np.sin(2 * math.pi * 0.5 * t)  # 0.5 Hz: 302 g, 0.94 m/s: the documented blind spot
    assert sampling_warnings([Record("c", t / 1000.0, slower, 1e4 + slower)]) == []


def test_gaps_are_counted_with_the_largest_step():
    t = np.arange(3000) * 0.01
    t[1000:] += 0.29  # a 0.3 s step
    t[2000:] += 0.09  # a 0.1 s step
    r = Record("G", t, np.sin(t), np.cos(t))
    (msg,) = gap_warnings([r])
    assert msg.startswith("test 'G': 2 time step(s) over 5x the median step 0.01 s, the largest 0.3 s at t = 9.99 s")
    assert gap_warnings([Record("H", np.arange(50) * 0.01, np.ones(50), np.ones(50))]) == []


def test_a_slip_in_every_one_of_fifty_tests_is_one_line_per_check():
    from chainid.model import kernels

    t = np.arange(4096) / 1024.0
    recs = []
    for k in range(50):  # chain tests written in metres, read as mm
        x = 1.906 + 0.3 * np.sin(2 * math.pi * (2 + 0.1 * k) * t)
        recs.append(Record(f"T{k}", t, x * 1e-3, np.asarray(kernels.force(x, None, "paper"), dtype=float)))
    msgs = plausibility_warnings(recs, default_chain())
    assert len(msgs) == 2  # the span check and the stiffness check, each once
    assert all("[the same check on 49 more test(s): 'T1', 'T2'," in m for m in msgs)
    assert "--units x=m" in msgs[0]


def test_the_not_a_chain_rule_from_the_catalogue():
    from chainid.model import kernels

    name, proof, x_proof = smallest_chain()
    assert name == "din22252:14x50" and 1.9e5 < proof < 2.0e5 and 15.0 < x_proof < 25.0
    seal = _seal()
    assert "the force changes sign" in not_a_chain([seal])  # friction pushes and pulls
    pos = Record("P", seal.t, seal.x, 48.0 + seal.F)  # the rod force: positive, 40..57 N over a 42 mm stroke
    why = not_a_chain([pos])
    assert why is not None and f"below 1 % of the proof load of the smallest catalogue chain ({name}" in why
    t = np.arange(4096) / 1024.0
    x = 1.906 + 0.3 * np.sin(2 * math.pi * 2.0 * t)
    chain = Record("C", t, x, np.asarray(kernels.force(x, None, "paper"), dtype=float))
    assert not_a_chain([chain]) is None
    assert not_a_chain([Record("kN", t, x, chain.F / 1000.0)]) is None  # a kN slip stays a unit slip
    short = Record("Q", seal.t, seal.x * 0.4, 48.0 + seal.F)  # 17 mm stroke: within the chain's stretch
    assert not_a_chain([short]) is None
