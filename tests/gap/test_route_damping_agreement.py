"""The two routes agree on the damping of a mixed set.

A linear device (k = 20 N/mm) whose viscous damping follows a law over record features, c = 10 + 0.8·(ω − 3) +
2·(A − 1) N·s/mm (ω the band centre [rad/s], A the half range of x [mm]: ±25 % across the tests).  Six steady
harmonic tests alone go the harmonic route (c_e per test from the loops, Eq. 21–28's form); the same tests with two
band-limited random records go the time route, whose base's dashpot follows record features (the paper's c_e(ω, A)
on any excitation): both bases carry the law, and nothing beyond them differs.
Reference: the law above in closed form; each route's c for every harmonic test within 3 % of it and of the other
route's.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.gap import diagnose
from chainid.records import Record

pytestmark = pytest.mark.slow
K, FS, SIGMA = 20.0, 200.0, 0.05


def c_true(omega: float, A: float) -> float:
    """The device's damping law [N·s/mm] at band centre ω [rad/s] and half range A [mm]."""
    return 10.0 + 0.8 * (omega - 3.0) + 2.0 * (A - 1.0)


def _harmonic(i: int, omega: float, A: float, rng: np.random.Generator) -> Record:
    t = np.arange(int(8 * 2 * math.pi / omega * FS)) / FS
    x = 1.0 + A * np.sin(omega * t)
    xd = A * omega * np.cos(omega * t)
    F = K * x + c_true(omega, A) * xd + rng.normal(0, SIGMA, t.size)
    return Record(f"h{i}", t, x, F)


def _random(i: int, rng: np.random.Generator) -> tuple[Record, float]:
    t = np.arange(int(40 * FS)) / FS
    w = 2 * math.pi * np.arange(4, 25) / 40.0  # 0.1 … 0.6 Hz on the record's own period: a periodic multisine
    a = rng.uniform(0.5, 1.0, w.size)
    ph = rng.uniform(0, 2 * math.pi, w.size)
    s = 1.0 / np.abs((a[:, None] * np.sin(w[:, None] * t + ph[:, None])).sum(0)).max()
    a = a * s * (0.8 + 0.2 * i)
    x = 1.0 + (a[:, None] * np.sin(w[:, None] * t + ph[:, None])).sum(0)
    xd = (a[:, None] * w[:, None] * np.cos(w[:, None] * t + ph[:, None])).sum(0)
    omega_c = float((w * a**2).sum() / (a**2).sum())  # the variance-weighted mean angular frequency
    A = float((x.max() - x.min()) / 2)
    c = c_true(omega_c, A)
    return Record(f"r{i}", t, x, K * x + c * xd + rng.normal(0, SIGMA, t.size)), c


PLAN = [(1.5, 0.7), (3.0, 0.7), (6.0, 0.7), (1.5, 1.3), (3.0, 1.3), (6.0, 1.3)]


@pytest.fixture(scope="module")
def routes():
    rng = np.random.default_rng(5)
    harm = [_harmonic(i, w, A, rng) for i, (w, A) in enumerate(PLAN)]
    rand = [_random(i, rng)[0] for i in range(2)]
    h = diagnose(harm, ["h4"], None, uncertainty=False, quiet=True)
    m = diagnose(harm + rand, ["h4", "r1"], None, uncertainty=False, quiet=True)
    return h, m


def test_a_harmonic_set_goes_the_harmonic_route_and_a_mixed_set_the_time_route(routes):
    h, m = routes
    assert (h["route"], m["route"]) == ("harmonic", "time")


def test_the_harmonic_route_reads_each_tests_damping(routes):
    h, _ = routes
    dmp = h["_model"].damping
    for i, (w, A) in enumerate(PLAN):
        if f"h{i}" in dmp.per_test:
            assert dmp.per_test[f"h{i}"] == pytest.approx(c_true(w, A), rel=0.03)


def test_the_time_routes_base_carries_the_law_and_predicts_every_harmonic_tests_c(routes):
    h, m = routes
    assert m["verdict"] == "none", m["warnings"]
    assert m["baseline"]["damping_law"] == "feature"
    law = m["_model"].damping
    assert law.form == "feature"
    hd = h["_model"].damping
    for i, (w, A) in enumerate(PLAN):
        c_time = law.resolve(w, A, K).params["c"]
        assert c_time == pytest.approx(c_true(w, A), rel=0.03)
        c_harm = hd.per_test.get(f"h{i}")
        if c_harm is not None:
            assert c_time == pytest.approx(c_harm, rel=0.03)
