"""Pins of chainid.records helpers to hand numbers (survivors of the mutation run, issue 20 §5).
Units: s, mm."""
from __future__ import annotations

import math
import re

import numpy as np
import pytest

from chainid.records.simulate import _envelope
from chainid.records.validate import _spanned_cycles


def test_taper_envelope_and_slope_by_hand():
    """Linear taper of 1 period (T = 1 s) in and out of 6 periods: e = 0.5, de/dτ = +1 at τ = 0.5; e = 1, 0 at 3;
    e = 0.5, −1 at 5.5.  With 1.5 periods the ramps overlap: at τ = 0.9 the ramp down rules (e = 0.6, slope −1).
    Bugs caught: the ramp-up's condition (τ < T_t) or its tie rule (up <= down) changed."""
    e, de = _envelope(np.array([0.5, 3.0, 5.5]), 1.0, 6, 1.0)
    np.testing.assert_allclose(e, [0.5, 1.0, 0.5], rtol=1e-15)
    np.testing.assert_allclose(de, [1.0, 0.0, -1.0], rtol=1e-15)
    e, de = _envelope(np.array([0.2, 0.75, 0.9]), 1.0, 1.5, 1.0)
    np.testing.assert_allclose(e, [0.2, 0.75, 0.6], rtol=1e-12)
    np.testing.assert_allclose(de, [1.0, 1.0, -1.0], rtol=1e-15)  # at 0.75 up = down: the ramp up (tie rule)
    e, de = _envelope(np.array([0.0, 1.0]), 1.0, 6, 0.0)
    assert e.tolist() == [1.0, 1.0] and de.tolist() == [0.0, 0.0]


def test_spanned_cycles_of_a_pure_sine():
    """x = 3 + sin(2π·0.75·u) over the record: 0.75 periods spanned, R² = 1 (R² = 1 − SS_res/SS_tot with the
    squared deviations).  Bug caught: SS_tot not squared."""
    t = np.linspace(0.0, 2.0, 400)
    u = t / 2.0
    c, r2 = _spanned_cycles(t, 3.0 + np.sin(2 * math.pi * 0.75 * u))
    assert c == pytest.approx(0.75, abs=1e-9) and r2 == pytest.approx(1.0, abs=1e-9)


def test_estimate_memory_by_hand():
    """Two tests of 6 cycles × 200 samples (no ramp): 1200 samples each; kept 24 B each, peak 200 B for the larger:
    2·1200·24 + 1200·200 = 297 600 B; an empty plan needs 0.  Bug caught: the empty-plan guard inverted."""
    from chainid.records.simulate import TestSpec, estimate_memory

    plan = [TestSpec("a", 2.0, 2.0, 0.2), TestSpec("b", 5.0, 2.0, 0.2)]  # (id, omega rad/s, x0 mm, A mm)
    assert estimate_memory(plan, n_cycles=6, samples_per_cycle=200) == pytest.approx(297_600.0, rel=1e-12)
    assert estimate_memory([]) == 0.0


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


@pytest.mark.parametrize("n_cycles,taper,ok", [(8, 4.0, True), (8, 4.001, False), (5, 2.5, True), (5, 2.6, False),
                                               (6, 0.0, True), (6, -0.1, False)])
def test_taper_may_reach_half_the_cycles(n_cycles, taper, ok):
    """The taper (in and out) may take up to n_cycles/2 cycles each, inclusive; beyond, the message names the
    option, the value and the bound n_cycles/2 (4 for 8 cycles, 2.5 for 5).  Bug caught: ``n_cycles / 2`` →
    ``n_cycles & 2`` (8 & 2 = 0: any taper refused)."""
    from chainid.records.simulate import _check_options

    if ok:
        _check_options(n_cycles, 200, None, taper, 0.0, 0.0, None)
    else:
        with pytest.raises(ValueError, match=rf"taper_cycles = {taper!r} is invalid: valid range 0 to "
                                             rf"n_cycles/2 = {n_cycles / 2:g}$"):
            _check_options(n_cycles, 200, None, taper, 0.0, 0.0, None)


def test_earthquake_above_the_ground_frequency_keeps_the_kanai_tajimi_numerator():
    """Above f_g the Kanai–Tajimi |H|² falls as (1 + 4ζ²r)/r² (r = (f/f_g)²), not as 1/r²: the power of the
    displacement in 4–8 Hz over that in 0.8–1.6 Hz (f_g = 2 Hz, ζ = 0.5, six records normalised and summed)
    against the same ratio of the textbook KT × CP form, within a factor 1.6 (measured over seeds 0–47 in
    groups of six: 0.89–1.28).  Bug caught: ``4ζ²·r`` → ``4ζ² % r`` in the numerator (the ratio drops ~5×)."""
    from spectral_forms import earthquake_band_ratio

    ratio = earthquake_band_ratio(24.0, 120.0, range(6, 12), 10.0, (4.0, 8.0), (0.8, 1.6))
    assert ratio == pytest.approx(1.0, abs=0.6)


@pytest.mark.parametrize("delim", [" ", ",", ";"])
def test_a_regular_text_file_is_read_by_the_fast_path_as_by_the_scan(tmp_path, delim):
    """A regular delimited file (whitespace: numpy's loadtxt; else pyarrow) is read by the fast path, which
    gives the same numbers as the line-by-line scan (the other method; both correctly rounded).  Bug caught:
    the fast path made to fail on every file (``loadtxt(..., ndmin=3)`` raises; the scan hid it)."""
    from reader_paths import fast_and_scan

    from chainid.records.spec import ReaderSpec

    p = tmp_path / "r.txt"
    rows = [(0.01 * i, 1.0 + 0.1 * i, -3.5e2 + i / 3) for i in range(50)]
    sep = "  " if delim == " " else delim
    p.write_text(sep.join(["t", "x", "F"]) + "\n" + "".join(sep.join(repr(v) for v in r) + "\n" for r in rows))
    _, fast, slow = fast_and_scan(p, ReaderSpec())
    assert fast is not None
    for k, j in (("t", 0), ("x", 1), ("F", 2)):
        assert fast[k].tolist() == slow[k].tolist() == [r[j] for r in rows]


# --- own-seed (701) mutation survivors -------------------------------------------------------------------------
def test_record_window_is_half_open():
    """``window(t0, t1)`` keeps t0 <= t < t1: t = 0..9 s, window(2, 5) → 2, 3, 4 (x and F alike); window(2.5, 5)
    → 3, 4.  Bug caught: ``t >= t_start`` → ``t == t_start``."""
    from chainid.records.record import Record

    t = np.arange(10.0)
    r = Record("a", t, 10.0 + t, 100.0 * t)
    w = r.window(2.0, 5.0)
    assert w.t.tolist() == [2.0, 3.0, 4.0] and w.x.tolist() == [12.0, 13.0, 14.0]
    assert w.F.tolist() == [200.0, 300.0, 400.0] and w.test == "a"
    assert r.window(2.5, 5.0).t.tolist() == [3.0, 4.0]


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


# --- own-seed (702) mutation survivors -------------------------------------------------------------------------
def test_aliasing_warning_states_samples_per_cycle():
    """A 10 Hz sine sampled at 30 Hz (12 s): 3 samples per cycle, under the 4 that the check asks; the warning
    names 30 Hz, 3 samples per cycle and the 10 Hz main frequency.  Bug caught: ``fs / f`` → ``fs | f``."""
    from chainid.records.plausible import sampling_warnings
    from chainid.records.record import Record

    t = np.arange(360) / 30.0
    x = 2.0 + np.sin(2 * np.pi * 10.0 * t + 0.3)
    w = sampling_warnings([Record("a", t, x, 100.0 * x)])
    assert len(w) == 1
    assert w[0].startswith("test 'a': 30 Hz sampling gives 3 samples per cycle of the main frequency 10 Hz")


def test_startup_ramp_must_end_inside_the_record():
    """start-up steps: 0 < t_ramp < record length T = n/fs (strict): t_ramp = T is refused with the range, just
    under T is accepted.  Bug caught: ``t_ramp < T`` → ``<=``."""
    from chainid.records.excitation import startup_steps

    n, fs = 200, 20.0  # T = 10 s
    with pytest.raises(ValueError, match=r"t_ramp = 10.0 s, .* valid range 0 < t_ramp < record length 10 s"):
        startup_steps(n, fs, [1.0], 10.0, 1.0, 1.0, 0.5)
    m = startup_steps(n, fs, [1.0], 9.5, 1.0, 1.0, 0.5)
    assert m.t.size == n


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


def test_too_few_cycles_message_states_the_period():
    """A clean sine of period 0.5 s over 4 periods, asked for 5: the message gives the period 0.5 s (2π/ω).
    Bug caught: ``2π / ω`` → ``2π ** ω`` (equal only for ω = 1, the other tests' case)."""
    from chainid.records.record import Record
    from chainid.records.validate import validate_record

    t = np.linspace(0, 2.0, 800, endpoint=False)
    x = 2 + 0.3 * np.sin(4 * np.pi * t)
    with pytest.raises(ValueError, match=r"fewer than 5 full cycles .* spans 4 periods of 0\.5 s and has 4 "):
        validate_record(Record("a", t, x, 1000 * x), min_cycles=5)


def test_ragged_row_message_shows_one_field_more_than_the_header(tmp_path):
    """A row with more fields than the header: the message shows the row's first nf + 1 fields (enough to see
    the extra one): a header of 4 fields and a row of 7 (decimal commas) show 'a,0.1,2,5,0'.  Bug caught: ``row[:nf + 1]`` → ``row[:nf // 1]``."""
    from chainid.records.textcanon import read_csv_strict

    p = tmp_path / "r.csv"
    p.write_text("test,t,x,F\na,0,1,2\na,0.1,2,5,0,7,8\n")
    with pytest.raises(ValueError, match=r"line 3: 7 fields but the header has 4 \(test,t,x,F\); .* "
                                         r"\(row starts 'a,0.1,2,5,0'\)"):
        read_csv_strict(p)


def test_memory_refusal_states_the_limit_in_gib():
    """Two tests of 6 × 200 samples need 297 600 B (by hand, see test_estimate_memory_by_hand); with a limit of
    2¹⁷ B the message says 0.000277 GiB needed, over the limit of 0.000122 GiB.  Bug caught: the limit's
    ``/ 1024**3`` → ``/ 1024 + 3``."""
    from chainid.records.simulate import TestSpec, simulate

    plan = [TestSpec("a", 2.0, 2.0, 0.2), TestSpec("b", 5.0, 2.0, 0.2)]
    with pytest.raises(ValueError, match=r"would need about 0\.000277 GiB \(2400 samples; largest: test 'a', "
                                         r"omega = 2 rad/s, 1200 samples\), over the limit of 0\.000122 GiB"):
        simulate(plan, None, 1.0, max_memory=2**17, n_cycles=6, samples_per_cycle=200)


# --- plausibility of the sampling, and the table's row messages (contracts no test stated) ----------------------
def _sine_record(test, f, fs, cycles):
    from chainid.records.record import Record

    t = np.arange(int(round(cycles * fs / f))) / fs
    x = 2.0 + 0.5 * np.sin(2 * np.pi * f * t)
    return Record(test, t, x, 1000.0 * x)


@pytest.mark.parametrize("f,fs,words", [
    (0.005, 1.0, "the main frequency 0.005 Hz (a cycle of 200 s) is implausibly slow"),
    (2000.0, 20000.0, "the main frequency 2000 Hz is implausibly fast for a chain test"),
    (0.02, 1.0, None), (500.0, 20000.0, None), (1.0, 4.0, None),  # inside 0.01–1000 Hz; 4 samples a cycle is enough
])
def test_sampling_warnings_for_implausible_main_frequencies(f, fs, words):
    """The main frequency of a record (a sine on an FFT bin, 10 cycles) is plausible in 0.01–1000 Hz; outside,
    one warning names the test, the frequency (and for a slow one its cycle, 1/f) and the likely unit slip."""
    from chainid.records.plausible import sampling_warnings

    w = sampling_warnings([_sine_record("s", f, fs, 10)])
    if words is None:
        assert w == []
    else:
        assert len(w) == 1 and w[0].startswith(f"test 's': {words}"), w


def test_sampling_above_a_megahertz_is_a_unit_slip():
    """A time step of 1e-7 s (10 MHz, over the 1 MHz limit): one warning naming the step and the rate; a step of
    2 µs (500 kHz) is not warned about."""
    from chainid.records.plausible import sampling_warnings
    from chainid.records.record import Record

    t = np.arange(400) * 1e-7
    x = 2.0 + np.sin(2 * np.pi * 250_000.0 * t)
    w = sampling_warnings([Record("u", t, x, x)])
    assert w == ["test 'u': time step 1e-07 s implies sampling at 1e+07 Hz, above 1e+06 Hz: is t in s while "
                 "declared ms or us (--units t=...)?"]
    t = np.arange(400) * 2e-6
    assert not any("above 1e+06 Hz" in m for m in sampling_warnings([Record("v", t, x, x)]))


def _table(**cols):
    from chainid.records.table import RawTable

    return RawTable("src.csv", {k: np.asarray(v) for k, v in cols.items()}, None, False, None)


def test_table_rows_of_a_test_must_be_contiguous_and_named():
    """Rows 1–2 of test a, 3 of b, 4 of a again: 'row 4: test 'a': rows are not contiguous'; a blank id on row 3:
    'row 3: empty test id' (rows 1-based); contiguous ids give one record per test in file order."""
    from chainid.records.spec import ReaderSpec
    from chainid.records.table import records_from_table

    num = dict(t=[0.0, 0.1, 0.0, 0.2], x=[1.0, 2.0, 3.0, 4.0], F=[5.0, 6.0, 7.0, 8.0])
    with pytest.raises(ValueError, match=r"^src.csv: row 4: test 'a': rows are not contiguous"):
        records_from_table(_table(test=["a", "a", "b", "a"], **num), ReaderSpec(), "f")
    with pytest.raises(ValueError, match=r"^src.csv: row 3: empty test id$"):
        records_from_table(_table(test=["a", "a", " ", "c"], **num), ReaderSpec(), "f")
    recs = records_from_table(_table(test=["b", "b", " a", "a "], **num), ReaderSpec(), "f")
    assert [r.test for r in recs] == ["b", "a"] and recs[1].x.tolist() == [3.0, 4.0]


def test_table_names_the_first_non_finite_value_its_row_and_the_count():
    """x = [1, nan, 2, inf]: 'column 'x' (x) value nan at row 2 (of 4) is not finite (2 such value(s))'."""
    from chainid.records.spec import ReaderSpec
    from chainid.records.table import records_from_table

    tab = _table(t=[0.0, 0.1, 0.2, 0.3], x=[1.0, np.nan, 2.0, np.inf], F=[1.0, 2.0, 3.0, 4.0])
    with pytest.raises(ValueError, match=r"^src.csv: column 'x' \(x\) value nan at row 2 \(of 4\) is not finite "
                                         r"\(2 such value\(s\)\)$"):
        records_from_table(tab, ReaderSpec(), "f")
