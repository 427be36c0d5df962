"""Write records in the canonical long format ``test,t,x,F`` (s, mm, N): CSV or Parquet, atomically and fast.

CSV numbers are text that reads back to the identical float64 in at most 17 significant digits.  Formatted by
polars when it is installed (the optional extra ``chainid[fast]``: shortest round-trip text, about 2x less CPU),
else by chainid's numba kernel on all cores (:mod:`chainid.infra.floattext`; ``repr``'s text for the few values it
cannot certify); with ``NUMBA_DISABLE_JIT=1`` by pyarrow's writer, and without pyarrow by a block-formatted
``%.17g`` writer.  All give the same values (``benchmarks/readers_bench.py`` measures them).  A record with NaN or
inf is written by the kernel (``nan``, ``inf`` as before; polars would write ``NaN``).
"""
from __future__ import annotations

from pathlib import Path
from typing import Iterable

import numpy as np

from chainid.records.record import Record

__all__ = ["OUTPUT_FORMATS", "write_canonical", "write_canonical_to"]

#: Output suffix -> format.
OUTPUT_FORMATS = {".csv": "csv", ".parquet": "parquet", ".pq": "parquet"}
_BLOCK = 1 << 16
_ROWS_PER_WRITE = 1 << 19


def _check_ids(records: list[Record]) -> None:
    seen: set[str] = set()
    for r in records:
        if any(ch in r.test for ch in ",\n\r\""):
            raise ValueError(f"test id {r.test!r} must not contain commas, quotes or newlines")
        if not r.test.strip() or r.test != r.test.strip():
            raise ValueError(f"test id {r.test!r} must be non-empty without leading/trailing spaces")
        if r.test in seen:
            raise ValueError(f"test id {r.test!r} appears twice; test ids must be unique")
        seen.add(r.test)


def _arrow_table(records: list[Record]):
    import pyarrow as pa

    n = [r.t.size for r in records]
    codes = np.repeat(np.arange(len(records), dtype=np.int32), n)
    test = pa.DictionaryArray.from_arrays(pa.array(codes), pa.array([r.test for r in records], pa.string()))
    cat = (lambda k: np.concatenate([getattr(r, k) for r in records]) if records else np.zeros(0))
    return pa.table({"test": test, "t": cat("t"), "x": cat("x"), "F": cat("F")})


def _write_csv_plain(fh, records: list[Record]) -> None:
    for r in records:
        m = np.column_stack([r.t, r.x, r.F])
        fmt = f"{r.test},%.17g,%.17g,%.17g\n"
        for i in range(0, m.shape[0], _BLOCK):
            blk = m[i:i + _BLOCK]
            fh.write(((fmt * blk.shape[0]) % tuple(blk.ravel().tolist())).encode())


def _blocks(records: list[Record]):
    for r in records:
        for i in range(0, r.t.size, _ROWS_PER_WRITE):
            j = i + _ROWS_PER_WRITE
            yield Record(r.test, r.t[i:j], r.x[i:j], r.F[i:j])


def _format_block(rec: Record) -> bytes:
    import pyarrow as pa
    import pyarrow.csv as pacsv

    sink = pa.BufferOutputStream()
    pacsv.write_csv(_arrow_table([rec]), sink,
                    write_options=pacsv.WriteOptions(include_header=False, quoting_style="none"))
    return sink.getvalue()


def _write_csv_arrow(fh, records: list[Record]) -> None:
    """Blocks of rows formatted by pyarrow on two threads (it releases the GIL), written in order."""
    from concurrent.futures import ThreadPoolExecutor

    with ThreadPoolExecutor(max_workers=2) as pool:
        pending = []
        for blk in _blocks(records):
            pending.append(pool.submit(_format_block, blk))
            if len(pending) > 2:  # bounded memory: at most 3 blocks formatted ahead
                fh.write(memoryview(pending.pop(0).result()))
        for fut in pending:
            fh.write(memoryview(fut.result()))


def _write_csv_kernel(fh, records: list[Record], polars=None) -> None:
    """The numba kernel's text (or polars', if given), chunk by chunk (bounded memory)."""
    from chainid.infra.floattext import csv_chunks

    for r in records:
        if polars is not None and all(np.isfinite(a).all() for a in (r.t, r.x, r.F)):
            for i in range(0, r.t.size, _ROWS_PER_WRITE):
                j = i + _ROWS_PER_WRITE
                polars.DataFrame({"test": polars.repeat(r.test, r.t[i:j].size, eager=True), "t": r.t[i:j],
                                  "x": r.x[i:j], "F": r.F[i:j]}).write_csv(fh, include_header=False)
            continue
        for piece in csv_chunks(r.test.encode(), [r.t, r.x, r.F]):
            fh.write(piece)


def _polars():
    """polars if installed (``pip install "chainid[fast]"``), else None."""
    try:
        import polars
    except ImportError:
        return None
    return polars


def write_canonical(path: str | Path, records: Iterable[Record], overwrite: bool = False,
                    fmt: str | None = None) -> Path:
    """Write records as ``test,t,x,F`` (t s, x mm, F N): CSV, or Parquet by the suffix ``.parquet``/``.pq``.

    Parameters
    ----------
    path : str or Path
        Output file; written to a temporary file beside it and renamed (never a partial file).
    records : iterable of Record
        The tests (unique ids without commas, quotes or newlines).
    overwrite : bool
        Replace an existing file (default: an existing file is an error).
    fmt : {"csv", "parquet"} or None
        None = by the suffix (anything but .parquet/.pq is CSV).

    Returns
    -------
    Path
        The written path.
    """
    from chainid.infra.fileio import atomic_open

    p = Path(path)
    fmt = fmt or OUTPUT_FORMATS.get(p.suffix.lower(), "csv")
    recs = list(records)
    _check_ids(recs)
    if fmt == "parquet":
        try:
            import pyarrow.parquet as pq
        except ImportError:
            raise ValueError("writing Parquet needs pyarrow, which is not installed: pip install pyarrow (a dependency "
                             "of chainid)") \
                from None
        table = _arrow_table(recs)
        with atomic_open(p, "wb", force=overwrite, what="records") as fh:
            pq.write_table(table, fh)
        return p
    if fmt != "csv":
        raise ValueError(f"output format {fmt!r} is invalid; valid: 'csv', 'parquet'")
    with atomic_open(p, "wb", force=overwrite, what="records") as fh:
        _write_csv(fh, recs)
    return p


def _write_csv(fh, recs: list[Record]) -> None:
    from chainid.infra.floattext import jit_enabled

    try:
        import pyarrow.csv as pacsv
    except ImportError:
        pacsv = None
    fh.write(b"test,t,x,F\n")
    if jit_enabled():
        _write_csv_kernel(fh, recs, _polars())
    elif pacsv is None:
        _write_csv_plain(fh, recs)
    else:
        _write_csv_arrow(fh, recs)


def write_canonical_to(fh, records: Iterable[Record]) -> None:
    """Write records as CSV ``test,t,x,F`` (s, mm, N) into an open binary stream (stdout: ``convert --to -``);
    the same text as :func:`write_canonical`, not atomic (a stream has no rename)."""
    recs = list(records)
    _check_ids(recs)
    _write_csv(fh, recs)
