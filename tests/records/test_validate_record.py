"""Record validation and analysis (chainid.records.validate): cycles spanned, too few or under one cycle, side-file
estimates, the cached estimate, compression, the first bad sample.  Units s, mm, N."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.records.record import Record
from chainid.records.validate import _spanned_cycles, analyse_record, check_data, try_analyse, validate_record


def test_one_and_a_half_cycles_are_reported_as_such():
    """A steady sine of period 2π s over 1.5 periods: fewer than the 2 whole cycles needed; the message says the
    record spans 1.5 periods of 6.283 s."""
    t = np.linspace(0.0, 3 * math.pi, 1500, endpoint=False)
    x = 2.0 + 0.3 * np.sin(t)
    rec = Record("a", t, x, 1000.0 * x)
    with pytest.raises(ValueError, match=r"test 'a': fewer than 2 full cycles .* spans 1\.5 periods of 6\.283 s"):
        validate_record(rec)
    with pytest.raises(ValueError, match=r"spans 1\.5 periods .* within 5 % of the plateau"):
        validate_record(rec, steady_tol=0.05)


def test_check_data_names_the_first_bad_sample():
    from chainid.records.validate import check_data

    t = np.arange(6) * 0.1
    good = Record("g", t, np.ones(6), np.zeros(6))  # F = 0 N is not compressive
    check_data(good)
    x = np.ones(6)
    x[3] = np.nan
    with pytest.raises(ValueError, match=r"test 'n': column 'x' has a NaN/non-finite value at sample 3"):
        check_data(Record("n", t, x, np.ones(6)))
    t2 = t.copy()
    t2[4] = t2[3]  # a repeated time: not strictly increasing at sample 4
    with pytest.raises(ValueError, match=r"test 'r': t is not strictly increasing at sample 4 \(t = 0\.3 s then 0\.3 s\)"):
        check_data(Record("r", t2, np.ones(6), np.ones(6)))
    F = np.array([5.0, -1.0, 2.0, -3.0, 1.0, 0.0])  # dips below zero, mean 0.67 N: a warning (a damped chain can)
    from chainid.records.validate import RecordWarning

    with pytest.warns(RecordWarning, match=r"test 'c': the measured force dips below zero \(min F = -3 N at t = 0\.3 s"):
        check_data(Record("c", t, np.ones(6), F))
    Fm = np.array([1.0, -1.0, 2.0, -3.0, 1.0, 0.0])  # mean -0.0 N: no tension on average, refused
    with pytest.raises(ValueError, match=r"test 'c': force goes compressive \(min F = -3 N at t = 0\.3 s\)"):
        check_data(Record("c", t, np.ones(6), Fm))
    check_data(Record("c", t, np.ones(6), F), allow_compression=True)


def test_spanned_cycles_of_a_pure_sine():
    """x = 3 + sin(2π·0.75·u) over the record: 0.75 periods spanned, R² = 1 (R² = 1 − SS_res/SS_tot with the
    squared deviations).  Bug caught: SS_tot not squared."""
    t = np.linspace(0.0, 2.0, 400)
    u = t / 2.0
    c, r2 = _spanned_cycles(t, 3.0 + np.sin(2 * math.pi * 0.75 * u))
    assert c == pytest.approx(0.75, abs=1e-9) and r2 == pytest.approx(1.0, abs=1e-9)


def test_under_one_cycle_message_and_condition():
    """Half a period of a clean sine (R² ≈ 1, c = 0.5) is refused, naming 0.5 period(s) and the period 2·span;
    white noise (no oscillation: R² small) is left to the other checks.  Bugs caught: 'and' made 'or', the
    period span/c garbled."""
    from chainid.records.record import Record
    from chainid.records.validate import _raise_if_under_one_cycle

    t = np.linspace(0.0, 1.0, 200)
    rec = Record("h", t, np.sin(math.pi * t), np.zeros_like(t))
    with pytest.raises(ValueError, match=r"about 0\.5 period\(s\).*period ~2 s, record 1 s"):
        _raise_if_under_one_cycle(rec)
    noise = np.random.default_rng(1).standard_normal(200)
    _raise_if_under_one_cycle(Record("n", t, noise, np.zeros_like(t)))  # no raise
    _raise_if_under_one_cycle(Record("two", t, np.sin(4 * math.pi * t), np.zeros_like(t)))  # 2 periods: no raise


def test_too_few_cycles_message_counts_the_dropped_first_cycle():
    """A clean sine over 4 periods, asked for 5: the message says 4 contiguous whole cycles, 3 left after the
    first is dropped (the count includes the cycle that selection drops: one more than kept).  Bug caught:
    ``n_cycles + 1`` → ``+ 2``."""
    from chainid.records.record import Record
    from chainid.records.validate import validate_record

    t = np.linspace(0, 4 * 2 * math.pi, 4 * 200, endpoint=False)
    x = 2 + 0.3 * np.sin(t)
    with pytest.raises(ValueError, match=r"fewer than 5 full cycles .* has 4 contiguous whole cycle\(s\) .*"
                                         r"\(3 left after dropping the ramp and the first cycle\)"):
        validate_record(Record("a", t, x, 1000 * x), min_cycles=5)


def test_too_few_cycles_message_states_the_period():
    """A clean sine of period 0.5 s over 4 periods, asked for 5: the message gives the period 0.5 s (2π/ω).
    Bug caught: ``2π / ω`` → ``2π ** ω`` (equal only for ω = 1, the other tests' case)."""
    from chainid.records.record import Record
    from chainid.records.validate import validate_record

    t = np.linspace(0, 2.0, 800, endpoint=False)
    x = 2 + 0.3 * np.sin(4 * np.pi * t)
    with pytest.raises(ValueError, match=r"fewer than 5 full cycles .* spans 4 periods of 0\.5 s and has 4 "):
        validate_record(Record("a", t, x, 1000 * x), min_cycles=5)


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


# --- seed 812 survivors ----------------------------------------------------------------------------------------
def test_under_one_cycle_of_a_given_estimate_states_the_records_own_span():
    """A record from t = 100 s to 100.8 s checked against a given estimate of 1 Hz (a side file): 0.8 periods, so
    "the record (0.8 s) spans 0.8 period(s) of 1 s; at least 2 whole cycles are needed".  Bug caught: the span
    ``t[-1] − t[0]`` → ``t[-1] + t[0]`` in the message (200.8 s)."""
    from chainid.signal.harmonic import HarmonicEstimate
    from chainid.records.validate import validate_record

    t = 100.0 + np.linspace(0.0, 0.8, 81)
    r = Record("u", t, 2.0 + np.sin(2 * np.pi * t), np.full(81, 10.0))
    est = HarmonicEstimate(omega=2 * np.pi, x0=2.0, A=1.0, theta=0.0, noise=0.01, t_origin=100.0)
    with pytest.raises(ValueError, match=r"^test 'u': less than one whole cycle: the record \(0\.8 s\) spans 0\.8 "
                                         r"period\(s\) of 1 s; at least 2 whole cycles are needed$"):
        validate_record(r, estimate=est)


def test_a_noisy_record_under_one_cycle_is_measured_by_the_spanned_cycles_fit():
    """0.7 s of a 1 Hz sine (A = 2 mm) with 0.3 mm of white noise on x, 400 samples: the regular estimate finds
    no clean oscillation, and the single-sinusoid fit over 0.3..3 periods says "x(t) spans about 0.7 period(s)
    of its oscillation (period ~1 s, record 0.7 s)" -- the sine drawn (R² ≈ 2²/2 / (2²/2 + 0.3²) = 0.96 > 0.5).
    Bug caught: the total sum of squares of the fit's R² ``(x − x̄)**2`` → ``(x − x̄)*2`` (≈ 0: the fit never
    passes its R² gate and the record is refused with another reason)."""
    from chainid.records.record import Record
    from chainid.records.validate import validate_record

    rng = np.random.default_rng(0)
    t = np.linspace(0.0, 0.7, 400)
    x = 3.0 + 2.0 * np.sin(2 * np.pi * t + 0.3) + 0.3 * rng.standard_normal(t.size)
    with pytest.raises(ValueError, match=r"^test 'p': less than one whole cycle: x\(t\) spans about 0\.7 period\(s\) "
                                         r"of its oscillation \(period ~1 s, record 0\.7 s\)"):
        validate_record(Record("p", t, x, 1000.0 + 500.0 * np.sin(2 * np.pi * t)))


def test_a_time_that_goes_backwards_is_named_at_its_first_sample():
    """t = 0, 0.1, 0.2, 0.3, 0.25, 0.5 (a step back at sample 4): the message names sample 4 and both times; with
    a step back at sample 2 and a repeated time at sample 4, the first one (sample 2) is named.  Bug caught (seed
    27): the first bad step ``dt <= 0`` → ``dt == 0`` (a step back was named at sample 1, or at the later repeat)."""
    x = np.ones(6)
    t = np.array([0.0, 0.1, 0.2, 0.3, 0.25, 0.5])
    with pytest.raises(ValueError,
                       match=r"test 'b': t is not strictly increasing at sample 4 \(t = 0\.3 s then 0\.25 s\)"):
        check_data(Record("b", t, x, x))
    t = np.array([0.0, 0.1, 0.05, 0.3, 0.3, 0.5])
    with pytest.raises(ValueError,
                       match=r"test 'b': t is not strictly increasing at sample 2 \(t = 0\.1 s then 0\.05 s\)"):
        check_data(Record("b", t, x, x))
