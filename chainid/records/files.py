"""Force–displacement records: CSV in/out, validation, harmonic estimation, steady cycles.

File format (long CSV, architecture contract)::

    test,t,x,F
    T1,0.000,0.0000,12.3
    ...

``test`` is an id string, ``t`` time [s], ``x`` elongation [mm], ``F`` tension [N].
Any number of tests; the rows of one test are contiguous; ``t`` is strictly
increasing within a test.  Extra columns are ignored.

Each test is a displacement-controlled harmonic test (paper Eq. 18, 25)::

    x(t) = x0 + A sin(omega t + theta)      after an optional ramp

The harmonic estimate lives in :mod:`chainid.signal.harmonic` and the steady-cycle
selection in :mod:`chainid.signal.steady`; their public names (:class:`HarmonicEstimate`,
:func:`estimate_harmonic`, :class:`SteadyWindow`, :func:`select_steady`) are
re-exported here.  This module reads and writes records, validates them
(:func:`validate_record`); the analysis of one record (:func:`analyse_record`,
:func:`try_analyse`) lives in :mod:`chainid.records.validate` and is re-exported here.

Input files are never modified; :func:`write_records` refuses to overwrite an
existing file unless ``overwrite=True``.
"""
from __future__ import annotations

import csv
import math
from array import array
from pathlib import Path
from typing import Iterable, Iterator

import numpy as np

from chainid.records.record import Record
from chainid.records.validate import analyse_record, check_data, try_analyse, validate_record
from chainid.signal.harmonic import HarmonicEstimate, estimate_harmonic
from chainid.signal.steady import SteadyWindow, select_steady

__all__ = [
    "Record",
    "HarmonicEstimate",
    "SteadyWindow",
    "read_records",
    "write_records",
    "validate_record",
    "estimate_harmonic",
    "select_steady",
    "analyse_record",
    "try_analyse",
    "check_data",
    "read_side_file",
    "write_side_file",
    "REQUIRED_COLUMNS",
]

REQUIRED_COLUMNS = ("test", "t", "x", "F")


# ----------------------------------------------------------------------------
# CSV in / out
# ----------------------------------------------------------------------------
def _parse_float(text: str, *, path: str, line: int, test: str, column: str) -> float:
    try:
        v = float(text)
    except (TypeError, ValueError):
        raise ValueError(
            f"{path}, line {line}: test {test!r}: column {column!r} value {text!r} is not a number"
        ) from None
    if math.isnan(v):
        raise ValueError(f"{path}, line {line}: test {test!r}: column {column!r} is NaN")
    if math.isinf(v):
        raise ValueError(f"{path}, line {line}: test {test!r}: column {column!r} is infinite ({text!r})")
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


def read_records(
    path: str | Path,
    *,
    validate: bool = True,
    allow_compression: bool = False,
    min_cycles: float = 2.0,
    min_snr: float = 3.0,
    steady_tol: float | None = None,
) -> list[Record]:
    """Read a long-format CSV ``test,t,x,F`` into a list of :class:`Record`.

    The file is read row by row into preallocated float arrays (8 bytes per
    value, 24 bytes per row), so the peak memory stays below the file size
    plus the arrays themselves (measured in ``benchmarks/records_bench.py``).

    Parameters
    ----------
    path : str or Path
        CSV file (UTF-8, a byte-order mark is accepted); header must contain the
        columns ``test``, ``t`` [s], ``x`` [mm], ``F`` [N].  Every row must have
        as many fields as the header (a decimal comma ``261,004688`` in an
        unquoted cell is an error, never read as 261).  The file is only read,
        never modified.
    validate : bool
        Run :func:`validate_record` on every test (default True).
    allow_compression : bool
        Accept negative (compressive) forces.  False for chain data (a chain
        cannot push); True for parts whose force changes sign (e.g. a friction
        damper identified with ``--model linear``).
    min_cycles : float
        Minimum number of whole oscillation cycles per test (default 2).
    min_snr : float
        Minimum ratio amplitude / RMS noise of x (default 3).
    steady_tol : float or None
        Steady-cycle tolerance for validation (fraction); None = adaptive.

    Returns
    -------
    list of Record
        In file order.

    Raises
    ------
    ValueError
        Naming the file, line and test: missing columns, a row whose field
        count differs from the header's, non-numeric value, NaN, non-contiguous
        test rows, a binary/non-UTF-8 file, and every :func:`validate_record`
        problem.
    """
    p = Path(path)
    if not p.is_file():
        raise ValueError(f"records file {str(p)!r} does not exist")
    spath = str(p)
    rows = _iter_rows(p, spath)
    header: list[str] | None = None
    for _, row in rows:
        if row and any(c.strip() for c in row):
            header = [h.strip() for h in row]
            break
    if header is None:
        raise ValueError(f"{spath}: file is empty; expected header {','.join(REQUIRED_COLUMNS)}")
    missing = [c for c in REQUIRED_COLUMNS if c not in header]
    if missing:
        raise ValueError(
            f"{spath}: missing column(s) {missing}; header is {header}, "
            f"required columns are {list(REQUIRED_COLUMNS)}"
        )
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
                v = _parse_float(cell.strip(), path=spath, line=line_no, test=test, column=c)
            if not math.isfinite(v):
                _parse_float(cell.strip(), path=spath, line=line_no, test=test, column=c)
            buf.append(v)
    if not order:
        raise ValueError(f"{spath}: no data rows")
    records = []
    for test in order:
        bt, bx, bF = cols.pop(test)
        rec = Record(test, np.frombuffer(bt, dtype=float), np.frombuffer(bx, dtype=float),
                     np.frombuffer(bF, dtype=float))
        if validate:
            try:
                rec.estimate = validate_record(
                    rec, allow_compression=allow_compression, min_cycles=min_cycles, min_snr=min_snr,
                    steady_tol=steady_tol,
                )
            except ValueError as exc:
                raise ValueError(f"{spath}: {exc}") from None
        records.append(rec)
    return records


def write_records(path: str | Path, records: Iterable[Record], overwrite: bool = False) -> Path:
    """Write records as long-format CSV ``test,t,x,F``.

    Parameters
    ----------
    path : str or Path
        Output file.
    records : iterable of Record
        Tests to write (t [s], x [mm], F [N]).
    overwrite : bool
        Replace an existing file.  Default False: an existing file is an error.

    Returns
    -------
    Path
        The written path.

    Raises
    ------
    ValueError
        If ``path`` exists and ``overwrite`` is False (naming the path), or if a
        test id contains a comma or newline.
    """
    from chainid.infra.fileio import atomic_open  # temp file in the target folder + rename: never a partial CSV

    p = Path(path)
    records = list(records)
    for r in records:
        if any(ch in r.test for ch in ",\n\r\""):
            raise ValueError(f"test id {r.test!r} must not contain commas, quotes or newlines")
    with atomic_open(p, "w", force=overwrite, what="records", newline="") as fh:
        fh.write("test,t,x,F\n")
        for r in records:
            for ti, xi, Fi in zip(r.t, r.x, r.F):
                fh.write(f"{r.test},{ti:.9g},{xi:.9g},{Fi:.9g}\n")
    return p


# ----------------------------------------------------------------------------
# Side file (omega, x0, A per test)
# ----------------------------------------------------------------------------
def read_side_file(path: str | Path) -> dict[str, tuple[float, float, float]]:
    """Read a side file ``test,omega,x0,A`` (omega rad/s, x0 mm, A mm).

    Returns
    -------
    dict
        test id -> (omega, x0, A).

    Raises
    ------
    ValueError
        Missing file or column, a bad cell, omega or A not > 0, or two rows for one test (line numbers named).
    """
    p = Path(path)
    if not p.is_file():
        raise ValueError(f"side file {str(p)!r} does not exist")
    out: dict[str, tuple[float, float, float]] = {}
    first: dict[str, int] = {}
    with p.open(newline="") as fh:
        reader = csv.DictReader(fh)
        cols = [c.strip() for c in (reader.fieldnames or [])]
        missing = [c for c in ("test", "omega", "x0", "A") if c not in cols]
        if missing:
            raise ValueError(f"{str(p)}: missing column(s) {missing}; required test,omega,x0,A")
        for line_no, row in enumerate(reader, start=2):
            row = {k.strip(): (v or "").strip() for k, v in row.items() if k is not None}
            test = row["test"]
            vals = tuple(
                _parse_float(row[c], path=str(p), line=line_no, test=test, column=c) for c in ("omega", "x0", "A")
            )
            if vals[0] <= 0:
                raise ValueError(f"{str(p)}, line {line_no}: test {test!r}: omega = {vals[0]} rad/s must be > 0")
            if vals[2] <= 0:
                raise ValueError(f"{str(p)}, line {line_no}: test {test!r}: A = {vals[2]} mm must be > 0")
            if test in out:  # two rows for one test: which one is meant? never pick one silently
                raise ValueError(f"{str(p)}, line {line_no}: test {test!r} appears twice (line {first[test]} "
                                 "too); give one row per test")
            first[test] = line_no
            out[test] = vals  # type: ignore[assignment]
    return out


def write_side_file(path: str | Path, estimates: dict[str, HarmonicEstimate], overwrite: bool = False) -> Path:
    """Write ``test,omega,x0,A`` (rad/s, mm, mm) for the given estimates."""
    from chainid.infra.fileio import atomic_open

    p = Path(path)
    with atomic_open(p, "w", force=overwrite, what="side file", newline="") as fh:
        fh.write("test,omega,x0,A\n")
        for k, e in estimates.items():
            fh.write(f"{k},{e.omega:.10g},{e.x0:.10g},{e.A:.10g}\n")
    return p
