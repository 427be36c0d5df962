"""The CSV float kernel (chainid.infra.floattext): every double reads back identical, by Python's float() and by
pyarrow's CSV reader, in at most 17 significant digits; references are float() (correctly rounded parsing) and
repr() (shortest round trip), never the kernel itself."""
from __future__ import annotations

import io
import math
import re
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from chainid.infra.floattext import MAX_CHARS, TABLES, csv_chunks, format_rows, jit_enabled

pytestmark = pytest.mark.skipif(not jit_enabled(), reason="the kernel is not compiled (NUMBA_DISABLE_JIT)")


def _texts(values, **kw) -> list[str]:
    v = np.asarray(values, dtype=float)
    return b"".join(bytes(p) for p in csv_chunks(b"", [v], **kw)).decode().splitlines()


def _sig_digits(s: str) -> int:
    mant = s.lstrip("-").split("e")[0].replace(".", "")
    return len(mant.strip("0")) if mant.strip("0") else 1


def _check(values) -> list[str]:
    v = np.asarray(values, dtype=float)
    texts = _texts(v)
    assert len(texts) == v.size
    for x, s in zip(v, texts):
        if math.isnan(x):
            assert s == "nan"
            continue
        back = float(s)
        assert np.float64(back).view(np.int64) == np.float64(x).view(np.int64), (repr(x), s)  # -0.0 included
        assert _sig_digits(s) <= 17, s
    return texts


SPECIAL = [0.0, -0.0, 0.1, -0.1, 1e-5, 1e-4, 0.3, 1.0, 2.0, 100.0, 20000.0, 1.7e9 + 0.0001, 1.7e9, 1e15, 1e16,
           1e17, 1e22, 1e23, 2.0 ** 53, 2.0 ** 53 + 2, 2.0 ** 53 - 1, 2.0 ** 63, 123456789012345680.0, 5e-324,
           2.2250738585072014e-308, 2.225073858507201e-308, 1.7976931348623157e308, 1e-280, 1e280, 9.99e-281,
           1.01e280, 0.5, 0.25, 2.0 ** -30, 2.0 ** -1000, 2.0 ** 900, 1 / 3, 2 / 3, 9007199254740993.0,
           0.1 + 0.2, 1e-310, -1e-320, np.nextafter(1.0, 2.0), np.nextafter(1.0, 0.0), np.nextafter(1e16, 0),
           np.inf, -np.inf, np.nan, 4.35, 0.000123456789, 99999999999999.98, 9.999999999999999e-5]


@pytest.mark.slow
def test_special_values_read_back_identical():
    texts = _check(SPECIAL + [-x for x in SPECIAL])
    assert texts[:4] == ["0.0", "-0.0", "0.1", "-0.1"]
    assert texts[SPECIAL.index(np.inf)] == "inf" and texts[SPECIAL.index(1.7e9 + 0.0001)] == "1700000000.0001"


def test_values_with_few_digits_are_written_as_repr():
    """repr is the shortest round trip; with <= 15 significant digits only one 15-digit decimal rounds to the
    value, so the kernel's text is repr's (layout included) -- below 1e16: above, a short decimal can be exactly
    half-way between two doubles (5e22 = 49999999999999995805696 + ulp/2), which the kernel's certificate leaves
    to the 16/17-digit candidates (still exact: checked)."""
    rng = np.random.default_rng(3)
    few = [float(f"{m}e{e}") for m, e in zip(rng.integers(1, 10 ** rng.integers(1, 15, 3000), dtype=np.int64),
                                          rng.integers(-30, 30, 3000))]
    few += [k / 10_000 for k in range(0, 20_000, 7)] + [1.7e9 + k * 1e-4 for k in range(1000)]
    texts = _check(few)
    short = [(x, s) for x, s in zip(few, texts) if _sig_digits(repr(x)) <= 15 and abs(x) < 1e16]
    assert len(short) > 2500
    assert all(s == repr(x) for x, s in short)


@settings(max_examples=100, deadline=None)
@given(st.lists(st.integers(0, 2 ** 64 - 1), min_size=1, max_size=200))
def test_random_bit_patterns_read_back_identical(words):
    """Any bit pattern: normal, subnormal, huge, tiny, negative zero, NaN, inf."""
    _check(np.array(words, dtype=np.uint64).view(np.float64))


@settings(max_examples=150, deadline=None)
@given(st.floats(allow_nan=False, allow_infinity=False, width=64))
def test_hypothesis_floats_read_back_identical(x):
    _check([x])


@pytest.mark.slow
def test_a_million_random_doubles_by_float_and_by_pyarrow():
    """10^6 doubles (random bits over all exponents, uniform data, Unix time stamps): float() and pyarrow's
    CSV reader give back the identical float64 of every one."""
    import pyarrow as pa
    import pyarrow.csv as pacsv

    rng = np.random.default_rng(11)
    bits = rng.integers(0, 2 ** 63, 600_000, dtype=np.int64) | (rng.integers(0, 2, 600_000, dtype=np.int64) << 63)
    v = bits.view(np.float64)
    v = np.concatenate([v[np.isfinite(v)], rng.uniform(-1e6, 1e6, 200_000),
                        1.7e9 + np.cumsum(rng.uniform(0, 1e-3, 200_000))])[:1_000_000]
    data = b"".join(bytes(p) for p in csv_chunks(b"T", [v, v[::-1].copy()]))
    texts = data.decode().splitlines()
    back = np.array([float(s.split(",")[1]) for s in texts])
    assert np.array_equal(back.view(np.int64), v.view(np.int64))
    assert max(_sig_digits(s.split(",")[1]) for s in texts[::50]) <= 17
    tab = pacsv.read_csv(io.BytesIO(data), read_options=pacsv.ReadOptions(column_names=["test", "a", "b"]),
                         convert_options=pacsv.ConvertOptions(column_types={"a": pa.float64(), "b": pa.float64()}))
    assert np.array_equal(tab["a"].to_numpy().view(np.int64), v.view(np.int64))
    assert np.array_equal(tab["b"].to_numpy().view(np.int64), v[::-1].view(np.int64))
    assert set(tab["test"].to_pylist()) == {"T"}


def test_rows_and_chunk_boundaries():
    """The row layout, and the same text whatever the chunk and block sizes (fallback values inside)."""
    rng = np.random.default_rng(5)
    a, b = rng.normal(size=1001), rng.normal(size=1001) * 1e5
    b[[0, 500, 1000]] = [np.nan, 5e-324, -np.inf]  # left to the exact fallback
    one = b"".join(bytes(p) for p in csv_chunks(b"id7", [a, b]))
    many = b"".join(bytes(p) for p in csv_chunks(b"id7", [a, b], chunk_rows=100, block_rows=7))
    assert one == many
    rows = one.decode().splitlines()
    assert rows[0] == f"id7,{_texts([a[0]])[0]},nan" and rows[500].endswith(",5e-324")
    assert rows[1000].endswith(",-inf") and len(rows) == 1001
    assert b"".join(bytes(p) for p in csv_chunks(b"", [a[:0]])) == b""


@pytest.mark.parametrize("path", ["kernel", "polars"])
def test_write_canonical_reads_back_identical(tmp_path, monkeypatch, path):
    """The records writer (kernel path, polars path): the fast reader and the row-by-row reader give back every sample's
    float64 exactly, Unix-epoch time stamps included (what %.9g lost)."""
    from chainid.records.files import read_records
    from chainid.records.record import Record
    from chainid.records.textcanon import read_csv_strict
    from chainid.records import writer
    from chainid.records.writer import write_canonical

    if path == "polars":
        pytest.importorskip("polars")
    else:
        monkeypatch.setattr(writer, "_polars", lambda: None)
    rng = np.random.default_rng(2)
    t = 1.7e9 + np.arange(5000) / 10_240.0
    recs = [Record(f"T{k}", t, rng.normal(size=t.size) * 10 ** k, 2e4 + rng.normal(size=t.size)) for k in range(3)]
    p = write_canonical(tmp_path / "r.csv", recs)
    for back in (read_records(p, validate=False), read_csv_strict(p)):
        assert [r.test for r in back] == ["T0", "T1", "T2"]
        for r, e in zip(back, recs):
            for a in "txF":
                assert np.array_equal(getattr(r, a).view(np.int64), getattr(e, a).view(np.int64))
    recs[1].x[7] = np.nan  # a record with NaN or inf: written as before ("nan"), by the kernel on either path
    recs[2].F[0] = -np.inf
    lines = write_canonical(tmp_path / "nan.csv", recs).read_text().splitlines()
    assert lines[5000 + 8].split(",")[2] == "nan" and lines[10_001].split(",")[3] == "-inf"


def _left_to_fallback(values) -> np.ndarray:
    """The values :func:`format_rows` leaves to the exact fallback (its ``ovr`` marks them -2)."""
    cols = np.asarray(values, dtype=float)[None, :]
    block = cols.shape[1]
    out = np.empty(block * (MAX_CHARS + 1) + 64, np.uint8)
    ovr = np.full(cols.size, -1, np.int32)
    format_rows(cols, np.zeros(0, np.uint8), out, block, np.zeros(1, np.int64), ovr, np.zeros(0, np.uint8),
                np.zeros(1, np.int64))
    return cols[0][ovr == -2]


@pytest.mark.slow
def test_the_kernel_certifies_every_ordinary_double_itself():
    """The documented contract of the fallback: only NaN, ±inf, subnormals, |v| outside [1e-280, 1e280] (and,
    rarely, a power of two) go to Python's repr; every other double is certified by the kernel with 15, 16 or 17
    digits.  20 000 random doubles (random mantissa bits, decimal exponents -279..279) and values that need 17
    digits (0.1 + 0.2, 1.1², nextafter(1, 2)) or 16 (1/3) leave nothing to the fallback.  Bugs caught: a candidate's
    certificate broken (``x17 < hi_ok`` → ``x17 is hi_ok``: every 17-digit value falls back), a threshold off."""
    rng = np.random.default_rng(7)
    mant = rng.integers(1, 1 << 52, 20_000, dtype=np.int64)  # never 0: no power of two
    v = (1.0 + mant.astype(float) / 2.0**52) * 10.0 ** rng.integers(-279, 280, mant.size).astype(float)
    v = v[(np.abs(v) >= 1e-280) & (np.abs(v) <= 1e280) & (np.float64(v).view(np.int64) & ((1 << 52) - 1) != 0)]
    v[::2] *= -1
    need17 = [0.1 + 0.2, 1.1 * 1.1, float(np.nextafter(1.0, 2.0))]  # 0.30000000000000004, 1.2100000000000002, ...
    assert [_sig_digits(repr(x)) for x in need17] == [17, 17, 17]
    need16 = [1 / 3, 2 / 3, 99999999999999.98]
    assert [_sig_digits(repr(x)) for x in need16] == [16, 16, 16]
    assert _left_to_fallback(np.concatenate([v, need17, need16])).size == 0
    special = [np.nan, np.inf, -np.inf, 5e-324, -1e-310, 9.99e-281, 1.01e280, 1e300, -1e-300]
    left = _left_to_fallback(special)
    assert left.size == len(special)


def test_the_pow10_table_is_ten_to_the_k_as_double_double_over_its_whole_range():
    """``TABLES[0]``, ``TABLES[1]``: 10^k for k = -300..300 as hi (10^k correctly rounded: Python's parser of
    '1e<k>') and lo (the rest, correctly rounded: exact decimal arithmetic at 700 digits).  Bug caught: the
    table's last entry (k = 300) left unset (``range(_KMIN, _KMAX + 1)`` → ``_KMAX + 0``)."""
    from decimal import Decimal, localcontext

    hi, lo = TABLES[0], TABLES[1]
    assert hi.size == lo.size == 601
    with localcontext() as ctx:
        ctx.prec = 700
        for i, k in enumerate(range(-300, 301)):
            assert hi[i] == float(f"1e{k}"), k
            assert lo[i] == float(Decimal(10) ** k - Decimal(hi[i])), k
    assert hi[-1] == 1e300 and hi[0] == 1e-300


def _halfway(text: str, v: float) -> bool:
    """Whether the decimal ``text`` lies exactly half-way between ``v`` and a neighbouring double (exact rationals)."""
    q = Fraction(text)
    return any(q == (Fraction(v) + Fraction(math.nextafter(v, to))) / 2 for to in (-math.inf, math.inf))


def test_values_at_and_next_to_every_power_of_ten_are_written_as_repr():
    """Around 10^n the scaled value y = |v|·10^k sits at the ends of [1e16, 1e17), where the kernel corrects its
    decimal exponent (y rounding to 1e17 from below, or to 1e16 from above).  For every n in -279..279, the double
    nearest 10^n (Python's parser) and 4 doubles either side: no value is left to the fallback, each reads back
    identical, is laid out as ``repr`` lays it out, and is ``repr``'s text save for two documented exceptions:
    ``repr``'s decimal exactly half-way between two doubles (1e23), and a tie between two decimals of as many digits
    (1000000000000000.25: '.3', where ``repr`` rounds half to even, '.2'); exact rationals decide both.  Bugs
    caught: the correction at 1e17 taken for y just below it (``yl >= 0`` → ``yl != 0``:
    '0.9999999999999999e-259'), the one at 1e16 taken for y just above it (``yl < 0`` → ``yl != 0``: a digit ':'
    written)."""
    vals = []
    for n in range(-279, 280):
        lo = hi = float(f"1e{n}")
        vals.append(lo)
        for _ in range(4):
            lo, hi = math.nextafter(lo, 0.0), math.nextafter(hi, math.inf)
            vals += [lo, hi]
    v = np.array(vals)
    v[1::2] *= -1
    assert _left_to_fallback(v).size == 0
    texts = b"".join(bytes(m) for m in csv_chunks(b"", [v])).decode().splitlines()
    assert len(texts) == v.size
    assert all(float(t) == x for t, x in zip(texts, v.tolist()))
    positional, scientific = re.compile(r"-?[1-9]\d*\.\d+|-?0\.\d+"), re.compile(r"-?[1-9](\.\d+)?e[+-]\d\d\d?")
    for t, x in zip(texts, v.tolist()):
        assert (positional if 1e-4 <= abs(x) < 1e16 else scientific).fullmatch(t), (t, x)
    off = [(t, x) for t, x in zip(texts, v.tolist()) if t != repr(x)]
    for t, x in off:
        gap_t, gap_r = abs(Fraction(t) - Fraction(x)), abs(Fraction(repr(x)) - Fraction(x))
        tie = _sig_digits(t) == _sig_digits(repr(x)) and gap_t == gap_r
        assert tie or _halfway(repr(x), x), (t, x)
    assert len(off) <= 4, off


def test_every_power_of_two_and_its_neighbours_read_back_identical():
    """At an exact power of two the gap to the next double below is half the gap above, so a decimal below it must
    lie within a quarter of the upper gap to read back as it.  Every 2^k in the kernel's range (1e-280..1e280) and
    the doubles either side: each text reads back identical in ≤ 17 digits (for 42 powers the kernel writes 17
    digits where ``repr``'s 16 lie above: longer, still exact).  Seed-29 survivor: the power-of-two test on the
    mantissa bits (``bt & mask == 0`` → ``bt - mask == 0``, never true) gave every power the full gap below."""
    vals = []
    for k in range(-930, 931):
        v = 2.0**k
        if 1e-280 <= v <= 1e280:
            vals += [v, -v, math.nextafter(v, 0.0), math.nextafter(v, math.inf)]
    assert len(vals) == 4 * 1861
    _check(vals)
