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


@pytest.mark.parametrize("ratio,text", [
    (1000.0, "x in m read as mm"), (1e-3, "F in kN read as N"), (25.4, "x in inches declared mm?"),
    (1 / 25.4, "x declared inches while in mm"), (1 / 4448.2, "F in kip read as N"),
    (1 / 4.448, "F in lbf read as N (--units F=lbf)"), (1 / 4.448 * 2.9, "F in lbf read as N"),
    (0.75, "a unit slip of x or F?"),  # 3.34 x the lbf ratio 0.2248: outside every slip's factor-3 window
    (8.0, "a unit slip of x or F?"),  # 25.4 / 8 = 3.2: outside the inches window too
])
def test_stiffness_ratio_names_the_slip_within_a_factor_three(ratio, text):
    """The stiffness-ratio check names the known slip nearest (in log) to the record's k over the chain's, when
    it is within a factor 3: m/mm or kN/N (1000), inches (25.4), kip (4448.2 N) and lbf (4.448 N) per unit; else
    the generic question.  Bug caught: the lbf factor 4.448 garbled (3.448: 0.75 would be named lbf)."""
    from chainid.records.plausible import _slip

    assert text in _slip(ratio)


def test_random_phases_are_uniform_on_zero_two_pi(monkeypatch):
    """The band-limited random and earthquake programs sum lines with random phases, uniform on [0, 2π) (the
    module docstring): every phase drawn lies in [0, 2π) and their circular mean |mean e^{iφ}| is below 4/√N (N
    lines; a uniform phase gives 1/√N on average).  Bug caught: ``uniform(0, 2π)`` → ``uniform(0, 2**π)`` (phases
    up to 8.8 rad, a mean resultant of 0.22)."""
    import chainid.records.excitation as ex

    phases = []
    real = ex._fourier

    def spy(t, f, amp, ph):
        phases.append(np.asarray(ph, float))
        return real(t, f, amp, ph)

    monkeypatch.setattr(ex, "_fourier", spy)
    rng = np.random.default_rng(11)
    ex.earthquake(20_000, 200.0, 0.3, 2.0, rng)
    ex.band_random(20_000, 200.0, 0.5, 20.0, 0.1, 2.0, rng, wander=0.05)
    assert len(phases) == 3
    for ph in phases[:2]:  # the quake's and the band's lines (the wander has only a few)
        assert ph.size >= 1000
        assert ph.min() >= 0.0 and ph.max() < 2 * np.pi
        assert abs(np.mean(np.exp(1j * ph))) < 4 / np.sqrt(ph.size)


@pytest.mark.parametrize("arrow", [True, False])
def test_writer_without_the_kernel_round_trips_over_several_blocks(tmp_path, monkeypatch, arrow):
    """With the numba kernel off (``NUMBA_DISABLE_JIT=1``) the CSV is written by pyarrow in blocks of rows, or
    without pyarrow by ``%.17g``: 2 507 and 10 rows in blocks of 1 000 read back bit-exact, in order, under the
    header ``test,t,x,F``.  Bug caught: the block end ``i + rows`` → ``i / rows`` (the pyarrow path had no test:
    the other round-trip tests run with the kernel)."""
    import sys

    import chainid.infra.floattext as ft
    import chainid.records.writer as w

    monkeypatch.setattr(ft, "jit_enabled", lambda: False)
    monkeypatch.setattr(w, "_ROWS_PER_WRITE", 1000)
    monkeypatch.setattr(w, "_BLOCK", 1000)
    if not arrow:
        monkeypatch.setitem(sys.modules, "pyarrow", None)
        monkeypatch.setitem(sys.modules, "pyarrow.csv", None)
    rng = np.random.default_rng(2)
    n = 2507
    t = np.cumsum(rng.uniform(1e-4, 2e-3, n))
    a = Record("A", t, rng.normal(2.2, 0.3, n) * np.pi, rng.normal(1e4, 3e3, n) / 3.0)
    b = Record("B2", t[:10].copy(), np.full(10, 1 / 3), np.full(10, 2 / 3))
    p = w.write_canonical(tmp_path / "o.csv", [a, b])
    lines = p.read_text(encoding="ascii").splitlines()
    assert lines[0] == "test,t,x,F" and len(lines) == 1 + n + 10
    rows = [ln.split(",") for ln in lines[1:]]
    assert [r[0] for r in rows] == ["A"] * n + ["B2"] * 10
    for k, col in (("t", 1), ("x", 2), ("F", 3)):
        vals = np.array([float(r[col]) for r in rows])
        np.testing.assert_array_equal(vals[:n], getattr(a, k))
        np.testing.assert_array_equal(vals[n:], getattr(b, k))


# --- weak spots of excitation.py: closed forms ------------------------------------------------------------------
def test_smoothstep_values_and_derivatives_by_hand():
    """s(u) = 10u³ − 15u⁴ + 6u⁵ clipped to [0, 1], u = (t − t_i)/T with T = 2 s: s(0.25) = 0.103515625,
    s(0.5) = 0.5, ds/dt(0.5) = 30·u²(1 − u)²/T = 0.9375 /s, d²s/dt²(0.25) = 60u(1 − u)(1 − 2u)/T² = 1.40625 /s²;
    beyond the ends s is 0 or 1 with zero derivatives."""
    from chainid.records.excitation import smoothstep

    s, ds, dds = smoothstep(np.array([-0.5, 0.0, 0.25, 0.5, 1.0, 1.5]), 2.0)
    assert s == pytest.approx([0.0, 0.0, 0.103515625, 0.5, 1.0, 1.0], abs=1e-15)
    assert ds == pytest.approx([0.0, 0.0, 30 * 0.0625 * 0.5625 / 2, 0.9375, 0.0, 0.0], abs=1e-15)
    assert dds == pytest.approx([0.0, 0.0, 1.40625, 0.0, 0.0, 0.0], abs=1e-15)


def test_motion_sum_and_dominant_frequency_default():
    """A Motion's dominant frequency defaults to its band edge f_max; the sum of two motions adds x, ẋ, ẍ, keeps
    the larger f_max and f_dom, and the first one's A and kind."""
    from chainid.records.excitation import Motion

    t = np.arange(3.0)
    a = Motion(t, np.ones(3), np.full(3, 2.0), np.full(3, 3.0), 4.0, 0.5, "sweep")
    b = Motion(t, np.full(3, 10.0), np.full(3, 20.0), np.full(3, 30.0), 2.0, 9.0, "random", f_dom=7.0)
    assert a.f_dom == 4.0 and b.f_dom == 7.0
    c = a + b
    assert (c.x.tolist(), c.xd.tolist(), c.xdd.tolist()) == ([11.0] * 3, [22.0] * 3, [33.0] * 3)
    assert (c.f_max, c.A, c.kind, c.f_dom) == (4.0, 0.5, "sweep", 7.0)


@pytest.mark.parametrize("log,crossings", [(False, 90), (True, 67)])
def test_sweep_cycles_over_the_record_by_hand(log, crossings):
    """A sweep 0.5 → 4 Hz over 20 s runs ∫f dt cycles: linear (0.5 + 4)/2·20 = 45, exponential
    (4 − 0.5)·20/ln 8 = 33.66; x − x0 crosses zero twice a cycle (within 2)."""
    from chainid.records.excitation import sweep

    m = sweep(20_000, 1000.0, 0.5, 4.0, 0.2, 2.0, log=log)
    y = m.x - 2.0
    assert abs(int(np.sum(np.diff(np.sign(y)) != 0)) - crossings) <= 2
    assert m.f_max == 4.0 and m.A == 0.2 and m.kind == "sweep"


def test_startup_levels_step_times_and_running_phase_by_hand():
    """Levels 1, 2, 1.5 mm from x_start = 0 over a 2 s ramp in a 20 s record: the steps (0.5 s each) start at
    2 + (i + 1)·18/3 = 8 and 14 s.  Without vibration (A = 0) x is the mean: 0.5 at 1 s (half the quintic),
    1 before 8 s, 2 after 8.5 s, 1.5 after 14.5 s.  With A = 0.1 mm at 3 Hz, after the ramp
    x − mean = A sin(2π·3·(t − 1 s)) (the phase ∫ of the run-up, half the ramp)."""
    from chainid.records.excitation import startup_steps

    m = startup_steps(20_000, 1000.0, [1.0, 2.0, 1.5], 2.0, 0.5, 3.0, 0.0)
    t = m.t
    at = (lambda s: float(m.x[int(round(s * 1000))]))
    assert (at(1.0), at(7.99), at(8.5), at(13.99), at(14.5), at(19.0)) == pytest.approx(
        (0.5, 1.0, 2.0, 2.0, 1.5, 1.5), abs=1e-12)
    v = startup_steps(20_000, 1000.0, [1.0, 2.0, 1.5], 2.0, 0.5, 3.0, 0.1)
    sel = (t > 2.0) & (t < 7.9)
    np.testing.assert_allclose(v.x[sel] - 1.0, 0.1 * np.sin(2 * np.pi * 3.0 * (t[sel] - 1.0)), atol=1e-9)


def test_envelope_rests_before_the_lead_and_tapers_to_the_mean():
    """``with_envelope``: before the lead-in (1 s) the motion rests at its first value with ẋ = ẍ = 0; with a
    taper of 2 s it starts and ends at the record's mean and is untouched between the tapers."""
    from chainid.records.excitation import sweep, with_envelope

    base = sweep(8000, 400.0, 0.5, 2.0, 0.2, 2.0)
    led = with_envelope(base, lead=1.0)
    pre = base.t < 1.0
    assert np.all(led.x[pre] == base.x[0]) and np.all(led.xd[pre] == 0.0) and np.all(led.xdd[pre] == 0.0)
    tap = with_envelope(base, taper=2.0)
    xm = float(np.mean(base.x))
    assert tap.x[0] == pytest.approx(xm, abs=1e-12) and tap.x[-1] == pytest.approx(xm, abs=1e-12)
    mid = (base.t > 2.0) & (base.t < base.t[-1] - 2.0)
    np.testing.assert_allclose(tap.x[mid], base.x[mid], atol=1e-12)
    np.testing.assert_allclose(tap.xd[mid], base.xd[mid], atol=1e-12)


# --- weak spots of simulate.py: the start at rest and the messages ----------------------------------------------
def test_a_test_without_ramp_starts_at_rest_at_the_mean():
    """No ramp: the first sample (t = 0) is at x0 with ẋ = ẍ = 0, so F(0) = k·x0 = 20000·2.2 N exactly; the next
    sample follows x0 + A sin(ωt)."""
    from stand_ins import LinearSpring

    from chainid.records.simulate import TestSpec, simulate_test

    r = simulate_test(TestSpec("a", 2.0, 2.2, 0.25), LinearSpring(20000.0), 500.0, n_cycles=1, samples_per_cycle=16)
    assert r.x[0] == 2.2 and r.F[0] == 20000.0 * 2.2
    assert r.x[1] == pytest.approx(2.2 + 0.25 * math.sin(2.0 * r.t[1]), abs=1e-15)


def test_simulation_messages_name_the_test_the_value_and_the_range():
    """A non-finite damping, a non-finite force from the hook (its first sample named), a repeated test id, a bad
    memory limit: each one ValueError naming what and where; a compressive force is accepted for a part that is
    not a chain (a linear spring)."""
    from stand_ins import LinearSpring

    from chainid.records.simulate import TestSpec, simulate, simulate_test

    sp = TestSpec("a", 2.0, 2.2, 0.25)
    with pytest.raises(ValueError, match=r"^test 'a': the damping law gives c_e = inf N·s/mm at omega = 2 rad/s, "
                                         r"A = 0\.25 mm, x0 = 2\.2 mm: valid range finite"):
        simulate_test(sp, LinearSpring(20000.0), float("inf"))

    def hook(t, x, xd, xdd, F):
        F = F.copy()
        F[5:] = np.nan
        return F

    r = simulate_test(sp, LinearSpring(20000.0), 0.0, n_cycles=1, samples_per_cycle=16)
    with pytest.raises(ValueError, match=rf"^test 'a': the simulated force is nan N at t = {r.t[5]:.6g} s "
                                         rf"\(x = {r.x[5]:.6g} mm\): valid range finite"):
        simulate_test(sp, LinearSpring(20000.0), 0.0, n_cycles=1, samples_per_cycle=16, force_fn=hook)
    with pytest.raises(ValueError, match=r"^plan: test id 'a' is repeated; test ids must be unique$"):
        simulate([sp, TestSpec("a", 3.0, 2.2, 0.25)], LinearSpring(20000.0), 0.0)
    for bad in (0, -1.0, float("nan"), "1"):
        with pytest.raises(ValueError, match=rf"^max_memory = {bad!r} bytes is invalid: valid range > 0 \(or None\)$"):
            simulate([sp], LinearSpring(20000.0), 0.0, max_memory=bad)
    deep = simulate([TestSpec("c", 2.0, 0.1, 0.25)], LinearSpring(20000.0), 0.0, max_memory=None, n_cycles=1)
    assert deep[0].F.min() == pytest.approx(20000.0 * (0.1 - 0.25), rel=1e-3)


def test_a_non_finite_motion_force_is_named_as_a_plain_number():
    """``simulate_motion`` with a hook that returns inf from sample 3: "the simulated force is inf N at t = 0.03 s"
    (a plain number, not numpy's ``np.float64(inf)`` repr)."""
    from stand_ins import LinearSpring

    from chainid.records.excitation import simulate_motion, sweep

    m = sweep(200, 100.0, 1.0, 3.0, 0.2, 2.0)

    def hook(t, x, xd, xdd, F):
        F = F.copy()
        F[3:] = np.inf
        return F

    with pytest.raises(ValueError, match=r"^test 'm': the simulated force is inf N at t = 0\.03 s: valid range finite$"):
        simulate_motion("m", m, LinearSpring(20000.0), 0.0, force_fn=hook)


# --- weak spots of spec.py: profiles and overrides ---------------------------------------------------------------
def test_reader_profile_errors_and_role_by_role_overrides(tmp_path):
    """A ``--reader`` profile: a missing file, a file that is not TOML, an unknown key and a bad value are each one
    error naming the option and the file; command-line options replace the profile's roles one by one
    (``--units x=m`` keeps its t and F units), None keeps the profile's value, and ``parse_assignments`` reads
    ``--columns`` digits as 1-based positions and ``--scale`` values as numbers."""
    from chainid.records.spec import ReaderSpec, load_profile, parse_assignments, spec_from_options

    missing = tmp_path / "none.toml"
    with pytest.raises(ValueError, match=rf"^--reader '{missing}': no such profile file$"):
        load_profile(missing)
    bad = tmp_path / "bad.toml"
    bad.write_text("fs = = 3\n", encoding="utf-8")
    with pytest.raises(ValueError, match=rf"^--reader '{bad}': not a TOML file \("):
        load_profile(bad)
    bad.write_text("fs = 100\nrate = 3\n", encoding="utf-8")
    with pytest.raises(ValueError, match=rf"^--reader '{bad}': unknown key\(s\) \['rate'\]; valid keys are "):
        load_profile(bad)
    bad.write_text("fs = -1\n", encoding="utf-8")
    with pytest.raises(ValueError, match=rf"^--reader '{bad}': reader fs = -1 Hz is invalid; valid range fs > 0 Hz$"):
        load_profile(bad)
    prof = tmp_path / "rig.toml"
    prof.write_text('fs = 100\nskip_rows = 2\n[units]\nt = "ms"\nx = "in"\nF = "kN"\n[columns]\nx = "Disp"\n',
                    encoding="utf-8")
    s = spec_from_options(prof, units="x=m", columns="F=3", skip_rows=None)
    assert s.units == {"t": "ms", "x": "m", "F": "kN"} and s.columns == {"x": "Disp", "F": 3}
    assert s.fs == 100.0 and s.skip_rows == 2
    assert parse_assignments("x=2, F=Load", "--columns") == {"x": 2, "F": "Load"}
    assert parse_assignments("x=-1", "--scale", numeric=True) == {"x": -1.0}
    assert parse_assignments(None, "--units") == {}
    assert ReaderSpec().is_default and not ReaderSpec(fs=10.0).is_default
    assert ReaderSpec(fs=10.0).merged(fs=None, units={}).fs == 10.0


def test_record_converts_to_float_arrays_and_refuses_ragged_or_two_dimensional_columns():
    """A Record holds float arrays and a string id; columns of different lengths or of two dimensions are one
    error naming the test and the lengths."""
    r = Record(7, [0, 1, 2], [1, 2, 3], [4, 5, 6])
    assert r.test == "7" and r.t.dtype == r.x.dtype == r.F.dtype == np.float64
    with pytest.raises(ValueError, match=r"^test 'a': t, x and F must have the same length \(got 3, 2, 3\)$"):
        Record("a", [0, 1, 2], [1, 2], [4, 5, 6])
    with pytest.raises(ValueError, match=r"^test 'b': t, x and F must be one-dimensional arrays$"):
        Record("b", np.zeros((2, 2)), np.zeros((2, 2)), np.zeros((2, 2)))


def test_taper_of_a_two_second_period_by_hand():
    """Linear taper of 1 period of T = 2 s in and out of 6 periods (12 s): e(τ) = min(τ/2, (12 − τ)/2, 1), so
    e = 0.5, 1, 0.5, 0.25 at τ = 1, 6, 11, 11.5 s with slopes +1/2, 0, −1/2, −1/2 per s.  Bug caught: the ramp
    down ``(T_tot − τ) / T_t`` → ``** T_t`` (the older test's T_t = 1 s, where both agree)."""
    from chainid.records.simulate import _envelope

    e, de = _envelope(np.array([1.0, 6.0, 11.0, 11.5]), 2.0, 6, 1.0)
    np.testing.assert_allclose(e, [0.5, 1.0, 0.5, 0.25], rtol=1e-15)
    np.testing.assert_allclose(de, [0.5, 0.0, -0.5, -0.5], rtol=1e-15)


# --- weak spots of formats.py: where the tables of a container are and what they are called -------------------
def test_container_tables_their_places_and_test_ids():
    """A nested container (JSON-like dicts and lists) holds one table wherever an x and an F column sit side by
    side: a list of tables gets ids ``<file id>_1, _2``; a dict of tables (keyed) its keys; a single table no id (the
    file's); a scalar ``test`` beside the arrays names it; nested names ``group/name`` reach into groups.
    Positions are refused, and a container without the columns names its top-level keys.  MATLAB's (1, N) and
    (N, 1) vectors become (N,)."""
    from chainid.records.formats import _squeeze, _tables
    from chainid.records.spec import ReaderSpec

    S = ReaderSpec()
    a = {"t": [0, 1], "x": [1, 2], "F": [3, 4]}

    def ids(obj, keyed=False, spec=S):
        return [(tb.source, tb.test, list(tb.columns)) for tb in _tables(obj, "f.json", spec, "stem", keyed)]

    assert ids([a, a]) == [("f.json[0]", "stem_1", ["t", "x", "F"]), ("f.json[1]", "stem_2", ["t", "x", "F"])]
    assert ids({"A": a, "B": a}, keyed=True) == [("f.json/A", "A", ["t", "x", "F"]), ("f.json/B", "B", ["t", "x", "F"])]
    assert ids(a) == [("f.json", None, ["t", "x", "F"])]
    assert ids({"test": "T9", **a}) == [("f.json", "T9", ["t", "x", "F"])]
    assert ids({"run": {"data": a}}) == [("f.json/run/data", None, ["t", "x", "F"])]
    nested = ReaderSpec(columns={"x": "g/disp", "F": "g/load"})
    assert _tables({"g": {"disp": [1, 2], "load": [3, 4]}}, "f.json", nested, "s", False)[0].columns == \
        {"g/disp": [1, 2], "g/load": [3, 4]}
    with pytest.raises(ValueError, match=r"^f\.json: no 'x' and 'F' columns found \(top level: \['q'\]\); name them "
                                         r"with --columns x=NAME,F=NAME$"):
        _tables({"q": 1}, "f.json", S, "stem", False)
    with pytest.raises(ValueError, match=r"^f\.json: --columns x=2: positions are for headerless text files"):
        _tables(a, "f.json", ReaderSpec(columns={"x": 2}), "stem", False)
    assert [_squeeze(np.zeros(s)).shape for s in ((1, 3), (3, 1), (2, 3))] == [(3,), (3,), (2, 3)]
