"""Delimited text records as rigs write them: a header block, the rig's column names or none, any delimiter
(comma, semicolon, tab, runs of whitespace), a decimal comma.

The layout (header block, delimiter, header or not) is read from the first lines; the columns in use are then
parsed fast (pyarrow's CSV reader; numpy's C ``loadtxt`` for whitespace-separated numbers).  If the fast parse
fails or finds a NaN, the file is scanned line by line (:func:`scan_strict`), which raises the error naming the
file, the line, the column and the value; it is also the reader when pyarrow is not installed.
"""
from __future__ import annotations

import csv
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from chainid.records.spec import ReaderSpec
from chainid.records.table import RawTable, resolve_roles
from chainid.records.textcanon import parse_float

__all__ = ["TextLayout", "text_layout", "scan_strict", "read_text_table"]


@dataclass(frozen=True)
class TextLayout:
    """Where the data of a text file are: delimiter, column names, first data line (1-based), field count."""

    delimiter: str
    names: list[str]
    positional: bool
    data_line: int
    n_fields: int


def _split(line: str, delim: str) -> list[str]:
    if delim == " ":
        return line.split()
    return next(csv.reader([line], delimiter=delim))


def _is_number(s: str, decimal: str) -> bool:
    s = s.strip()
    if decimal == ",":
        s = s.replace(",", ".")
    try:
        float(s)
    except ValueError:
        return False
    return "_" not in s


def text_layout(path: Path, spec: ReaderSpec) -> TextLayout:
    """Skip ``spec.skip_rows`` lines and blank lines; sniff the delimiter; decide whether there is a header.

    Raises
    ------
    ValueError
        Not UTF-8 text, no line after the header block, duplicate column names in the header.
    """
    spath = str(path)
    line_no, first = 0, None
    try:
        with path.open(encoding="utf-8-sig", newline="") as fh:
            for line_no, line in enumerate(fh, start=1):
                if "\x00" in line:
                    raise ValueError(f"{spath}, line {line_no}: a NUL byte: a binary file, not text records")
                if line_no > spec.skip_rows and line.strip():
                    first = line.rstrip("\r\n")
                    break
    except UnicodeDecodeError as exc:
        raise ValueError(f"{spath}: not a UTF-8 text file (undecodable byte at file offset {exc.start} near line "
                         f"{line_no + 1})") from None
    if first is None:
        raise ValueError(f"{spath}: no line after the {spec.skip_rows} skipped row(s): the file is empty")
    delim = spec.delimiter
    if delim is None:
        delim = next((d for d in ("\t", ";", ",", "|") if d in first), " ")
        if delim == "," and spec.decimal == ",":
            delim = ";" if ";" in first else " "
    fields = [f.strip() for f in _split(first, delim)]
    header = spec.header if spec.header is not None else not all(_is_number(f, spec.decimal) for f in fields)
    if header:
        dup = sorted({f for f in fields if fields.count(f) > 1 and f})
        if dup:
            raise ValueError(f"{spath}, line {line_no}: column name(s) {dup} appear more than once in the header "
                             f"{fields}; which one is meant? Rename or drop the others")
        return TextLayout(delim, fields, False, line_no + 1, len(fields))
    return TextLayout(delim, [str(i + 1) for i in range(len(fields))], True, line_no, len(fields))


def scan_strict(path: Path, lay: TextLayout, use: dict[str, str], decimal: str) -> dict[str, np.ndarray]:
    """Parse the used columns line by line; the first bad cell raises naming file, line, column and value."""
    spath = str(path)
    idx = {name: lay.names.index(name) for name in use.values()}
    role_of = {name: role for role, name in use.items()}
    vals: dict[str, list] = {name: [] for name in idx}
    with path.open(encoding="utf-8-sig", newline="") as fh:
        for line_no, line in enumerate(fh, start=1):
            if line_no < lay.data_line or not line.strip():
                continue
            row = _split(line.rstrip("\r\n"), lay.delimiter)
            if len(row) != lay.n_fields:
                raise ValueError(f"{spath}, line {line_no}: {len(row)} fields but the "
                                 f"{'header' if not lay.positional else 'first data row'} has {lay.n_fields}; "
                                 f"a decimal comma or a stray separator? (row starts {line[:80]!r})")
            for name, j in idx.items():
                cell = row[j].strip()
                if role_of[name] == "test":
                    vals[name].append(cell)
                    continue
                text = cell
                if decimal == ",":
                    if "." in cell:
                        raise ValueError(f"{spath}, line {line_no}: column {name!r} value {cell!r}: a '.' in a "
                                         "file read with --decimal ','")
                    text = cell.replace(",", ".")
                try:
                    vals[name].append(parse_float(text, path=spath, line=line_no, test=None, column=name))
                except ValueError as exc:
                    raise ValueError(str(exc).replace(repr(text), repr(cell))) from None
    out = {}
    for name, v in vals.items():
        out[name] = np.asarray(v, dtype=str if role_of[name] == "test" else float)
    if not out or next(iter(out.values())).size == 0:
        raise ValueError(f"{spath}: no data rows after line {lay.data_line - 1}")
    return out


def _fast(path: Path, lay: TextLayout, use: dict[str, str], decimal: str) -> dict[str, np.ndarray] | None:
    """The used columns by pyarrow (or numpy for whitespace); None when anything is irregular."""
    names = list(use.values())
    numeric = [n for r, n in use.items() if r != "test"]
    if lay.delimiter == " ":
        if "test" in use or decimal == ",":
            return None
        cols = [lay.names.index(n) for n in names]
        try:  # every column (loadtxt refuses ragged rows only then); a text column sends the file to the scan
            a = np.loadtxt(path, skiprows=lay.data_line - 1, ndmin=2, comments=None, encoding="utf-8-sig")
        except (ValueError, UnicodeDecodeError):
            return None
        if a.shape[0] == 0 or a.shape[1] != lay.n_fields or not np.isfinite(a[:, cols]).all():
            return None
        return {n: np.ascontiguousarray(a[:, k]) for k, n in zip(cols, names)}
    try:
        import pyarrow as pa
        import pyarrow.csv as pacsv
    except ImportError:
        return None
    cn = [f"c{i}" for i in range(lay.n_fields)]
    key = {n: cn[lay.names.index(n)] for n in names}
    types = {key[n]: pa.float64() for n in numeric}
    if "test" in use:
        types[key[use["test"]]] = pa.string()
    try:
        table = pacsv.read_csv(
            path, read_options=pacsv.ReadOptions(skip_rows=lay.data_line - 1, column_names=cn, block_size=1 << 20),
            parse_options=pacsv.ParseOptions(delimiter=lay.delimiter),
            convert_options=pacsv.ConvertOptions(include_columns=list(key.values()), column_types=types,
                                                 null_values=[], strings_can_be_null=False, decimal_point=decimal))
    except (pa.ArrowException, ValueError):
        return None
    if table.num_rows == 0:
        return None
    out = {}
    for n in names:
        col = table.column(key[n])
        if col.null_count:
            return None
        a = col.to_numpy(zero_copy_only=False)
        if n in numeric and not np.isfinite(a).all():
            return None
        out[n] = a
    return out


def read_text_table(path: Path, spec: ReaderSpec) -> RawTable:
    """The columns a spec uses of one text file, as a :class:`RawTable` (names as in the file, or positions)."""
    lay = text_layout(path, spec)
    use = resolve_roles(lay.names, spec, str(path), lay.positional)
    cols = _fast(path, lay, use, spec.decimal)
    if cols is None:
        cols = scan_strict(path, lay, use, spec.decimal)
    return RawTable(str(path), {n: cols[n] for n in lay.names if n in cols}, None, lay.positional, use)
