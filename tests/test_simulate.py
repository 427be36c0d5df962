"""Simulator: plans, signal shape, seeded noise, the force hook, CSV plans."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.model.laws import PolynomialLaw, ViscousLaw
from chainid.records.files import read_records, write_records
from chainid.records.simulate import (
    PAPER_RAMP_RATE,
    TestSpec,
    model_force,
    paper_plan,
    read_plan,
    simulate,
    simulate_test,
    write_plan,
)
from stand_ins import LinearSpring


def Lin():
    """The closed-form spring of these tests: F = 20000·x."""
    return LinearSpring(20000.0)


def test_paper_plan_matches_table1_with_documented_conversion():
    plan = paper_plan()
    assert [s.test for s in plan] == [str(i) for i in range(1, 10)]
    cols = [1, 4, 6, 8, 10, 6, 6, 6, 6]
    for s, c in zip(plan, cols):
        assert s.omega == pytest.approx(c * math.pi / 10)
    # Eq. 25: test 3 at 1.884 rad/s
    assert plan[2].omega == pytest.approx(1.884, rel=1e-3)
    assert [s.A for s in plan] == [0.25] * 5 + [0.2, 0.3, 0.35, 0.4]
    assert [s.x0 for s in plan] == [2.2] * 5 + [2.15, 2.25, 2.3, 2.35]


def test_signal_shape_ramp_and_harmonic():
    spec = TestSpec("a", 1.884, 2.2, 0.25)
    rec = simulate_test(spec, Lin(), 1000.0, ramp_rate=PAPER_RAMP_RATE, n_cycles=3, samples_per_cycle=100)
    t0 = 2.2 / PAPER_RAMP_RATE
    ramp = rec.t <= t0
    np.testing.assert_allclose(rec.x[ramp], PAPER_RAMP_RATE * rec.t[ramp], atol=1e-12)
    osc = ~ramp
    np.testing.assert_allclose(rec.x[osc], 2.2 + 0.25 * np.sin(1.884 * (rec.t[osc] - t0)), atol=1e-12)
    # Eq. 1 with exact derivatives
    v = 1.884 * 0.25 * np.cos(1.884 * (rec.t[osc] - t0))
    a = -1.884**2 * 0.25 * np.sin(1.884 * (rec.t[osc] - t0))
    np.testing.assert_allclose(rec.F[osc], 20000.0 * rec.x[osc] + 1000.0 * v + 3.2e-3 * a, rtol=1e-12)
    assert rec.t[-1] == pytest.approx(t0 + 3 * 2 * math.pi / 1.884, abs=2 * 2 * math.pi / 1.884 / 100)


def test_noise_seeded_and_sized():
    plan = paper_plan()[:2]
    a = simulate(plan, Lin(), 1000.0, seed=5, noise_x=1e-3, noise_F=10.0)
    b = simulate(plan, Lin(), 1000.0, seed=5, noise_x=1e-3, noise_F=10.0)
    c = simulate(plan, Lin(), 1000.0, seed=6, noise_x=1e-3, noise_F=10.0)
    clean = simulate(plan, Lin(), 1000.0, seed=5)
    np.testing.assert_array_equal(a[0].F, b[0].F)
    assert not np.array_equal(a[0].F, c[0].F)
    dx = np.concatenate([r.x - q.x for r, q in zip(a, clean)])
    dF = np.concatenate([r.F - q.F for r, q in zip(a, clean)])
    n = dx.size  # std estimate within ~5 standard errors (1/sqrt(2n))
    assert np.std(dx) == pytest.approx(1e-3, rel=5 / math.sqrt(2 * n))
    assert np.std(dF) == pytest.approx(10.0, rel=5 / math.sqrt(2 * n))


def test_force_hook():
    spec = TestSpec("h", 2.0, 2.2, 0.25)
    seen = {}

    def hook(t, x, xdot, xddot, F_model):
        seen["args"] = (t, x, xdot, xddot)
        return F_model + 100.0 * np.sign(xdot)  # Coulomb friction, 100 N

    plain = simulate_test(spec, Lin(), 500.0, n_cycles=3)
    hooked = simulate_test(spec, Lin(), 500.0, n_cycles=3, force_fn=hook)
    t, x, xdot, xddot = seen["args"]
    np.testing.assert_allclose(hooked.F - plain.F, 100.0 * np.sign(xdot))
    np.testing.assert_allclose(model_force(x, xdot, xddot, Lin(), 500.0), plain.F)
    with pytest.raises(ValueError, match="force_fn returned shape"):
        simulate_test(spec, Lin(), 500.0, force_fn=lambda *a: np.zeros(3))


def test_taper_envelope():
    spec = TestSpec("tap", 2.0, 2.2, 0.25)
    rec = simulate_test(spec, Lin(), 500.0, n_cycles=10, taper_cycles=2)
    T = math.pi
    mid = (rec.t > 2 * T) & (rec.t < 8 * T)
    assert np.max(np.abs(rec.x[mid] - 2.2)) == pytest.approx(0.25, rel=1e-3)
    early = rec.t < 0.5 * T
    assert np.max(np.abs(rec.x[early] - 2.2)) < 0.25 * 0.26


def test_law_and_plan_io(tmp_path):
    p = tmp_path / "plan.csv"
    write_plan(p, paper_plan())
    back = read_plan(p)
    assert [s.test for s in back] == [s.test for s in paper_plan()]
    np.testing.assert_allclose([[s.omega, s.x0, s.A] for s in back],
                               [[s.omega, s.x0, s.A] for s in paper_plan()], rtol=1e-9)
    with pytest.raises(ValueError, match="already exists"):
        write_plan(p, paper_plan())
    bad = tmp_path / "bad.csv"
    bad.write_text("test,omega,x0,A\nq,fast,2,0.2\n")
    with pytest.raises(ValueError, match=r"test 'q': omega = 'fast' is not a number"):
        read_plan(bad)
    bad.write_text("test,omega,x0,A\nq,-2,2,0.2\n")
    with pytest.raises(ValueError, match=r"test 'q': omega = -2.0 is invalid"):
        read_plan(bad)
    bad.write_text("test,omega,A\nq,2,0.2\n")
    with pytest.raises(ValueError, match=r"missing column"):
        read_plan(bad)


def test_records_written_are_valid_input(tmp_path):
    law = PolynomialLaw([28.02, -651.57, -8386.50, 7394.84, 4378.89])
    recs = simulate(paper_plan(), Lin(), law, seed=1, ramp_rate=PAPER_RAMP_RATE, noise_x=1e-3, noise_F=20)
    p = tmp_path / "sim.csv"
    write_records(p, recs)
    back = read_records(p)
    assert len(back) == 9


def test_bad_settings():
    spec = TestSpec("b", 2.0, 2.2, 0.25)
    for kw, msg in [({"n_cycles": 0}, "n_cycles"), ({"samples_per_cycle": 4}, "samples_per_cycle"),
                    ({"ramp_rate": -1.0}, "ramp_rate"), ({"noise_x": -1.0}, "noise")]:
        with pytest.raises(ValueError, match=msg):
            simulate_test(spec, Lin(), 1.0, **kw)
    with pytest.raises(ValueError, match=r"test 'z': A = 0.0 is invalid"):
        TestSpec("z", 1.0, 2.0, 0.0)
    assert ViscousLaw([3.0]).predict(1.0, 1.0)[0] == 3.0


def test_grid_plan_order_ids_and_extras():
    from chainid.records.simulate import grid_plan

    plan = grid_plan((1.0, 2.0), (0.1, 0.3), 2.0, extra=[(3.0, 2.2, 0.15)], prefix="g")
    assert [p.test for p in plan] == ["g1", "g2", "g3", "g4", "g5"]
    assert [(p.omega, p.x0, p.A) for p in plan] == [(1.0, 2.0, 0.1), (1.0, 2.0, 0.3), (2.0, 2.0, 0.1),
                                                    (2.0, 2.0, 0.3), (3.0, 2.2, 0.15)]
    with pytest.raises(ValueError, match="A"):
        grid_plan((1.0,), (-0.1,), 2.0)
