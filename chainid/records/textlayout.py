"""Where the data of a delimited text file are: the header block and its metadata, the column-name line (by
``skip_rows``, by ``header_marker`` or by content), the delimiter, the names, the first data line.

What ``skip_rows`` counts: the physical lines (blank ones included) *above* the column-name line, or above the
first data row of a file without names.  A DAQ's ``Header Size: N`` line counts the block *with* its name line, so
the names are on line N and ``skip_rows`` must be N − 1; a file that says so while ``skip_rows`` disagrees is one
error saying which value fits (a line taken as the names that looks like a data row is refused too: a data row is
never lost silently).  Lines ``Key: value`` above the names are the file's metadata; ``Sampling Interval`` [s] and
``Sampling Rate`` [Hz] give the time step of a file without a time column (when ``fs`` is not given).
"""
from __future__ import annotations

import csv
import math
import re
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

from chainid.records.patterns import bounded_search, check_pattern
from chainid.records.readerspec import ReaderSpec

__all__ = ["HEAD_LINES", "TextLayout", "split_fields", "is_number", "text_layout"]

#: Lines read to find the column names (and searched by ``header_marker``); the header block must be within them.
HEAD_LINES = 1000
_SAMPLE = 200  # data lines whose field counts give the common row length
_META = re.compile(r"^\s*([A-Za-z][A-Za-z0-9 _./()-]*?)\s*[:=]\s*(.*?)\s*$")


@dataclass(frozen=True)
class TextLayout:
    """Where the data of a text file are: delimiter, column names, first data line (1-based), field count.

    ``n_common`` is the most common field count of the first data rows (rows of a ragged file may lack trailing
    fields: an ``Events`` column filled on event rows only); ``data_offset`` the byte offset of the first data
    line; ``meta`` the ``Key: value`` lines above the names (keys lower-case); ``dt`` [s] the time step they state.
    """

    delimiter: str
    names: list[str]
    positional: bool
    data_line: int
    n_fields: int
    n_common: int = 0
    data_offset: int = 0
    meta: dict[str, str] = field(default_factory=dict)
    dt: float | None = None


def split_fields(line: str, delim: str) -> list[str]:
    """The fields of one line (runs of whitespace for ``" "``, else CSV quoting rules)."""
    if delim == " ":
        return line.split()
    return next(csv.reader([line], delimiter=delim))


def is_number(s: str, decimal: str) -> bool:
    """True for a decimal number as a rig writes it (``1.5``, ``-2e3``; ``1,5`` with a decimal comma)."""
    s = s.strip()
    if decimal == ",":
        s = s.replace(",", ".")
    try:
        float(s)
    except ValueError:
        return False
    return "_" not in s


def _head(path: Path) -> tuple[list[str], list[int]]:
    """The first :data:`HEAD_LINES` lines (without line ends) and the byte offset after each."""
    spath = str(path)
    lines: list[str] = []
    ends: list[int] = []
    pos = 0
    with path.open("rb") as fh:
        for raw in fh:
            pos += len(raw)
            try:
                text = raw.decode("utf-8-sig" if not lines else "utf-8")
            except UnicodeDecodeError as exc:
                raise ValueError(f"{spath}: not a UTF-8 text file (undecodable byte at file offset "
                                 f"{pos - len(raw) + exc.start} near line {len(lines) + 1})") from None
            if "\x00" in text:
                raise ValueError(f"{spath}, line {len(lines) + 1}: a NUL byte: a binary file, not text records")
            lines.append(text.rstrip("\r\n"))
            ends.append(pos)
            if len(lines) >= HEAD_LINES:
                break
    return lines, ends


def _metadata(lines: list[str]) -> dict[str, str]:
    out: dict[str, str] = {}
    for ln in lines:
        m = _META.match(ln)
        if m and m.group(2):
            out.setdefault(m.group(1).strip().lower(), m.group(2))
    return out


def _header_size(path: Path, lines: list[str], spec: ReaderSpec) -> None:
    """Refuse a ``skip_rows`` that disagrees with the file's own ``Header Size: N`` line (see the module doc)."""
    for k, ln in enumerate(lines[:50]):
        m = re.match(r"^\s*header\s*size\s*[:=]\s*(\d+)\s*$", ln, flags=re.I)
        if not m:
            continue
        n = int(m.group(1))
        if k >= n or n > len(lines):
            return  # not the header block's own size line
        if spec.skip_rows != n - 1:
            raise ValueError(f"{path}, line {k + 1}: the file says {ln.strip()!r}, a block of {n} lines counting "
                             f"the column-name line, so the names are on line {n}: --skip-rows counts the lines "
                             f"above the names and must be {n - 1}, not {spec.skip_rows} (or give --header-marker)")
        return


def _name_line(path: Path, lines: list[str], spec: ReaderSpec) -> int:
    """0-based index of the column-name line (or of the first data row of a file without names)."""
    if spec.header_marker is not None:
        rx = check_pattern(spec.header_marker, "--header-marker")
        for i in range(spec.skip_rows, len(lines)):
            if bounded_search(rx, lines[i][:4096], "--header-marker"):
                return i
        raise ValueError(f"{path}: no line among the first {len(lines)} (after {spec.skip_rows} skipped) matches "
                         f"--header-marker {spec.header_marker!r}")
    _header_size(path, lines, spec)
    for i in range(spec.skip_rows, len(lines)):
        if lines[i].strip():
            return i
    raise ValueError(f"{path}: no line after the {spec.skip_rows} skipped row(s): the file is empty")


def _sniff(first: str, spec: ReaderSpec) -> str:
    delim = spec.delimiter
    if delim is None:
        delim = next((d for d in ("\t", ";", ",", "|") if d in first), " ")
        if delim == "," and spec.decimal == ",":
            delim = ";" if ";" in first else " "
    return delim


def _looks_like_data(path: Path, i: int, fields: list[str], lines: list[str], delim: str, spec: ReaderSpec) -> None:
    """A line taken as the names whose numbers sit where the next line has numbers is a data row: refuse."""
    num = [j for j, f in enumerate(fields) if is_number(f, spec.decimal)]
    if not num:
        return
    nxt = next((ln for ln in lines[i + 1:] if ln.strip()), None)
    if nxt is None:
        return
    other = [f.strip() for f in split_fields(nxt, delim)]
    if all(j < len(other) and is_number(other[j], spec.decimal) for j in num):
        raise ValueError(f"{path}, line {i + 1} was taken as the column names but looks like a data row (field(s) "
                         f"{[j + 1 for j in num]} are numbers, as on the next line): is --skip-rows one too many "
                         f"(it is {spec.skip_rows})? For a file without names give header = false or --names")


def _time_step(meta: dict[str, str]) -> float | None:
    """The time step [s] the metadata state (``Sampling Interval`` in s, else 1 / ``Sampling Rate`` in Hz)."""
    for key, inv in (("sampling interval", False), ("sample interval", False), ("sampling rate", True),
                     ("sample rate", True)):
        if key in meta:
            try:
                v = float(meta[key].split()[0])
            except (ValueError, IndexError):
                continue
            if math.isfinite(v) and v > 0:
                return 1.0 / v if inv else v
    return None


def text_layout(path: Path, spec: ReaderSpec) -> TextLayout:
    """Find the header block, the names and the first data line; sniff the delimiter (see the module docstring).

    Raises
    ------
    ValueError
        Not UTF-8 text, no line after the header block, no line matching ``header_marker``, a ``skip_rows`` the
        file's ``Header Size`` contradicts, a data row taken as names, duplicate column names.
    """
    spath = str(path)
    lines, ends = _head(path)
    i = _name_line(path, lines, spec)
    first = lines[i]
    delim = _sniff(first, spec)
    fields = [f.strip() for f in split_fields(first, delim)]
    meta = _metadata(lines[:i])
    if spec.names is not None:
        names, positional = list(spec.names), False
        has_line = spec.header if spec.header is not None else not all(is_number(f, spec.decimal) for f in fields)
    else:
        has_line = spec.header if spec.header is not None else not all(is_number(f, spec.decimal) for f in fields)
        if has_line and spec.header is None and spec.header_marker is None:
            _looks_like_data(path, i, fields, lines, delim, spec)
        names, positional = (fields, False) if has_line else ([str(j + 1) for j in range(len(fields))], True)
    if not positional:
        dup = sorted({f for f in names if names.count(f) > 1 and f})
        if dup:
            raise ValueError(f"{spath}, line {i + 1}: column name(s) {dup} appear more than once in the header "
                             f"{names}; which one is meant? Rename or drop the others")
    d0 = i + 1 if has_line else i  # 0-based index of the first data line
    counts = Counter(len(split_fields(ln, delim)) for ln in lines[d0:d0 + _SAMPLE] if ln.strip())
    n_common = min(counts.most_common(1)[0][0], len(names)) if counts else len(names)
    offset = ends[d0 - 1] if d0 > 0 else 0
    return TextLayout(delim, names, positional, d0 + 1, len(names), n_common, offset, meta, _time_step(meta))
