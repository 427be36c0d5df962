"""records pins from the blind mutation run of seed 23 (issue 20 §5): the exponential sweep's acceleration, the
Clough–Penzien high-pass below its corner, the random band's order, and the two fast readers' own contracts
(each checked against a finite difference, the textbook spectrum, the documented message or the docstring).
Units: mm, N, s, Hz.
"""
from __future__ import annotations

import math
import re

import numpy as np
import pytest

from chainid.records.excitation import band_random, sweep


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


def test_canonical_csv_fast_path_returns_views_of_one_array(tmp_path):
    """``read_canonical_csv``'s docstring: with the header on line 1, the arrays of all tests are views into three
    arrays of the whole file (the pyarrow path; the strict reader makes one array per test).  Two tests of
    3 rows: both t arrays share one base, and the numbers are the file's.  Bug caught: the line-1 header test
    inverted (``not line.strip()`` → ``line.strip()``: every file went to the strict reader)."""
    pytest.importorskip("pyarrow")
    from chainid.records.textcanon import read_canonical_csv

    p = tmp_path / "r.csv"
    rows = [("a", 0.0, 1.0, 10.0), ("a", 0.1, 1.5, 12.0), ("a", 0.2, 2.0, 14.0),
            ("b", 0.0, 3.0, 30.0), ("b", 0.1, 3.5, 32.0), ("b", 0.2, 4.0, 34.0)]
    p.write_text("test,t,x,F\n" + "".join(f"{a},{b!r},{c!r},{d!r}\n" for a, b, c, d in rows))
    recs = read_canonical_csv(p)
    assert [r.test for r in recs] == ["a", "b"]
    assert recs[1].x.tolist() == [3.0, 3.5, 4.0] and recs[0].F.tolist() == [10.0, 12.0, 14.0]
    assert recs[0].t.base is not None and recs[0].t.base is recs[1].t.base


def test_whitespace_fast_path_skips_a_preamble_to_the_data_line(tmp_path):
    """A whitespace logger file with two preamble lines (``skip_rows = 2``) and a header (data from line 4) is read
    by the fast path (numpy's loadtxt skipping data_line − 1 = 3 lines), with the same numbers as the
    line-by-line scan.  Bug caught: ``skiprows = data_line − 1`` → ``data_line >> 1`` (1 line skipped: the header is read as data and
    the file left to the scan)."""
    from reader_paths import fast_and_scan

    from chainid.records.spec import ReaderSpec

    p = tmp_path / "log.txt"
    rows = [(0.01 * i, 1.0 + 0.1 * i, -3.5e2 + i / 3) for i in range(40)]
    p.write_text("logger TX-9 serial 4411\nrate 100 Hz\nt  x  F\n" + "".join("  ".join(repr(v) for v in r) + "\n"
                                                                             for r in rows))
    lay, fast, slow = fast_and_scan(p, ReaderSpec(skip_rows=2))
    assert lay.data_line == 4 and lay.names == ["t", "x", "F"]
    assert fast is not None
    for k, j in (("t", 0), ("x", 1), ("F", 2)):
        assert fast[k].tolist() == slow[k].tolist() == [r[j] for r in rows]
    assert math.isclose(fast["F"][-1], -3.5e2 + 39 / 3)


# ---------------------------------------------------------------- survivors of the seed-24 check (records)
def Record_(*a):  # noqa: N802
    from chainid.records.record import Record

    return Record(*a)


def test_a_force_under_a_ten_thousandth_of_the_working_load_is_named():
    """``chain_warnings``: a largest force under 1/10000 of the chain's working load (kN read as N) is named;
    at 1/20000 it warns, at 1/5000 not (the paper's chain; working load from its practice sheet).  Bug caught:
    ``wl * 1e-4`` → ``wl % 1e-4`` (the threshold ~0: never warned)."""
    from chainid.chain.spec import default_chain
    from chainid.model.practice import chain_practice
    from chainid.records.plausible import chain_warnings

    chain = default_chain()
    wl = chain_practice(chain)["working_load_N"]
    t = np.linspace(0.0, 10.0, 500)
    x = 2.2 + 0.25 * np.sin(2.0 * t)
    for frac, warns in ((1 / 20000, True), (1 / 5000, False)):
        F = wl * frac * (0.6 + 0.4 * np.sin(2.0 * t))
        out = [w for w in chain_warnings([Record_("a", t, x, F)], chain) if "working load" in w]
        assert bool(out) is warns, (frac, out)
        if warns:
            assert out[0].startswith(f"test 'a': the largest force {wl * frac:.3g} N is under 1/10000 of the "
                                     f"chain's working load ({wl:.4g} N)")


# --- seed 24 survivors -----------------------------------------------------------------------------------------
def test_a_motion_at_the_nyquist_frequency_is_named_at_half_the_sampling_rate():
    """x alternating every sample (x = 3 + cos(π n)) at 1 kHz is a 500 Hz motion, 2 samples per cycle: the
    aliasing warning names 500 Hz, exactly fs/2 (its spectrum's last bin).  Bug caught: the bin zeroed before
    the peak search moved from DC to the last one (``spec[0]`` → ``spec[-1]``: the peak becomes the bin next to
    Nyquist, 499 Hz)."""
    from chainid.records.plausible import sampling_warnings
    from chainid.records.record import Record

    n = 1000
    t = np.arange(n) / 1000.0
    x = 3.0 + np.cos(np.pi * np.arange(n))
    (w,) = sampling_warnings([Record("a", t, x, 1000.0 + 100.0 * x)])
    assert "1000 Hz sampling gives 2 samples per cycle of the main frequency 500 Hz " in w


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


def test_white_noise_has_no_main_frequency_and_draws_no_sampling_warning():
    """x white noise at 1 kHz (10 seeds, 2000 samples): no line holds half the power (the peak and its two
    neighbours each side hold about 5 of 1001 equal shares), so there is no main frequency and no sampling
    warning.  Bug caught (seed 25): the power test ``0.5 * power.sum()`` → ``0.5 ** power.sum()`` (≈ 0: the
    largest noise line becomes the main frequency, and 7 of these 10 seeds are called aliased, above fs/4)."""
    from chainid.records.plausible import sampling_warnings
    from chainid.records.record import Record

    t = np.arange(2000) / 1000.0
    for seed in range(10):
        x = 2.2 + 0.1 * np.random.default_rng(seed).standard_normal(t.size)
        assert sampling_warnings([Record("n", t, x, 1000.0 + 10.0 * x)]) == [], seed
