"""Force–displacement records: CSV in/out, validation, harmonic estimation, steady cycles.

File format (long CSV, architecture contract; other layouts and formats through
:class:`~chainid.records.spec.ReaderSpec` and :func:`~chainid.records.reader.read_any`)::

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
from pathlib import Path
from typing import Iterable, Sequence

from chainid.records.reader import read_any
from chainid.records.record import Record
from chainid.records.spec import ReaderSpec
from chainid.records.textcanon import REQUIRED_COLUMNS, parse_float
from chainid.records.writer import write_canonical
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

# ----------------------------------------------------------------------------
# Records in / out
# ----------------------------------------------------------------------------
def read_records(
    path: str | Path | Sequence[str | Path],
    *,
    validate: bool = True,
    allow_compression: bool = False,
    min_cycles: float = 2.0,
    min_snr: float = 3.0,
    steady_tol: float | None = None,
    spec: ReaderSpec | None = None,
) -> list[Record]:
    """Read records into a list of :class:`Record` (t [s], x [mm], F [N]).

    Without ``spec`` and given one file, the file is the canonical long CSV ``test,t,x,F`` (read by
    :func:`chainid.records.textcanon.read_canonical_csv`: pyarrow's parser with the strict row reader's
    errors).  Otherwise :func:`chainid.records.reader.read_any` reads any layout and format.

    Parameters
    ----------
    path : str, Path or sequence
        CSV file (UTF-8, a byte-order mark is accepted); header must contain the
        columns ``test``, ``t`` [s], ``x`` [mm], ``F`` [N].  Every row must have
        as many fields as the header (a decimal comma ``261,004688`` in an
        unquoted cell is an error, never read as 261).  With a ``spec``: also a
        directory or glob of one file per test, in any format of :mod:`chainid.records.formats`.
        Files are only read, never modified.
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
    spec : ReaderSpec or None
        Columns, units, sampling rate, signs and text layout of the rig's files (None: canonical).

    Returns
    -------
    list of Record
        In file order.

    Raises
    ------
    ValueError
        Naming the file, line and test: missing or duplicate columns, a row whose field
        count differs from the header's, non-numeric value (also ``1_3000``), NaN,
        non-contiguous test rows, a binary/non-UTF-8 file, a directory with no records,
        a FIFO or device, and every :func:`validate_record` problem.
    """
    records = read_any(path, spec)
    spath = str(path) if isinstance(path, (str, Path)) else ", ".join(str(q) for q in path)
    if validate:
        for rec in records:
            try:
                rec.estimate = validate_record(
                    rec, allow_compression=allow_compression, min_cycles=min_cycles, min_snr=min_snr,
                    steady_tol=steady_tol,
                )
            except ValueError as exc:
                raise ValueError(f"{spath}: {exc}") from None
    return records


def write_records(path: str | Path, records: Iterable[Record], overwrite: bool = False) -> Path:
    """Write records as long-format CSV ``test,t,x,F`` (or Parquet by the suffix ``.parquet``).

    Numbers are written as text that reads back to the identical float64, at most 17 significant digits
    (see :func:`chainid.records.writer.write_canonical`); the file appears atomically.

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
        test id contains a comma, quote or newline, or appears twice.
    """
    return write_canonical(path, records, overwrite=overwrite)


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
                parse_float(row[c], path=str(p), line=line_no, test=test, column=c) for c in ("omega", "x0", "A")
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
