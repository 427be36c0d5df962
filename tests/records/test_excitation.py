"""Excitation programs (chainid.records.excitation) against closed forms: sweeps, band-limited random lines,
earthquakes (Kanai–Tajimi × Clough–Penzien), start-up steps, envelopes, exact derivatives, and the simulated force
with its quantisation.  Units s, mm, N, Hz."""
from __future__ import annotations

import math
import re

import numpy as np
import pytest

from chainid.records import excitation as ex
from chainid.records.excitation import band_random, earthquake, sweep

from spectral_forms import earthquake_band_ratio, kt_cp_displacement


@pytest.mark.slow
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


def test_the_taper_is_the_quintic_step_in_from_the_first_sample_and_out_to_the_last():
    """Taper τ = 2 s on a 20 s sweep: x − x̄ = s(t/τ)·s((T − t)/τ)·(x_base − x̄), s(u) = 10u³ − 15u⁴ + 6u⁵ on
    [0, 1] by hand and T the last sample's time, at every sample (to 1e-12 mm, rounding of x ~ 2 mm): the taper
    ends on the last sample, so the one before it keeps s(Δt/τ) of its swing (3e-10 mm here), not 0."""
    from chainid.records.excitation import sweep, with_envelope

    base = sweep(8000, 400.0, 0.5, 2.0, 0.2, 2.0)
    tap = with_envelope(base, taper=2.0)
    xm = float(np.mean(base.x))

    def s(u):
        u = np.clip(u, 0.0, 1.0)
        return 10 * u**3 - 15 * u**4 + 6 * u**5

    t, T = base.t, base.t[-1]
    want = s(t / 2.0) * s((T - t) / 2.0)
    np.testing.assert_allclose(tap.x - xm, want * (base.x - xm), rtol=0, atol=1e-12)
    assert abs(want[-2] * (base.x[-2] - xm)) > 1e-10


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


def _fd(m):
    """Central differences of x and ẋ (an independent check of the exact derivatives), interior samples."""
    dt = m.t[1] - m.t[0]
    return (m.x[2:] - m.x[:-2]) / (2 * dt), (m.xd[2:] - m.xd[:-2]) / (2 * dt)


@pytest.mark.parametrize("kind", ["random", "sweep", "startup", "quake", "enveloped"])
def test_excitation_derivatives_are_exact(kind):
    rng = np.random.default_rng(3)
    m = {"random": lambda: ex.band_random(4000, 400.0, 0.2, 2.0, 0.1, 2.0, rng, wander=0.05),
         "sweep": lambda: ex.sweep(4000, 400.0, 0.3, 3.0, 0.2, 2.0, log=True),
         "startup": lambda: ex.startup_steps(4000, 400.0, [1.8, 2.2, 1.9], 3.0, 0.8, 2.0, 0.1, 0.5),
         "quake": lambda: ex.earthquake(4000, 400.0, 0.3, 2.0, rng, f_g=2.0, pulse=1.0, offset=0.2),
         "enveloped": lambda: ex.with_envelope(ex.sweep(4000, 400.0, 0.5, 2.0, 0.2, 2.0), lead=1.0, taper=2.0)}[kind]()
    v, a = _fd(m)
    # central differences err by h²/6·x''' : < 1 % of the peak at >= 100 samples per period of the band edge
    assert np.max(np.abs(v - m.xd[1:-1])) <= 0.01 * np.max(np.abs(m.xd))
    assert np.max(np.abs(a - m.xdd[1:-1])) <= 0.02 * np.max(np.abs(m.xdd))


def test_excitation_closed_forms():
    rng = np.random.default_rng(4)
    # a linear sweep 0.5 -> 2.5 Hz over 20 s: zero crossings of x − x0 in the first and last 4 s give the
    # instantaneous frequency at 2 s and 18 s: 0.5 + 0.1·t Hz
    m = ex.sweep(20000, 1000.0, 0.5, 2.5, 0.2, 2.0)
    y = m.x - 2.0
    for t_mid in (2.0, 18.0):
        sel = np.abs(m.t - t_mid) <= 2.0
        n_cross = np.sum(np.diff(np.sign(y[sel])) != 0)
        assert n_cross / (2 * 4.0) == pytest.approx(0.5 + 0.1 * t_mid, rel=0.15)
    # band-limited random: RMS as asked, no power outside the band
    r = ex.band_random(8000, 200.0, 0.5, 3.0, 0.1, 2.0, rng)
    assert np.std(r.x) == pytest.approx(0.1, rel=1e-9)
    P = np.abs(np.fft.rfft(r.x - r.x.mean())) ** 2
    f = np.fft.rfftfreq(r.x.size, 1 / 200.0)
    assert P[(f < 0.45) | (f > 3.05)].sum() <= 1e-12 * P.sum()
    # earthquake: peak |x − x0| as asked; starts and ends near rest (envelope)
    q = ex.earthquake(6000, 200.0, 0.3, 2.0, rng)
    assert np.max(np.abs(q.x - 2.0)) == pytest.approx(0.3, rel=1e-9)
    assert abs(q.x[0] - 2.0) < 0.01 * 0.3 and np.max(np.abs(q.x[-200:] - 2.0)) < 0.25 * 0.3
    # start-up: the mean reaches the last level; the running frequency is f_run after the ramp
    s = ex.startup_steps(8000, 400.0, [1.8, 2.2], 4.0, 0.5, 2.0, 0.1, 0.5)
    assert s.x[0] == pytest.approx(0.5) and np.mean(s.x[-800:]) == pytest.approx(2.2, abs=0.02)
    with pytest.raises(ValueError, match="fs/2"):
        ex.sweep(1000, 10.0, 0.5, 6.0, 0.1, 2.0)


def test_earthquake_spectrum_slope_is_kanai_tajimi_clough_penzien():
    """Between f_c = 0.2 Hz and f_g = 2 Hz the Clough–Penzien |H|² is about 1 and the displacement (acceleration
    over ω²) falls as about f⁻², raised a little by the Kanai–Tajimi peak at f_g: the log-log slope of the
    generated displacement's amplitude spectrum over 0.3–2 Hz matches that of the closed form within 0.25
    (a high-pass of another order tilts it by a whole unit). Measured over seeds 5–12: within 0.13."""
    band = (0.3, 2.0)
    fs, T = 8.0, 960.0  # a long record: the envelope smears the random-phase spectrum over fewer bins
    n = int(fs * T)
    rng = np.random.default_rng(6)
    m = earthquake(n, fs, 10.0, 0.0, rng, f_hi=3.0)
    X = np.abs(np.fft.rfft(m.x))
    f = np.fft.rfftfreq(n, 1 / fs)
    sel = (f >= band[0]) & (f <= band[1])
    slope = np.polyfit(np.log(f[sel]), np.log(X[sel]), 1)[0]
    ref = np.polyfit(np.log(f[sel]), np.log(kt_cp_displacement(f[sel])), 1)[0]
    assert slope == pytest.approx(ref, abs=0.25)
    assert float(np.max(np.abs(m.x))) == pytest.approx(10.0, rel=1e-9)  # scaled to the peak


@pytest.mark.slow
def test_earthquake_clough_penzien_corner_by_band_power():
    """Power of the displacement in 0.15–0.35 Hz (around the Clough–Penzien corner f_c = 0.2 Hz) over that in
    0.8–1.6 Hz, averaged over six records, against the same ratio of the textbook KT × CP form: within a factor
    1.6 (measured over seeds 0–29 in groups of six: 0.75–1.13). A corner of another shape or damping moves it by
    an order of magnitude."""
    ratio = earthquake_band_ratio(8.0, 480.0, range(18, 24), 3.0, (0.15, 0.35), (0.8, 1.6))
    assert ratio == pytest.approx(1.0, abs=0.6)


def test_excitation_band_errors_name_the_nyquist_frequency():
    from chainid.records.excitation import band_random

    rng = np.random.default_rng(0)
    with pytest.raises(ValueError, match=r"band \[1, 60\] Hz is invalid: valid range 0 < f_lo < f_hi < fs/2 = 50$"):
        band_random(1000, 100.0, 1, 60, 0.1, 2.0, rng)
    with pytest.raises(ValueError, match=r"band \[1, 1.5\] Hz holds 1 line\(s\) over 1 s: valid range >= 2 lines"):
        band_random(100, 100.0, 1, 1.5, 0.1, 2.0, rng)
    with pytest.raises(ValueError, match=r"f_c = 2.0, f_g = 2.0, f_hi = 10.0 Hz invalid: .* fs/2 = 50"):
        earthquake(1000, 100.0, 1.0, 0.0, rng, f_c=2.0)


def test_simulate_motion_force_and_quantisation_by_hand():
    """F = m·ẍ + F_k(x) + c·ẋ of a linear spring (mass 2 kg: m·ẍ in N with ẍ in mm/s² is 1e-3 m ẍ), then
    rounded to the force quantum: every force a multiple of it, within half a quantum of the exact one."""
    from chainid.model.base import LinearModel
    from chainid.records.excitation import simulate_motion, sweep

    m = sweep(2000, 100.0, 0.5, 2.0, 0.3, 2.0)
    spring = LinearModel(k=150.0, x_ref=1.0, mass=2.0)
    exact = 2.0 * m.xdd * 1e-3 + 150.0 * (m.x - 1.0) + 40.0 * m.xd
    r = simulate_motion("s", m, spring, 40.0)
    np.testing.assert_allclose(r.F, exact, rtol=1e-12, atol=1e-9)
    q = simulate_motion("q", m, spring, 40.0, quantum_F=0.5)
    np.testing.assert_allclose(q.F / 0.5, np.round(q.F / 0.5), atol=1e-9)
    assert np.max(np.abs(q.F - exact)) <= 0.25 + 1e-9
    assert np.ptp(q.F) > 100  # the quantum does not flatten the signal
    np.testing.assert_array_equal(q.x, m.x)
    np.testing.assert_array_equal(q.t, m.t)


# --- seed-22 mutation survivors (issue 20 §5) ------------------------------------------------------------------
@pytest.mark.parametrize("n", [63, 10, 64.0, 100.0, "128"])
def test_generators_refuse_fewer_than_64_or_a_non_integer_sample_count(n):
    """The excitation generators take n as an integer >= 64 (the message names n, the value and the range); 64
    itself is accepted.  Bug caught: ``isinstance(n, int) and n >= 64`` → ``or`` (63 or 64.0 accepted)."""
    from chainid.records.excitation import sweep

    with pytest.raises(ValueError, match=rf"n = {re.escape(repr(n))} samples is invalid: valid range integer >= 64"):
        sweep(n, 100.0, 1.0, 2.0, 0.5, 3.0)
    m = sweep(64, 100.0, 1.0, 2.0, 0.5, 3.0)
    assert m.t.size == 64 and m.t[-1] == pytest.approx(63 / 100.0, rel=1e-15)
    assert m.x[0] == pytest.approx(3.0, abs=1e-12)  # x0 + A sin(0)


@pytest.mark.slow
def test_earthquake_above_the_ground_frequency_keeps_the_kanai_tajimi_numerator():
    """Above f_g the Kanai–Tajimi |H|² falls as (1 + 4ζ²r)/r² (r = (f/f_g)²), not as 1/r²: the power of the
    displacement in 4–8 Hz over that in 0.8–1.6 Hz (f_g = 2 Hz, ζ = 0.5, six records normalised and summed)
    against the same ratio of the textbook KT × CP form, within a factor 1.6 (measured over seeds 0–47 in
    groups of six: 0.89–1.28).  Bug caught: ``4ζ²·r`` → ``4ζ² % r`` in the numerator (the ratio drops ~5×)."""
    from spectral_forms import earthquake_band_ratio

    ratio = earthquake_band_ratio(24.0, 120.0, range(6, 12), 10.0, (4.0, 8.0), (0.8, 1.6))
    assert ratio == pytest.approx(1.0, abs=0.6)


def test_band_random_wander_lines_are_below_a_quarter_of_the_band():
    """``wander``: a slow wander of RMS ``wander`` mm on lines 1/T … M/T, M = max(2, ⌊f_lo·T/4⌋) (below f_lo/4).
    The same seed with and without wander differs by exactly that wander: on FFT bins (the lines are bins of the
    record) its power is on bins 1..M only, and its RMS is 0.2 mm.  f_lo = 1 Hz, T = 40 s: M = 10.  Bug caught:
    the line count ``M + 1`` → ``M << 1`` (lines up to 2M − 1)."""
    from chainid.records.excitation import band_random

    n, fs = 4000, 100.0
    a = band_random(n, fs, 1.0, 5.0, 1.0, 0.0, np.random.default_rng(4))
    b = band_random(n, fs, 1.0, 5.0, 1.0, 0.0, np.random.default_rng(4), wander=0.2)
    d = b.x - a.x
    P = np.abs(np.fft.rfft(d)) ** 2
    assert P[11:].sum() < 1e-20 * P[1:11].sum() and (P[1:11] > 0).all()
    assert float(np.std(d)) == pytest.approx(0.2, rel=1e-9)


def test_startup_ramp_must_end_inside_the_record():
    """start-up steps: 0 < t_ramp < record length T = n/fs (strict): t_ramp = T is refused with the range, just
    under T is accepted.  Bug caught: ``t_ramp < T`` → ``<=``."""
    from chainid.records.excitation import startup_steps

    n, fs = 200, 20.0  # T = 10 s
    with pytest.raises(ValueError, match=r"t_ramp = 10.0 s, .* valid range 0 < t_ramp < record length 10 s"):
        startup_steps(n, fs, [1.0], 10.0, 1.0, 1.0, 0.5)
    m = startup_steps(n, fs, [1.0], 9.5, 1.0, 1.0, 0.5)
    assert m.t.size == n
    with pytest.raises(ValueError, match=r"t_ramp = 0.0 s, .* valid range 0 < t_ramp"):  # no ramp: refused too
        startup_steps(n, fs, [1.0], 0.0, 1.0, 1.0, 0.5)


def test_band_random_lines_fill_the_band_flat_and_scale_to_the_rms():
    """``band_random``: equal-amplitude lines at k/T on [f_lo, f_hi] (FFT bins 40..200 for 1–5 Hz over 40 s),
    nothing outside; scaled to the RMS about x0; the Motion's amplitude A = √2·rms (a sine of that RMS).  Bugs
    caught: the lines ``k / T`` → ``k // T``; ``√2·rms`` → ``√2 / rms``."""
    from chainid.records.excitation import band_random

    n, fs, rms = 4000, 100.0, 2.0
    m = band_random(n, fs, 1.0, 5.0, rms, 3.0, np.random.default_rng(5))
    X = np.abs(np.fft.rfft(m.x - 3.0))
    inside = X[40:201]
    np.testing.assert_allclose(inside, inside.mean(), rtol=1e-8)
    assert X[:40].max() < 1e-8 * inside.mean() and X[201:].max() < 1e-8 * inside.mean()
    assert float(np.std(m.x)) == pytest.approx(rms, rel=1e-12) and float(np.mean(m.x)) == pytest.approx(3.0, abs=1e-9)
    assert m.A == pytest.approx(math.sqrt(2) * rms, rel=1e-15) and m.kind == "random" and m.f_max == 5.0


def test_exponential_sweep_acceleration_is_the_second_derivative_where_the_sweep_rate_dominates():
    """x = A sin φ with φ' = 2π f0 e^{rt}: ẍ = A(φ'' cos φ − φ'² sin φ) with φ'' = r·φ'.  From 0.05 to 5 Hz in
    2 s (r = ln 100 / 2 = 2.3 /s) the first half second has φ'' (0.7 /s²) above φ'² (0.1 /s²): a central
    difference at 20 kHz (error h²/12·x'''' < 1e-9 mm/s²) against ẍ within 1e-4 of its peak there.
    Bug caught: ``dw = w * r`` → ``w ** r`` (the sweep-rate term 0.7 → 0.07)."""
    fs = 20_000.0
    m = sweep(40_000, fs, 0.05, 5.0, 1.0, 0.0, log=True)
    h = 1.0 / fs
    a_fd = (m.x[2:] - 2 * m.x[1:-1] + m.x[:-2]) / h**2
    sel = m.t[1:-1] < 0.5
    peak = np.max(np.abs(m.xdd[1:-1][sel]))
    assert peak > 0.5  # the sweep-rate term is there: φ''·A = 2π·0.05·2.3 = 0.72 mm/s² at t = 0
    assert np.max(np.abs(a_fd[sel] - m.xdd[1:-1][sel])) <= 1e-4 * peak


@pytest.mark.slow
def test_earthquake_below_the_corner_follows_the_clough_penzien_high_pass():
    """Below f_c = 0.2 Hz the Clough–Penzien |H|² = r²/((1 − r)² + 4·0.7²·r), r = (f/f_c)², removes the drift of
    a doubly integrated ground motion.  The displacement power in 0.04–0.1 Hz over that in 0.3–0.6 Hz (six
    records of 960 s normalised and summed) against the same ratio of the textbook KT × CP form, within a
    factor 1.6 (measured over seeds 0–47 in groups of six: 0.93–1.26).  Bug caught: r = (f/f_c)² →
    (f/f_c)¹ (the ratio grows 11×)."""
    from spectral_forms import earthquake_band_ratio

    assert 1 / 1.6 <= earthquake_band_ratio(8.0, 960.0, range(6), 3.0, (0.04, 0.1), (0.3, 0.6)) <= 1.6


@pytest.mark.parametrize("f_lo, f_hi", [(2.0, 1.0), (1.0, 1.0)])
def test_band_random_refuses_a_band_out_of_order_by_its_own_rule(f_lo, f_hi):
    """The documented range is 0 < f_lo < f_hi < fs/2: a reversed or empty band is refused as such (not as
    'holds 0 lines').  Bug caught: ``f_lo < f_hi`` → ``f_lo != f_hi`` (a reversed band got the line count's
    message)."""
    with pytest.raises(ValueError, match=re.escape(f"band [{f_lo}, {f_hi}] Hz is invalid: valid range "
                                                   "0 < f_lo < f_hi < fs/2 = 50")):
        band_random(1000, 100.0, f_lo, f_hi, 0.1, 0.0, np.random.default_rng(0))


def test_linear_sweep_acceleration_closed_form():
    """Linear sweep 1 → 21 Hz over 4 s (k = 5 Hz/s), A = 0.5 mm: φ = 2π(f0·t + k·t²/2), so
    ẍ = A·(2π·k·cos φ − (2π(f0 + k·t))²·sin φ) (hand), to 1e-9 of its largest value; the sweep-rate term
    A·2π·k = 15.7 mm/s² is what the check sees near the start (there ω²A = 19.7 mm/s²).  Bug caught (seed 27):
    ``2 * np.pi * k`` → ``2 % np.pi * k`` (φ'' = 2k instead of 2πk)."""
    m = sweep(4000, 1000.0, 1.0, 21.0, 0.5, 2.0)
    t = np.arange(4000) / 1000.0
    ph = 2 * np.pi * (1.0 * t + 0.5 * 5.0 * t * t)
    want = 0.5 * (2 * np.pi * 5.0 * np.cos(ph) - (2 * np.pi * (1.0 + 5.0 * t)) ** 2 * np.sin(ph))
    np.testing.assert_allclose(m.xdd, want, rtol=0, atol=1e-9 * np.max(np.abs(want)))


@pytest.mark.parametrize("fs", [0.0, -0.5, float("nan"), float("inf")])
def test_a_sampling_rate_that_is_not_positive_and_finite_is_refused(fs):
    """``fs`` must be finite and > 0 (a zero rate gives infinite times, a negative one times running backwards);
    the message names the value and the range.  Bug caught: ``fs > 0`` → ``fs > -1`` (0 and -0.5 passed)."""
    from chainid.records.excitation import sweep

    with pytest.raises(ValueError, match=rf"^fs = {re.escape(repr(fs))} Hz is invalid: valid range > 0$"):
        sweep(1000, fs, 0.5, 2.0, 1.0, 5.0)
