"""Records files (chainid.records.files): CSV in and out, validation errors naming line and test, side files,
the harmonic estimate and steady selection of a written record.  Units s, mm, N."""
from __future__ import annotations

import hashlib
import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from chainid.records.files import (
    Record,
    analyse_record,
    estimate_harmonic,
    read_records,
    read_side_file,
    validate_record,
    write_records,
    write_side_file,
)


def harmonic_record(
    test="T1", omega=2.0, x0=2.2, A=0.25, cycles=6.0, spc=200, ramp=None, noise=0.0, seed=0, F0=20000.0, k=20000.0
):
    """x = x0 + A sin(omega (t - t0)) after a ramp; F = F0 + k (x - x0)."""
    T = 2 * math.pi / omega
    t0 = x0 / ramp if ramp else 0.0
    t = np.arange(int(round((t0 + cycles * T) / (T / spc)))) * (T / spc)
    x = np.where(t > t0, x0 + A * np.sin(omega * (t - t0)), (ramp or 0.0) * t if ramp else x0)
    rng = np.random.default_rng(seed)
    xm = x + rng.normal(0, noise, t.size) if noise else x
    return Record(test, t, xm, F0 + k * (x - x0))


def write_csv(path, text):
    path.write_text(text)
    return path


# --------------------------------------------------------------------------- I/O
def test_roundtrip_and_no_overwrite(tmp_path):
    recs = [harmonic_record("A"), harmonic_record("B", omega=3.0)]
    p = tmp_path / "r.csv"
    write_records(p, recs)
    back = read_records(p)
    assert [r.test for r in back] == ["A", "B"]
    for a, b in zip(recs, back):
        np.testing.assert_allclose(b.t, a.t, rtol=1e-8, atol=1e-12)
        np.testing.assert_allclose(b.x, a.x, rtol=1e-8)
        np.testing.assert_allclose(b.F, a.F, rtol=1e-8)
    before = p.read_bytes()
    with pytest.raises(ValueError, match="r.csv.*already exists"):
        write_records(p, recs[:1])
    assert p.read_bytes() == before
    write_records(p, recs[:1], overwrite=True)
    assert [r.test for r in read_records(p)] == ["A"]


def test_read_does_not_modify_file(tmp_path):
    p = tmp_path / "r.csv"
    write_records(p, [harmonic_record("A")])
    h = hashlib.sha256(p.read_bytes()).hexdigest()
    read_records(p)
    assert hashlib.sha256(p.read_bytes()).hexdigest() == h


def test_missing_columns(tmp_path):
    p = write_csv(tmp_path / "m.csv", "test,t,x\nA,0,1\n")
    with pytest.raises(ValueError, match=r"missing column\(s\) \['F'\]"):
        read_records(p)


def test_non_numeric_names_line_and_test(tmp_path):
    p = write_csv(tmp_path / "n.csv", "test,t,x,F\nA,0,1,2\nA,0.1,abc,2\n")
    with pytest.raises(ValueError, match=r"line 3: test 'A': column 'x' value 'abc' is not a number"):
        read_records(p)


def test_nan_names_line_and_test(tmp_path):
    p = write_csv(tmp_path / "nan.csv", "test,t,x,F\nB,0,1,2\nB,0.1,1,nan\n")
    with pytest.raises(ValueError, match=r"line 3: test 'B': column 'F' is NaN"):
        read_records(p)


def test_non_contiguous_rows(tmp_path):
    p = write_csv(tmp_path / "c.csv", "test,t,x,F\nA,0,1,2\nB,0,1,2\nA,0.1,1,2\n")
    with pytest.raises(ValueError, match=r"line 4: test 'A'.*not contiguous"):
        read_records(p, validate=False)


def test_time_not_increasing(tmp_path):
    r = harmonic_record("T")
    r.t[50] = r.t[49]
    p = tmp_path / "t.csv"
    write_records(p, [r])
    with pytest.raises(ValueError, match=r"test 'T': t is not strictly increasing at sample 50"):
        read_records(p)


def test_fewer_than_two_cycles(tmp_path):
    p = tmp_path / "few.csv"
    write_records(p, [harmonic_record("short", cycles=1.6)])
    with pytest.raises(ValueError, match=r"test 'short': fewer than 2 full cycles"):
        read_records(p)


def test_amplitude_below_noise(tmp_path):
    p = tmp_path / "noise.csv"
    write_records(p, [harmonic_record("quiet", A=1e-3, noise=0.01, cycles=8)])
    with pytest.raises(ValueError, match=r"test 'quiet': amplitude below the noise"):
        read_records(p)


def test_compression_optional(tmp_path):
    r = harmonic_record("damper", F0=0.0, k=1000.0)  # force changes sign
    p = tmp_path / "comp.csv"
    write_records(p, [r])
    with pytest.raises(ValueError, match=r"test 'damper': force goes compressive"):
        read_records(p)
    assert read_records(p, allow_compression=True)[0].test == "damper"


def test_empty_and_missing_file(tmp_path):
    with pytest.raises(ValueError, match="does not exist"):
        read_records(tmp_path / "nope.csv")
    p = write_csv(tmp_path / "e.csv", "")
    with pytest.raises(ValueError, match="empty"):
        read_records(p)
    p = write_csv(tmp_path / "h.csv", "test,t,x,F\n")
    with pytest.raises(ValueError, match="no data rows"):
        read_records(p)


# --------------------------------------------------------------------------- estimation
@pytest.mark.parametrize("omega", [0.3141592653589793, 1.884, 10.0, 150.0])
def test_harmonic_estimate_with_ramp_and_noise(omega):
    r = harmonic_record(omega=omega, ramp=0.08973 * max(1.0, omega), noise=1e-3, seed=3)
    est = estimate_harmonic(r.t, r.x)
    # 1e-3 mm noise on ~1000 samples: amplitude/mean errors ~ 1e-3 * sqrt(2/N) ~ 5e-5 mm
    assert est.omega == pytest.approx(omega, rel=2e-4)
    assert est.x0 == pytest.approx(2.2, abs=3e-4)
    assert est.A == pytest.approx(0.25, abs=3e-4)
    assert est.noise == pytest.approx(1e-3, rel=0.15)
    # ramp dropped: window starts after the ramp end plus one cycle
    t0 = 2.2 / (0.08973 * max(1.0, omega))
    T = 2 * math.pi / omega
    assert est.window.t_start >= t0 + T - 0.02 * T
    assert est.window.n_cycles == 5  # 6 whole cycles after the ramp, the first dropped
    assert est.window.t_end - est.window.t_start == pytest.approx(est.window.n_cycles * T, rel=1e-3)


def test_steady_selection_with_taper():
    omega, A = 2.0, 0.25
    T = 2 * math.pi / omega
    t = np.arange(0, 16 * T, T / 100)
    env = np.clip(np.minimum(t / (4 * T), (16 * T - t) / (4 * T)), 0, 1)
    x = 2.2 + A * env * np.sin(omega * t)
    est = estimate_harmonic(t, x)
    w = est.window
    # amplitude full only for t in [4T, 12T]: cycles 4..11 steady; first steady one dropped
    assert w.cycles_kept == list(range(5, 12))
    assert w.t_start == pytest.approx(5 * T, rel=1e-6)
    assert w.t_end == pytest.approx(12 * T, rel=1e-6)
    assert est.A == pytest.approx(A, rel=1e-6)
    assert "cycles 5-11 of" in w.describe()


def test_side_file(tmp_path):
    r = harmonic_record("S", omega=2.0)
    p = tmp_path / "side.csv"
    est = estimate_harmonic(r.t, r.x)
    write_side_file(p, {"S": est})
    side = read_side_file(p)
    assert side["S"][0] == pytest.approx(2.0, rel=1e-6)
    e2 = analyse_record(r, side["S"])
    assert e2.source == "side file"
    assert e2.A == pytest.approx(0.25, rel=1e-6)
    with pytest.raises(ValueError, match="already exists"):
        write_side_file(p, {"S": est})
    bad = write_csv(tmp_path / "bad.csv", "test,omega,x0,A\nS,-1,2,0.2\n")
    with pytest.raises(ValueError, match=r"test 'S': omega = -1.0 rad/s must be > 0"):
        read_side_file(bad)
    bad = write_csv(tmp_path / "bad2.csv", "test,omega,x0\nS,1,2\n")
    with pytest.raises(ValueError, match=r"missing column"):
        read_side_file(bad)


def test_validate_nan_in_memory():
    r = harmonic_record("M")
    r.x[10] = np.nan
    with pytest.raises(ValueError, match=r"test 'M': column 'x' has a NaN"):
        validate_record(r)


@pytest.mark.slow
@settings(max_examples=40, deadline=None)
@given(
    logw=st.floats(-1.0, 2.5),
    A=st.floats(0.02, 1.0),
    x0=st.floats(0.5, 5.0),
    cycles=st.integers(3, 10),
    ramp_periods=st.one_of(st.none(), st.floats(0.2, 4.0)),
    spc=st.integers(20, 300),
)
def test_estimate_property(logw, A, x0, cycles, ramp_periods, spc):
    omega = 10.0**logw
    T = 2 * math.pi / omega
    ramp = None if ramp_periods is None else x0 / (ramp_periods * T)
    r = harmonic_record(omega=omega, x0=x0, A=A, cycles=cycles, spc=spc, ramp=ramp)
    est = estimate_harmonic(r.t, r.x)
    assert est.omega == pytest.approx(omega, rel=1e-6)
    assert est.A == pytest.approx(A, rel=1e-6)
    assert est.x0 == pytest.approx(x0, abs=1e-6 * A)
    assert est.window.n_cycles >= cycles - 1  # all whole cycles after the ramp, the first dropped


# --------------------------------------------------------------------------- reader strictness (issue 13 item 2)
def _clean_csv_text(n_cycles=6):
    r = harmonic_record("T1", cycles=n_cycles)
    lines = ["test,t,x,F"] + [f"T1,{a:.9g},{b:.9g},{c:.9g}" for a, b, c in zip(r.t, r.x, r.F)]
    return lines


def test_decimal_comma_row_is_an_error_naming_file_line_and_counts(tmp_path):
    lines = _clean_csv_text()
    # line 51 of the file (header = line 1): F written with a decimal comma -> 5 fields
    parts = lines[50].split(",")
    lines[50] = ",".join(parts[:3]) + ",261,004688"
    p = write_csv(tmp_path / "comma.csv", "\n".join(lines) + "\n")
    with pytest.raises(ValueError, match=r"comma\.csv, line 51: 5 fields but the header has 4"):
        read_records(p)


def test_short_row_is_an_error(tmp_path):
    lines = _clean_csv_text()
    lines[9] = "T1,0.5,2.2"
    p = write_csv(tmp_path / "short.csv", "\n".join(lines) + "\n")
    with pytest.raises(ValueError, match=r"short\.csv, line 10: 3 fields but the header has 4"):
        read_records(p)


def test_utf8_bom_accepted(tmp_path):
    lines = _clean_csv_text()
    p = tmp_path / "bom.csv"
    p.write_bytes(b"\xef\xbb\xbf" + ("\n".join(lines) + "\n").encode())
    plain = write_csv(tmp_path / "plain.csv", "\n".join(lines) + "\n")
    a, b = read_records(p)[0], read_records(plain)[0]
    assert a.test == "T1"
    assert np.array_equal(a.x, b.x) and np.array_equal(a.F, b.F)
    assert a.t.size == len(lines) - 1


@pytest.mark.parametrize("payload", [bytes(range(256)) * 40, b"\x89PNG\r\n\x1a\n" + b"\x00" * 500])
def test_garbage_file_names_the_file(tmp_path, payload):
    p = tmp_path / "garbage.bin"
    p.write_bytes(payload)
    with pytest.raises(ValueError, match=r"garbage\.bin"):
        read_records(p)


def test_less_than_one_cycle_says_so(tmp_path):
    p = tmp_path / "part.csv"
    write_records(p, [harmonic_record("part", cycles=0.7)])
    with pytest.raises(ValueError, match=r"test 'part': less than one whole cycle"):
        read_records(p)


def test_side_file_round_trip_and_bounds(tmp_path):
    from types import SimpleNamespace

    from chainid.records.files import read_side_file, write_side_file

    est = {"a": SimpleNamespace(omega=1.0 / 3.0, x0=2.2, A=0.25), "b": SimpleNamespace(omega=2.0, x0=0.0, A=1e-3)}
    p = write_side_file(tmp_path / "s.csv", est)
    assert p.read_text().splitlines() == ["test,omega,x0,A", "a,0.3333333333,2.2,0.25", "b,2,0,0.001"]
    assert read_side_file(p) == {"a": (0.3333333333, 2.2, 0.25), "b": (2.0, 0.0, 0.001)}
    for body, words in (("1,0,2.2,0.25", r"line 2: test '1': omega = 0.0 rad/s must be > 0"),
                        ("1,1,2.2,0", r"line 2: test '1': A = 0.0 mm must be > 0"),
                        ("1,1,2.2,0.2\n2,1,2,1\n1,1,2.2,0.3", r"line 4: test '1' appears twice \(line 2 too\)")):
        q = tmp_path / "bad.csv"
        q.write_text("test,omega,x0,A\n" + body + "\n")
        with pytest.raises(ValueError, match=words):
            read_side_file(q)
    q.write_text("test,omega,A\n1,1,1\n")
    with pytest.raises(ValueError, match=r"missing column\(s\) \['x0'\]; required test,omega,x0,A"):
        read_side_file(q)
    with pytest.raises(ValueError, match="does not exist"):
        read_side_file(tmp_path / "none.csv")
