"""Per-test identification results (chainid.damping.identify): TestResult's defaults and JSON, what identify_records
leaves out and why, the linear spring fitted on the steady window.  Units s, mm, N, N·s/mm."""
from __future__ import annotations

import math

import numpy as np
import pytest

from stand_ins import LinearSpring


def Lin():
    """The closed-form spring of these tests: F = 10000·x."""
    return LinearSpring(10000.0)


def test_test_result_defaults_of_a_hand_made_result():
    """A TestResult built by hand (a side file's values) used no cycles and no window: n_cycles 0, no kept
    cycles, source "estimated" (the documented defaults)."""
    from chainid.damping.identify import TestResult

    r = TestResult("T", 10.0, 2.0, 0.3, 2e4, 3e3, 0.1, 0.99, 300.0, 100.0, 50.0)
    d = r.to_dict()
    assert (d["n_cycles"], d["cycles_kept"], d["source"], d["t_start"], d["t_end"]) == (0, [], "estimated", 0.0, 0.0)


def test_linear_spring_fitted_on_the_steady_window_only():
    """F = 1000·(x − 0.5) N exactly on the steady cycles, but 300 N off during the first 3 s of ramp-in (amplitude
    growing): the spring fitted on the steady window is k = 1000 N/mm, x_ref = 0.5 mm (the ramp left out)."""
    from chainid.damping.identify import linear_model_from_records
    from chainid.records.record import Record

    t = np.arange(0.0, 20.0, 1 / 128)
    amp = 0.3 * np.minimum(t / 3.0, 1.0)
    x = 2.0 + amp * np.sin(2 * math.pi * t)
    F = 1000.0 * (x - 0.5) + np.where(t < 3.0, 300.0, 0.0)
    m = linear_model_from_records([Record("R", t, x, F)])
    assert m.k == pytest.approx(1000.0, rel=1e-6) and m.x_ref == pytest.approx(0.5, abs=1e-6)


def test_test_result_theta_in_the_records_own_time():
    """``TestResult.to_dict`` gives θ for t itself: x = x0 + A sin(ω(t − t0) + θ) = x0 + A sin(ωt + θ − ω t0), so
    θ_json = θ − ω·t0 wrapped to (−π, π] (ω = 2, θ = 0.5, t0 = 3: 0.5 − 6 + 2π = 0.78319); t0 = 0 leaves θ as is;
    t_origin is not in the JSON.  Bug caught: the shift ω·t0 garbled."""
    from chainid.damping.identify import TestResult

    r = TestResult(test="1", omega=2.0, x0=2.2, A=0.3, F0=1.0, FA=1.0, phi=0.0, r2=1.0, F_ac=1.0, c_e=1.0, W=1.0,
                   theta=0.5, t_origin=3.0)
    d = r.to_dict()
    assert d["theta"] == pytest.approx(0.5 - 6.0 + 2 * math.pi, abs=1e-12) and "t_origin" not in d
    t = np.linspace(3.0, 6.0, 7)
    np.testing.assert_allclose(np.sin(2.0 * t + d["theta"]), np.sin(2.0 * (t - 3.0) + 0.5), atol=1e-12)
    r.t_origin = 0.0
    assert r.to_dict()["theta"] == 0.5


def test_identify_records_leaves_out_a_non_finite_or_failed_estimate_and_checks_the_mass():
    """identify_records (three noise-free viscous tests, c = 300 N·s/mm on the spring 1e4 N/mm): a stiffness model
    whose force is NaN gives a non-finite c_e, and one that raises ValueError a failed estimate; each test is then
    left out with that reason (``strict`` raises it); ``progress`` is called (i, n, test) before each test; the mass
    must be a finite number >= 0 kg (0 accepted; the inertia is in phase with x, so c_e does not depend on it).
    Bugs caught: the finiteness check inverted, the failed-estimate branch dropped, the mass bound made > 0."""
    from chainid.damping.identify import identify_records
    from chainid.model.laws import ViscousLaw
    from chainid.records.simulate import TestSpec, simulate

    plan = [TestSpec(f"T{i}", w, 2.2, 0.2) for i, w in enumerate((1.0, 2.0, 3.0))]
    recs = simulate(plan, Lin(), ViscousLaw([300.0]), n_cycles=4, samples_per_cycle=100, ramp_rate=None)

    class NaNForce(LinearSpring):
        def force(self, x):
            return np.full(np.shape(x), np.nan)

    class Broken(LinearSpring):
        def force(self, x):
            raise ValueError("stand-in model refuses x")

    calls = []
    good = identify_records(recs, Lin(), mass_kg=0.0, progress=lambda i, n, t: calls.append((i, n, t)))
    assert calls == [(0, 3, "T0"), (1, 3, "T1"), (2, 3, "T2")]
    np.testing.assert_allclose([r.c_e for r in good], 300.0, rtol=1e-3)
    res = identify_records(recs, NaNForce(1e4))
    assert list(res) == []
    assert [x["reason"] for x in res.excluded] == ["damping estimate is not finite (c_e = nan N.s/mm)"] * 3
    res = identify_records(recs, Broken(1e4))
    assert [x["reason"] for x in res.excluded] == ["damping estimate failed: stand-in model refuses x"] * 3
    with pytest.raises(ValueError, match="test 'T0': damping estimate failed: stand-in model refuses x"):
        identify_records(recs, Broken(1e4), strict=True)
    for bad in (-1e-9, math.nan, math.inf, True):
        with pytest.raises(ValueError, match=r"mass_kg = .* is invalid: valid range >= 0 kg \(finite\)"):
            identify_records(recs, Lin(), mass_kg=bad)


def test_identify_records_needs_both_c_e_and_f_ac_finite(monkeypatch):
    """A test is kept only when c_e AND F_ac are finite (a finite F_ac over an ω·A that underflows gives c_e = inf;
    the rule is stated for both).  Bug caught: the rule weakened to "either is finite"."""
    import chainid.damping.identify as ident
    from chainid.records.simulate import TestSpec, simulate
    from chainid.model.laws import ViscousLaw

    recs = simulate([TestSpec("T0", 2.0, 2.2, 0.2), TestSpec("T1", 3.0, 2.2, 0.2)], Lin(), ViscousLaw([300.0]),
                    n_cycles=4, samples_per_cycle=100, ramp_rate=None)
    real = ident.identify_test
    for bad in (dict(c_e=math.inf, F_ac=5.0), dict(c_e=5.0, F_ac=math.nan)):
        def fake(rec, model, **kw):
            r = real(rec, model, **kw)
            if rec.test == "T1":
                r.c_e, r.F_ac = bad["c_e"], bad["F_ac"]
            return r
        monkeypatch.setattr(ident, "identify_test", fake)
        res = ident.identify_records(recs, Lin())
        assert [r.test for r in res] == ["T0"]
        assert res.excluded == [{"test": "T1", "reason": f"damping estimate is not finite (c_e = {bad['c_e']!r} N.s/mm)"}]


def test_identify_test_and_linear_spring_refuse_records_without_a_steady_cycle():
    """No steady whole cycle: identify_test names the test; the linear-spring fit says why it cannot start.
    A constant force has R² = 1 by definition (nothing to explain), not a division by zero."""
    from types import SimpleNamespace

    from chainid.damping.identify import fit_harmonic, identify_test, linear_model_from_records
    from chainid.records.record import Record

    t = np.linspace(0.0, 1.0, 50)
    rec = Record("Z9", t, 2.0 + 0.0 * t, 1e4 * (2.0 + 0.0 * t))
    with pytest.raises(ValueError, match=r"test 'Z9': no steady whole cycle to identify from"):
        identify_test(rec, Lin(), estimate=SimpleNamespace(window=None))
    with pytest.raises(ValueError, match=r"test 'Z9': no steady whole cycle"):
        identify_test(rec, Lin(), estimate=SimpleNamespace(window=SimpleNamespace(n_cycles=0)))
    with pytest.raises(ValueError, match=r"no test has steady cycles: cannot fit the linear spring \(--model linear "
                                         r"without --k\)"):
        linear_model_from_records([rec])
    h = fit_harmonic(np.linspace(0.0, 6.0, 40), np.full(40, 7.5))
    assert h.r2 == 1.0 and h.F0 == pytest.approx(7.5, rel=1e-12) and h.FA == pytest.approx(0.0, abs=1e-9)


def test_test_result_json_writes_non_finite_numbers_as_null():
    """TestResult.to_dict: the contract's strict JSON: every non-finite float (the NaN defaults of a hand-made
    result: W_ratio, r2_c, F_as, Fc0, steady_tol; an infinite c_e) is None; t_origin is not a key; θ is unchanged
    when the record starts at t = 0."""
    from chainid.damping.identify import TestResult

    r = TestResult("T", 10.0, 2.0, 0.3, 2e4, 3e3, 0.1, 0.99, 300.0, math.inf, 50.0, theta=0.7)
    d = r.to_dict()
    assert [d[k] for k in ("W_ratio", "r2_c", "F_as", "Fc0", "steady_tol", "c_e")] == [None] * 6
    assert "t_origin" not in d and d["theta"] == 0.7 and d["W"] == 50.0 and d["F_ac"] == 300.0


def test_a_loop_without_damping_has_no_energy_ratio():
    """A record whose force is exactly the spring's (F = k·x, no mass): F_c ≡ 0, so c_e = F_ac = 0 and the ratio
    W/(π c_e ω A²) has no value: NaN (null in the JSON), not a division by zero."""
    from chainid.damping.identify import identify_test
    from chainid.records.record import Record

    t = np.linspace(0.0, 8.0, 1601)
    x = 2.2 + 0.25 * np.sin(2 * math.pi * 0.5 * t)
    rec = Record("E", t, x, 10000.0 * x)
    r = identify_test(rec, Lin(), mass_kg=0.0)
    assert r.c_e == 0.0 and r.F_ac == 0.0 and math.isnan(r.W_ratio) and r.to_dict()["W_ratio"] is None
