"""The canonical long CSV ``test,t,x,F`` (s, mm, N): a fast reader (pyarrow) and the strict row-by-row reader.

:func:`read_canonical_csv` parses the file with pyarrow's streaming CSV reader.  Whenever the fast parse
fails or finds anything irregular (a bad cell, NaN, a row with another field count, test rows that are not
contiguous, a header not on line 1...), the file is read again by :func:`read_csv_strict`, the row-by-row
reader, which raises the precise error (file, line, test, column, value).  So both paths give the same records
and the same errors; without pyarrow installed the strict reader is used alone (slower, see
``benchmarks/records_bench.py``).
"""
from __future__ import annotations

import csv
import math
from array import array
from pathlib import Path
from typing import Iterator

import numpy as np

from chainid.records.record import Record

__all__ = ["REQUIRED_COLUMNS", "parse_float", "read_csv_strict", "read_canonical_csv"]

REQUIRED_COLUMNS = ("test", "t", "x", "F")


def parse_float(text: str, *, path: str, line: int, test: str | None, column: str) -> float:
    """``float(text)`` or a ValueError naming the file, line, test, column and value.

    Stricter than :func:`float`: Python's digit separators (``1_3000``) are refused, as are NaN and infinities.
    """
    where = f"{path}, line {line}: " + (f"test {test!r}: " if test is not None else "")
    try:
        if "_" in text:
            raise ValueError(text)
        v = float(text)
    except (TypeError, ValueError):
        raise ValueError(f"{where}column {column!r} value {text!r} is not a number") from None
    if math.isnan(v):
        raise ValueError(f"{where}column {column!r} is NaN")
    if math.isinf(v):
        raise ValueError(f"{where}column {column!r} is infinite ({text!r})")
    return v


def _iter_rows(p: Path, spath: str) -> Iterator[tuple[int, list[str]]]:
    """Yield ``(line number, fields)`` of a CSV file; UTF-8 (a BOM is accepted).

    Undecodable bytes or NUL characters (a binary or garbage file) raise a
    ValueError naming the file and the line.
    """
    line_no = 0
    try:
        with p.open(newline="", encoding="utf-8-sig") as fh:
            reader = csv.reader(fh)
            for row in reader:
                line_no = reader.line_num
                yield line_no, row
    except UnicodeDecodeError as exc:
        raise ValueError(
            f"{spath}: not a UTF-8 text CSV file (undecodable byte at file offset {exc.start} near line "
            f"{line_no + 1}); expected a CSV with header {','.join(REQUIRED_COLUMNS)}"
        ) from None
    except csv.Error as exc:
        raise ValueError(
            f"{spath}, line {line_no + 1}: not a readable CSV file ({exc}); expected a CSV with header "
            f"{','.join(REQUIRED_COLUMNS)}"
        ) from None


def _check_header(header: list[str], spath: str) -> None:
    missing = [c for c in REQUIRED_COLUMNS if c not in header]
    if missing:
        raise ValueError(
            f"{spath}: missing column(s) {missing}; header is {header}, "
            f"required columns are {list(REQUIRED_COLUMNS)} (another layout: map its columns with --columns, "
            "e.g. t=Time,x=Disp,F=Load, and see --units, --fs)"
        )
    dup = [c for c in REQUIRED_COLUMNS if header.count(c) > 1]
    if dup:
        raise ValueError(
            f"{spath}: column(s) {dup} appear more than once in the header {header} (at positions "
            f"{[i + 1 for i, h in enumerate(header) if h in dup]}); which one is meant? Rename or drop the others"
        )


def read_csv_strict(path: str | Path) -> list[Record]:
    """Read a long CSV ``test,t,x,F`` row by row (the reference reader; every error names file and line).

    Parameters
    ----------
    path : str or Path
        Regular CSV file, UTF-8 (a BOM is accepted), header with the columns ``test``, ``t`` [s], ``x`` [mm],
        ``F`` [N] (extra columns are ignored, a required column twice is an error).

    Returns
    -------
    list of Record
        Not validated, in file order.

    Raises
    ------
    ValueError
        Naming the file, line and test: missing or duplicate columns, a row whose field count differs from
        the header's, a non-numeric value (also ``1_3000``), NaN, non-contiguous test rows, a binary file.
    """
    p = Path(path)
    spath = str(p)
    rows = _iter_rows(p, spath)
    header: list[str] | None = None
    for _, row in rows:
        if row and any(c.strip() for c in row):
            header = [h.strip() for h in row]
            break
    if header is None:
        raise ValueError(f"{spath}: file is empty; expected header {','.join(REQUIRED_COLUMNS)}")
    _check_header(header, spath)
    nf = len(header)
    it_, ix_, iF_ = (header.index(c) for c in ("t", "x", "F"))
    itest = header.index("test")
    # per test: growable float64 buffers (array.array: amortised O(1) append, ~8 bytes/value)
    cols: dict[str, tuple[array, array, array]] = {}
    order: list[str] = []
    last: str | None = None
    cur: tuple[array, array, array] | None = None
    for line_no, row in rows:
        if len(row) != nf:
            if not row or all(not c.strip() for c in row):
                continue
            raise ValueError(
                f"{spath}, line {line_no}: {len(row)} fields but the header has {nf} "
                f"({','.join(header)}); a decimal comma or a stray separator? "
                f"(row starts {','.join(row[:nf + 1])[:80]!r})"
            )
        test = row[itest].strip()
        if test != last:
            if test == "":
                if all(not c.strip() for c in row):
                    continue
                raise ValueError(f"{spath}, line {line_no}: empty test id")
            if test in cols:
                raise ValueError(
                    f"{spath}, line {line_no}: test {test!r}: rows are not contiguous "
                    f"(the test appears again after other tests)"
                )
            cur = (array("d"), array("d"), array("d"))
            cols[test] = cur
            order.append(test)
            last = test
        assert cur is not None
        for buf, j, c in ((cur[0], it_, "t"), (cur[1], ix_, "x"), (cur[2], iF_, "F")):
            cell = row[j]
            try:
                v = float(cell)
            except ValueError:
                v = parse_float(cell.strip(), path=spath, line=line_no, test=test, column=c)
            if not math.isfinite(v) or "_" in cell:
                parse_float(cell.strip(), path=spath, line=line_no, test=test, column=c)
            buf.append(v)
    if not order:
        raise ValueError(f"{spath}: no data rows")
    out = []
    for test in order:
        bt, bx, bF = cols.pop(test)
        out.append(Record(test, np.frombuffer(bt, dtype=float), np.frombuffer(bx, dtype=float),
                          np.frombuffer(bF, dtype=float)))
    return out


def _first_line_header(p: Path) -> list[str] | None:
    """The header if it is on line 1 and parses as one CSV row, else None (the strict reader decides)."""
    try:
        with p.open(newline="", encoding="utf-8-sig") as fh:
            line = fh.readline()
    except (UnicodeDecodeError, OSError):
        return None
    if not line.strip() or '"' in line:
        return None
    return [h.strip() for h in line.rstrip("\r\n").split(",")]


def read_canonical_csv(path: str | Path) -> list[Record]:
    """Read a long CSV ``test,t,x,F`` fast (pyarrow), else by :func:`read_csv_strict`; same records, same errors.

    Parameters
    ----------
    path : str or Path
        As :func:`read_csv_strict`.

    Returns
    -------
    list of Record
        Not validated, in file order; t [s], x [mm], F [N].  The arrays of all tests are views into three
        arrays of the whole file (no copy per test), filled batch by batch (peak memory ~ the data).
    """
    p = Path(path)
    header = _first_line_header(p)
    if header is None or any(header.count(c) != 1 for c in REQUIRED_COLUMNS):
        return read_csv_strict(p)
    try:
        import pyarrow as pa
        import pyarrow.csv as pacsv
    except ImportError:
        return read_csv_strict(p)
    try:
        runs, cols = _stream(p, header, pa, pacsv)
    except (pa.ArrowException, ValueError):
        return read_csv_strict(p)  # anything irregular: the strict reader reads it again and names the line
    finally:
        # pyarrow's allocator keeps the parse buffers it freed (~0.4x a text file here): give them back before
        # the records are validated, or that memory stays resident on top of the validation's own
        pa.default_memory_pool().release_unused()
    t, x, F = cols
    return [Record(test, t[s:e], x[s:e], F[s:e]) for test, s, e in runs]


class _Irregular(ValueError):
    """Something the strict reader must look at (it raises the precise error, or reads what is fine)."""


def _stream(p: Path, header: list[str], pa, pacsv) -> tuple[list[tuple[str, int, int]], list[np.ndarray]]:
    """Parse batch by batch into three float arrays sized for the file's largest possible row count.

    The arrays are allocated once for ``file size / 8`` rows (no row of ``test,t,x,F`` is shorter than 8 bytes)
    and filled in order; pages never written are never touched, so the resident memory is the data itself
    (24 bytes per row) plus a few batches, never an Arrow table and its numpy copy at once.
    """
    import pyarrow.compute as pc

    names = [f"c{i}" for i in range(len(header))]
    pos = {c: f"c{header.index(c)}" for c in REQUIRED_COLUMNS}
    types = {pos["test"]: pa.string(), pos["t"]: pa.float64(), pos["x"]: pa.float64(), pos["F"]: pa.float64()}
    reader = pacsv.open_csv(
        p, read_options=pacsv.ReadOptions(skip_rows=1, column_names=names, block_size=1 << 20),
        parse_options=pacsv.ParseOptions(delimiter=","),
        convert_options=pacsv.ConvertOptions(include_columns=list(pos.values()), column_types=types,
                                             null_values=[], strings_can_be_null=False,
                                             quoted_strings_can_be_null=False))
    cap = p.stat().st_size // 8 + 1
    cols = [np.empty(cap) for _ in range(3)]
    runs: list[list] = []  # [test, start, end]
    seen: set[str] = set()
    n = 0
    for batch in reader:
        m = batch.num_rows
        if m == 0:
            continue
        if n + m > cap:  # cannot happen for a valid file (rows >= 8 bytes); be safe
            raise _Irregular("more rows than the file size allows")
        for k, role in enumerate(("t", "x", "F")):
            a = batch.column(batch.schema.get_field_index(pos[role]))
            if a.null_count:
                raise _Irregular("null")
            v = a.to_numpy()
            if not np.isfinite(v).all():
                raise _Irregular("not finite")
            cols[k][n:n + m] = v
        ree = pc.run_end_encode(batch.column(batch.schema.get_field_index(pos["test"])))
        start = n
        for end, test in zip(ree.run_ends.to_numpy(), ree.values.to_pylist()):
            if runs and runs[-1][0] == test:
                runs[-1][2] = n + int(end)
            else:
                if not test or test != test.strip() or test in seen:
                    raise _Irregular("test id")  # empty, padded, or rows not contiguous
                seen.add(test)
                runs.append([test, start, n + int(end)])
            start = n + int(end)
        n += m
    if n == 0:
        raise _Irregular("no rows")
    return [(r[0], r[1], r[2]) for r in runs], [c[:n] for c in cols]
