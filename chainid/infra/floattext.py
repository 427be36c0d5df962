"""Rows of doubles as CSV text that reads back to the identical float64, fast (a numba kernel, blocks on all cores).

Each double ``v`` is written with the fewest of 15, 16 or 17 significant digits (trailing zeros dropped) that
provably round to ``v`` again, in the layout of Python's ``repr`` (positional for 1e-4 <= |v| < 1e16, else
``d.ddde-XX``; ``-0.0`` kept).  Method, per value: ``y = |v|·10^k`` in [1e16, 1e17) as a double-double (Dekker's
error-free product with a double-double table of 10^k, relative error < 1e-30), the candidate integers
``D`` = ``y`` rounded to 15, 16, 17 digits, and the certificate ``|D - y| < ulp(v)/2 · 10^k`` (the lower half-gap
halved when ``v`` is a power of two) with a margin of 1e-7 (in units of the 17th digit; the error of ``y`` is
< 1e-13 there).  A value no candidate certifies -- NaN, ±inf, subnormals and |v| outside [1e-280, 1e280] by
design, and rarely a power of two whose 17-digit decimal falls in the narrower gap below it -- is written by
Python's ``repr`` after the kernel (exact, shortest).  The output is not always ``repr``'s: when two 16-digit
decimals round to ``v`` the nearer is taken, which may not be the one ``repr`` picks, and a short decimal exactly
half-way between two doubles (5e22) is left to the 16/17-digit candidates; all are exact.

Units: none (the numbers are written as given).
"""
from __future__ import annotations

import math
import os
from fractions import Fraction
from typing import Any

import numpy as np

try:  # numba with a cache that never crashes; plain Python (slow) if numba is absent
    from chainid.infra.numba_cache import njit_cached as _njit
except Exception:  # pragma: no cover
    def _njit(*a: Any, **k: Any) -> Any:
        return (lambda f: f) if not (a and callable(a[0])) else a[0]

__all__ = ["MAX_CHARS", "TABLES", "format_rows", "csv_chunks", "jit_enabled"]

#: Longest text of one value (sign, 17 digits, point, ``e-XXX``) -- a bound the buffers are sized by.
MAX_CHARS = 25
_KMIN, _KMAX = -300, 300


def _pow10_table() -> tuple[np.ndarray, np.ndarray]:
    """10^k for k in [_KMIN, _KMAX] as double-double (hi + lo, both correctly rounded)."""
    hi = np.empty(_KMAX - _KMIN + 1)
    lo = np.empty_like(hi)
    for i, k in enumerate(range(_KMIN, _KMAX + 1)):
        exact = Fraction(10) ** k
        hi[i] = float(exact)
        lo[i] = float(exact - Fraction(hi[i]))
    return hi, lo


_P_HI, _P_LO = _pow10_table()
_POW2 = np.array([math.ldexp(1.0, e - 1100) for e in range(2101)])  # 2^e for e in [-1100, 1000]
_DIG2 = np.frombuffer("".join(f"{i:02d}" for i in range(100)).encode(), np.uint8).copy()
_SPLIT = 134217729.0  # 2^27 + 1, Veltkamp's splitter
_MARGIN = 1e-7
_PAD = 32  # bytes a value's fixed-length copies may write past its end
#: The kernel's tables: 10^k as double-double (hi, lo), 2^e, the two-digit strings.
TABLES = (_P_HI, _P_LO, _POW2, _DIG2)


def jit_enabled() -> bool:
    """Whether the kernel is compiled (False with ``NUMBA_DISABLE_JIT=1`` or without numba: pure Python, slow)."""
    return hasattr(_format_block, "py_func")


@_njit(inline="always", error_model="numpy")
def _scaled(a: float, b: float, b_lo: float) -> tuple[float, float]:  # pragma: no cover
    """a·(b + b_lo) as a normalised double-double (Dekker's error-free product; no FMA needed)."""
    p = a * b
    c = _SPLIT * a
    ah = c - (c - a)
    al = a - ah
    c = _SPLIT * b
    bh = c - (c - b)
    bl = b - bh
    e = ((ah * bh - p) + ah * bl + al * bh) + al * bl
    e += a * b_lo
    s = p + e
    return s, e - (s - p)


@_njit(inline="always", error_model="numpy")
def _certified(yh: float, yl: float, thr_up: float, thr_lo: float) -> tuple[int, int]:  # pragma: no cover
    """The fewest of 15, 16, 17 digits that round back to the value: ``y = yh + yl`` (its scaled value, in [1e16,
    1e17)) rounded to each, the first within ``(-thr_lo, thr_up)`` of ``y`` (its half-gaps scaled alike, less the
    margin) taken, without a branch: ``(D, tz)``, ``tz`` the trailing zeros known (2 for 15 digits, 1 for 16, else 0);
    ``D = -1`` when none certifies."""
    fl = math.floor(yl)
    yfloor = np.int64(yh) + np.int64(fl)
    frac = yl - fl
    lo_ok = -thr_lo + _MARGIN
    hi_ok = thr_up - _MARGIN
    r100 = yfloor % 100
    r10 = r100 % 10
    d15 = yfloor - r100 + 100 * np.int64((r100 + frac) * 2.0 >= 100.0)
    d16 = yfloor - r10 + 10 * np.int64((r10 + frac) * 2.0 >= 10.0)
    d17 = yfloor + np.int64(frac >= 0.5)
    x15 = float(d15 - yfloor) - frac
    x16 = float(d16 - yfloor) - frac
    x17 = float(d17 - yfloor) - frac
    c15 = np.int64(x15 > lo_ok) & np.int64(x15 < hi_ok)
    c16 = np.int64(x16 > lo_ok) & np.int64(x16 < hi_ok) & (1 - c15)
    c17 = np.int64(x17 > lo_ok) & np.int64(x17 < hi_ok) & (1 - c15) & (1 - c16)
    ok = c15 | c16 | c17
    return c15 * d15 + c16 * d16 + c17 * d17 - (1 - ok), 2 * c15 + c16


@_njit(inline="always", error_model="numpy")
def _write_17_digits(out: np.ndarray, at: int, d: int, dig2: np.ndarray) -> None:  # pragma: no cover
    """The 17 digits of ``d`` (< 10^17) at out[at:at+17], by two short division chains of two digits a step."""
    hi = d // 100000000
    lo = d - hi * 100000000
    top = hi // 100000000  # one digit
    mid = hi - top * 100000000
    w = at + 15
    for _ in range(4):
        q = lo // 100
        r = lo - q * 100
        out[w] = dig2[2 * r]
        out[w + 1] = dig2[2 * r + 1]
        q2 = mid // 100
        r2 = mid - q2 * 100
        out[w - 8] = dig2[2 * r2]
        out[w - 7] = dig2[2 * r2 + 1]
        lo = q
        mid = q2
        w -= 2
    out[at] = 48 + top


@_njit(inline="always", error_model="numpy")
def _write_decimal(out: np.ndarray, pos: int, d: int, k: int, tz: int, neg: bool,
                   dig2: np.ndarray) -> int:  # pragma: no cover
    """``d·10^-k`` (``-`` first if ``neg``) at out[pos:] in the layout of ``repr`` (trailing zeros dropped, ``tz``
    of them known); the end position."""
    if d == 100000000000000000:  # 10^17 after rounding up: the same value as 10^16·10^-(k-1)
        d = 10000000000000000
        k -= 1
    exp10 = 16 - k  # exponent of the leading digit
    out[pos] = 45
    pos += np.int64(neg)
    if -4 <= exp10 < 0:  # 0.000ddd
        out[pos] = 48
        out[pos + 1] = 46
        out[pos + 2] = 48
        out[pos + 3] = 48
        out[pos + 4] = 48
        at = pos + 1 - exp10  # first digit
    else:
        at = pos + 1  # digits at pos+1.., the integer part moved left after
    _write_17_digits(out, at, d, dig2)
    end = at + 17 - tz
    while out[end - 1] == 48:
        end -= 1
    if exp10 < -4 or exp10 >= 16:  # d.ddde±XX (as repr)
        out[pos] = out[pos + 1]
        out[pos + 1] = 46
        pos = end if end > pos + 2 else pos + 1
        out[pos] = 101
        out[pos + 1] = 43 + 2 * np.int64(exp10 < 0)
        pos += 2
        ex = abs(exp10)
        if ex >= 100:
            out[pos] = 48 + ex // 100
            pos += 1
        out[pos] = 48 + (ex // 10) % 10
        out[pos + 1] = 48 + ex % 10
        pos += 2
    elif exp10 >= 0:  # ddd.ddd
        for j in range(exp10 + 1):
            out[pos + j] = out[pos + 1 + j]
        dot = pos + exp10 + 1
        out[dot] = 46
        pos = max(end, dot + 2)  # at least one fraction digit: the 0 of 20000.0 is still there
    else:
        pos = end
    return pos


@_njit(nogil=True, error_model="numpy")
def _format_block(cols: np.ndarray, bits: np.ndarray, prefix: np.ndarray, out: np.ndarray, pos: int, i0: int,
                  i1: int, ovr: np.ndarray, ovr_text: np.ndarray, ovr_start: np.ndarray, p_hi: np.ndarray,
                  p_lo: np.ndarray, pow2: np.ndarray, dig2: np.ndarray) -> int:  # pragma: no cover
    """Rows i0..i1-1 at out[pos:]; the end position.  Per value: its scaling to [1e16, 1e17) here, the certified
    decimal (:func:`_certified`) and its text (:func:`_write_decimal`) in helpers numba inlines into this one loop.
    The tables are read here, not in a helper: an array handed to an inlined helper that branches costs an atomic
    reference count per call (~40 ns a value here); the text's helpers take ``out`` and ``dig2`` at no such cost (the
    machine code is that of the single loop).  The choice among the candidates is branch-free (random data would
    mispredict every branch)."""
    nc = cols.shape[0]
    for i in range(i0, i1):
        for j in range(prefix.size):
            out[pos] = prefix[j]
            pos += 1
        for c in range(nc):
            if c > 0 or prefix.size > 0:
                out[pos] = 44
                pos += 1
            o = ovr[i * nc + c]
            v = cols[c, i]
            bt = bits[c, i]
            a = abs(v)
            d = np.int64(-1)
            k = 0
            tz = 0
            if o >= 0:  # text given by the exact fallback
                for j in range(ovr_start[o], ovr_start[o + 1]):
                    out[pos] = ovr_text[j]
                    pos += 1
            elif a == 0.0:
                out[pos] = 45
                pos += np.int64(bt < 0)
                out[pos] = 48
                out[pos + 1] = 46
                out[pos + 2] = 48
                pos += 3
            elif 1e-280 <= a <= 1e280:  # else NaN, inf, subnormal, extreme: d stays -1 (fallback)
                e2 = ((bt >> 52) & 0x7FF) - 1023  # a in [2^e2, 2^(e2+1))
                e10 = int(math.floor(e2 * 0.30102999566398120))
                e10 += np.int64(a >= p_hi[e10 + 1 - _KMIN])
                k = 16 - e10
                yh, yl = _scaled(a, p_hi[k - _KMIN], p_lo[k - _KMIN])
                if yh > 1e17 or (yh == 1e17 and yl >= 0.0):  # e10 off by one at the rounding of 10^n
                    k -= 1
                    yh, yl = _scaled(a, p_hi[k - _KMIN], p_lo[k - _KMIN])
                elif yh < 1e16 or (yh == 1e16 and yl < 0.0):
                    k += 1
                    yh, yl = _scaled(a, p_hi[k - _KMIN], p_lo[k - _KMIN])
                thr_up = p_hi[k - _KMIN] * pow2[e2 - 53 + 1100]  # ulp(a)/2 · 10^k
                thr_lo = thr_up * (0.5 if (bt & 0xFFFFFFFFFFFFF) == 0 else 1.0)  # a power of two: half gap below
                d, tz = _certified(yh, yl, thr_up, thr_lo)
                if d < 0:
                    ovr[i * nc + c] = -2  # nothing written: formatted again with repr's text
            else:
                ovr[i * nc + c] = -2
            if d >= 0:  # d·10^-k, written in place
                pos = _write_decimal(out, pos, d, k, tz, bt < 0, dig2)
        out[pos] = 10
        pos += 1
    return pos


def format_rows(cols: np.ndarray, prefix: np.ndarray, out: np.ndarray, block_rows: int, lens: np.ndarray,
                ovr: np.ndarray, ovr_text: np.ndarray, ovr_start: np.ndarray, pool: Any = None) -> None:
    """Format rows ``prefix,c0,c1,...\\n`` of ``cols`` (n_cols x n doubles) into ``out``, in blocks.

    Block ``b`` (rows ``b·block_rows`` up to the next block) is written at ``out[b·cap:]`` with ``cap =
    block_rows·(len(prefix) + n_cols·(MAX_CHARS + 1)) + 32``; its length goes to ``lens[b]``.  ``ovr`` (int32,
    one per value, row-major) is -1 for the kernel's own text, ``j >= 0`` to copy ``ovr_text[ovr_start[j]:
    ovr_start[j+1]]`` instead; the kernel sets -2 where it leaves a value to the exact fallback (nothing
    written there: format again with that value's text given).  The blocks run on ``pool`` (a
    ``concurrent.futures`` executor: the kernel releases the GIL) or in this thread.  Python threads rather
    than numba's ``prange``: OpenMP's workers spin between parallel regions, which costs CPU time (measured
    +40 % on 2 cores) for no gain in wall time.
    """
    nc, n = cols.shape
    bits = cols.view(np.int64)
    cap = block_rows * (prefix.size + nc * (MAX_CHARS + 1)) + _PAD

    def one(b: int) -> None:
        end = _format_block(cols, bits, prefix, out, b * cap, b * block_rows, min(n, (b + 1) * block_rows), ovr,
                            ovr_text, ovr_start, *TABLES)
        lens[b] = end - b * cap

    if pool is None:
        for b in range(lens.size):
            one(b)
    else:
        for f in [pool.submit(one, b) for b in range(lens.size)]:
            f.result()


def csv_chunks(prefix: bytes, cols: list[np.ndarray], chunk_rows: int = 1 << 18, block_rows: int = 1 << 13):
    """Yield the CSV text of rows ``prefix,c0,c1,...`` (``prefix`` empty: no leading field) chunk by chunk.

    Parameters
    ----------
    prefix : bytes
        Text of a leading field repeated on every row (e.g. the test id), without the comma; may be empty.
    cols : list of ndarray
        The columns (same length; converted to float64).
    chunk_rows : int
        Rows formatted per kernel call (memory: about ``chunk_rows·(len(prefix) + 26·len(cols))`` bytes).
    block_rows : int
        Rows per parallel block.

    Yields
    ------
    memoryview
        Consecutive pieces of the text; each is valid until the next one is requested.
    """
    nc = len(cols)
    pre = np.frombuffer(prefix, np.uint8)
    n = len(cols[0]) if cols else 0
    block_rows = max(1, min(block_rows, n))
    cap = block_rows * (pre.size + nc * (MAX_CHARS + 1)) + _PAD
    nblk_max = -(-min(chunk_rows, max(n, 1)) // block_rows)
    out = np.empty(nblk_max * cap, np.uint8)
    no_text, no_start = np.zeros(0, np.uint8), np.zeros(1, np.int64)
    from concurrent.futures import ThreadPoolExecutor
    from contextlib import nullcontext

    workers = max(1, min(os.cpu_count() or 1, 8))
    with (ThreadPoolExecutor(max_workers=workers) if n > block_rows and workers > 1 else nullcontext()) as pool:
        for i0 in range(0, n, chunk_rows):
            blk = np.empty((nc, min(chunk_rows, n - i0)))
            for c, col in enumerate(cols):
                blk[c] = col[i0:i0 + chunk_rows]
            nblk = -(-blk.shape[1] // block_rows)
            lens = np.zeros(nblk, np.int64)
            ovr = np.full(blk.size, -1, np.int32)
            format_rows(blk, pre, out, block_rows, lens, ovr, no_text, no_start, pool if nblk > 1 else None)
            left = np.flatnonzero(ovr == -2)
            if left.size:  # the exact fallback: Python's repr of the values the kernel could not certify
                texts = [repr(float(v)).encode() for v in blk.T.ravel()[left]]
                start = np.zeros(len(texts) + 1, np.int64)
                np.cumsum([len(t) for t in texts], out=start[1:])
                ovr[:] = -1
                ovr[left] = np.arange(left.size, dtype=np.int32)
                format_rows(blk, pre, out, block_rows, lens, ovr, np.frombuffer(b"".join(texts), np.uint8), start,
                            pool if nblk > 1 else None)
            mv = memoryview(out)
            for b in range(nblk):
                yield mv[b * cap:b * cap + lens[b]]
