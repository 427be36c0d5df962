"""More pins of chainid.records to hand numbers and the documented contract (issue 20 §5: own-seed mutation
survivors 812– and weak spots found by reading the modules).

Units: t s, x mm, F N, omega rad/s.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.records.record import Record
from chainid.records.validate import analyse_record, check_data, try_analyse


def _shifted(t0=100.0, theta=0.4):
    """12 s of x = 3 + 0.5 sin(2π(t − t0) + θ) at 100 Hz from t = t0 (1 Hz), F = 1000 + 100 x."""
    t = t0 + np.arange(0, 12, 1 / 100.0)
    x = 3.0 + 0.5 * np.sin(2 * np.pi * (t - t0) + theta)
    return Record("S", t, x, 1000.0 + 100.0 * x)


def test_side_file_estimate_fits_the_phase_from_the_first_sample_and_its_noise_by_hand():
    """With a side file (ω, x0, A) only θ is fitted, from the record's first sample (t_origin = 100 s): θ = 0.4.
    The first whole cycle starts where 2π(t − 100) + 0.4 = 2π, t = 100 + (2π − 0.4)/2π; it is dropped, so the
    window runs from one period later, 10 cycles, in the record's own time.  The noise is the RMS of x about the
    side file's harmonic: 0 for the true values; for x0 off by 0.02 mm and A by 0.03 mm it is
    sqrt(0.02² + 0.03²/2) over whole cycles."""
    r = _shifted()
    est = analyse_record(r, (2 * np.pi, 3.0, 0.5))
    assert est.source == "side file" and est.t_origin == 100.0
    assert est.theta == pytest.approx(0.4, abs=1e-12) and est.noise < 1e-12
    t1 = 100.0 + (2 * np.pi - 0.4) / (2 * np.pi) + 1.0
    assert est.window.t_start == pytest.approx(t1, abs=1e-9) and est.window.n_cycles == 10
    assert est.window.t_end == pytest.approx(t1 + 10.0, abs=1e-9)
    est = analyse_record(r, (2 * np.pi, 3.02, 0.53))
    assert (est.x0, est.A) == (3.02, 0.53)
    assert est.noise == pytest.approx(math.sqrt(0.02**2 + 0.03**2 / 2), rel=1e-9)


def test_side_file_without_a_steady_cycle_is_left_out():
    """A side-file ω that is 30 % off: the cycles at that frequency do not agree; the test is left out (the
    estimate's noise is infinite, so its amplitude is "below the noise")."""
    est, why = try_analyse(_shifted(), side=(2 * np.pi * 1.3, 3.0, 0.5))
    assert est is None and why.startswith(("amplitude below the noise", "fewer than 2 full cycles"))


def test_analyse_record_reuses_the_cached_estimate_only_for_the_same_tolerance():
    """A record's cached estimate (``rec.estimate``) is returned as is when it was made at the tolerance asked
    for (the same object), and recomputed for another tolerance."""
    r = _shifted()
    first = analyse_record(r, steady_tol=0.05)
    r.estimate = first
    assert analyse_record(r, steady_tol=0.05) is first
    other = analyse_record(r, steady_tol=0.1)
    assert other is not first and other.window.rel_tol == 0.1


def test_try_analyse_strips_the_test_prefix_and_refuses_a_bad_tolerance():
    """A reason is returned without the leading "test 'S': " (the caller names the test); a tolerance outside
    (0, 1) is an error naming it."""
    r = _shifted()
    est, why = try_analyse(r, min_snr=1e20)  # the clean record's noise is ~1e-16 mm
    assert est is None and why.startswith("amplitude below the noise: A = 0.5 mm")
    assert why.endswith("(need A >= 1e+20 x noise)")
    for tol in (0.0, 1.0):
        with pytest.raises(ValueError, match=rf"steady_tol = {tol!r} is invalid: must be in \(0, 1\)"):
            try_analyse(r, steady_tol=tol)
    est, why = try_analyse(r, steady_tol=0.05)
    assert est is not None and why == est.window.statement() and "tolerance 5 % (given)" in why


def test_compressive_force_names_the_minimum_and_its_time():
    """F goes below 0: the message names the smallest force and its time; allow_compression accepts it; F = 0 N
    is not compressive."""
    t = np.arange(6) * 0.5
    F = np.array([1.0, 0.0, -2.0, -5.0, 3.0, 1.0])
    with pytest.raises(ValueError, match=r"test 'c': force goes compressive \(min F = -5 N at t = 1\.5 s\)"):
        check_data(Record("c", t, np.ones(6), F))
    check_data(Record("c", t, np.ones(6), F), allow_compression=True)
    check_data(Record("z", t, np.ones(6), np.zeros(6)))
