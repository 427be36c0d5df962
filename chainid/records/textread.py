"""Delimited text records as rigs write them: a header block, the rig's column names or none, any delimiter
(comma, semicolon, tab, runs of whitespace), a decimal comma, ragged rows.

The layout (header block, delimiter, names) comes from :mod:`.textlayout`; the columns in use are then parsed
fast (pyarrow's CSV reader; numpy's C ``loadtxt`` for whitespace-separated numbers).  **Ragged rows**: a row
with fewer fields than the names has its missing trailing fields empty (a DAQ's ``Events`` column, filled on
event rows only); pyarrow reads the rows of the common length and hands the others (with their row numbers) to
a small Python parse that puts them back in place, so a ragged file stays on the fast path.  A **bad line** (more
fields than the names, an empty or unreadable value in a used column) is an error naming the file, the line, the
column and the value, or, with ``bad_lines = warn|skip``, is left out and counted.  Whenever the fast parse meets
anything irregular, the file is scanned line by line (:func:`scan_strict`), which applies that policy; it is also
the reader when pyarrow is not installed.
"""
from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from chainid.records.plan import plan_columns
from chainid.records.readerspec import ReaderSpec
from chainid.records.table import RawTable
from chainid.records.textcanon import parse_float
from chainid.records.textlayout import TextLayout, split_fields, text_layout

__all__ = ["TextLayout", "text_layout", "scan_strict", "read_text_table"]

_TEXT_KEYS = ("test", "events")


def _float_cell(cell: str, decimal: str, spath: str, line_no: int, name: str) -> float:
    text = cell
    if decimal == ",":
        if "." in cell:
            raise ValueError(f"{spath}, line {line_no}: column {name!r} value {cell!r}: a '.' in a file read with "
                             "--decimal ','")
        text = cell.replace(",", ".")
    try:
        return parse_float(text, path=spath, line=line_no, test=None, column=name)
    except ValueError as exc:
        raise ValueError(str(exc).replace(repr(text), repr(cell))) from None


def _parse_row(row: list[str], lay: TextLayout, idx: dict[str, int], text: set[str], decimal: str, spath: str,
               line_no: int, line: str) -> dict[str, Any]:
    """The used cells of one row; a ValueError naming the line for a bad row."""
    if len(row) > lay.n_fields:
        raise ValueError(f"{spath}, line {line_no}: {len(row)} fields but the "
                         f"{'header' if not lay.positional else 'first data row'} has {lay.n_fields}; "
                         f"a decimal comma or a stray separator? (row starts {line[:80]!r})")
    out: dict[str, Any] = {}
    for name, j in idx.items():
        cell = row[j].strip() if j < len(row) else ""
        if name in text:
            out[name] = cell
        elif j >= len(row):
            raise ValueError(f"{spath}, line {line_no}: {len(row)} fields but the "
                             f"{'header' if not lay.positional else 'first data row'} has {lay.n_fields}: "
                             f"column {name!r} is missing (row starts {line[:80]!r})")
        else:
            out[name] = _float_cell(cell, decimal, spath, line_no, name)
    return out


def scan_strict(path: Path, lay: TextLayout, use: dict[str, str], decimal: str, policy: str = "error",
                stats: dict | None = None) -> dict[str, np.ndarray]:
    """Parse the used columns line by line; a bad line raises naming file, line, column and value (``policy``
    ``error``), or is left out and counted in ``stats`` (``warn``/``skip``: ``stats["bad"]``, ``stats["first"]``)."""
    spath = str(path)
    idx = {name: lay.names.index(name) for name in use.values()}
    text = {use[k] for k in _TEXT_KEYS if k in use}
    vals: dict[str, list] = {name: [] for name in idx}
    bad, first = 0, None
    with path.open(encoding="utf-8-sig", newline="") as fh:
        for line_no, line in enumerate(fh, start=1):
            if line_no < lay.data_line or not line.strip():
                continue
            raw = line.rstrip("\r\n")
            try:
                cells = _parse_row(split_fields(raw, lay.delimiter), lay, idx, text, decimal, spath, line_no, raw)
            except ValueError as exc:
                if policy == "error":
                    raise
                bad += 1
                first = first or str(exc)
                continue
            for name, v in cells.items():
                vals[name].append(v)
    if stats is not None:
        stats.update(bad=bad, first=first)
    out = {name: np.asarray(v, dtype=object if name in text else float) for name, v in vals.items()}
    if not out or next(iter(out.values())).size == 0:
        raise ValueError(f"{spath}: no data rows after line {lay.data_line - 1}"
                         + (f" ({bad} bad line(s) left out; the first: {first})" if bad else ""))
    return out


def _whitespace(path: Path, lay: TextLayout, use: dict[str, str], decimal: str) -> dict[str, np.ndarray] | None:
    names = list(use.values())
    if any(k in use for k in _TEXT_KEYS) or decimal == ",":
        return None
    cols = [lay.names.index(n) for n in names]
    try:  # every column (loadtxt refuses ragged rows only then); a text column sends the file to the scan
        a = np.loadtxt(path, skiprows=lay.data_line - 1, ndmin=2, comments=None, encoding="utf-8-sig")
    except (ValueError, UnicodeDecodeError):
        return None
    if a.shape[0] == 0 or a.shape[1] != lay.n_fields or not np.isfinite(a[:, cols]).all():
        return None
    return {n: np.ascontiguousarray(a[:, k]) for k, n in zip(cols, names)}


def _arrow(path: Path, lay: TextLayout, use: dict[str, str], decimal: str, threads: bool,
           extra: list) -> Any:
    """pyarrow's parse of the rows of the common length from the first data line; others go to ``extra``."""
    import pyarrow as pa
    import pyarrow.csv as pacsv

    k = lay.n_common
    cn = [f"c{i}" for i in range(k)]
    text = {use[r] for r in _TEXT_KEYS if r in use}
    cols = {n: cn[lay.names.index(n)] for n in use.values() if lay.names.index(n) < k}
    types = {c: (pa.string() if n in text else pa.float64()) for n, c in cols.items()}

    def handler(row: Any) -> str:
        extra.append((row.number, row.text))
        return "skip"

    src = pa.memory_map(str(path))
    src.seek(lay.data_offset)
    return pacsv.read_csv(
        src, read_options=pacsv.ReadOptions(column_names=cn, block_size=1 << 20, use_threads=threads),
        parse_options=pacsv.ParseOptions(delimiter=lay.delimiter, invalid_row_handler=handler),
        convert_options=pacsv.ConvertOptions(include_columns=list(cols.values()) or cn[:1], column_types=types,
                                             null_values=[], strings_can_be_null=False,
                                             decimal_point=decimal)), cols


def _fast(path: Path, lay: TextLayout, use: dict[str, str], decimal: str) -> dict[str, np.ndarray] | None:
    """The used columns by pyarrow (or numpy for whitespace); None when anything is irregular."""
    if lay.delimiter == " ":
        return _whitespace(path, lay, use, decimal)
    try:
        import pyarrow as pa
        import pyarrow.csv  # noqa: F401
    except ImportError:
        return None
    extra: list = []
    try:
        table, cols = _arrow(path, lay, use, decimal, lay.n_common == lay.n_fields, extra)
        if extra and any(num is None for num, _ in extra):  # row numbers are known on one thread only
            extra.clear()
            table, cols = _arrow(path, lay, use, decimal, False, extra)
    except (pa.ArrowException, ValueError, OSError):
        return None
    text = {use[r] for r in _TEXT_KEYS if r in use}
    n = table.num_rows + len(extra)
    if n == 0:
        return None
    pos = np.array([num - 1 for num, _ in extra], dtype=np.int64)
    if pos.size and (pos.min() < 0 or pos.max() >= n or np.unique(pos).size != pos.size):
        return None
    keep = np.ones(n, dtype=bool)
    keep[pos] = False
    out: dict[str, np.ndarray] = {}
    for name in use.values():
        arr = np.empty(n, dtype=object) if name in text else np.empty(n)
        if name in cols:
            col = table.column(cols[name])
            if col.null_count:
                return None
            arr[keep] = col.to_numpy(zero_copy_only=False)
        elif name in text:  # a column past the common row length (an Events column): empty but on event rows
            arr[keep] = ""
        elif table.num_rows:
            return None  # a number column missing from the common rows: the scan names the line
        out[name] = arr
    idx = {name: lay.names.index(name) for name in use.values()}
    for p, (_, line) in zip(pos, extra):
        try:
            cells = _parse_row(split_fields(line, lay.delimiter), lay, idx, text, decimal, str(path), -1, line)
        except ValueError:
            return None  # a bad line: the scan gives its line number and applies the policy
        for name, v in cells.items():
            out[name][p] = v
    if any(not np.isfinite(a).all() for name, a in out.items() if name not in text):
        return None
    return out


def read_text_table(path: Path, spec: ReaderSpec) -> RawTable:
    """The columns a spec uses of one text file, as a :class:`RawTable` (names as in the file, or positions);
    ``bad_lines`` counts the lines left out under ``spec.bad_lines``."""
    lay = text_layout(path, spec)
    plan = plan_columns(lay.names, spec, str(path), lay.positional, dt_meta=lay.dt)
    use = plan.use()
    cols = _fast(path, lay, use, spec.decimal)
    stats: dict = {"bad": 0, "first": None}
    if cols is None:
        cols = scan_strict(path, lay, use, spec.decimal, spec.bad_lines, stats)
    return RawTable(str(path), {n: cols[n] for n in lay.names if n in cols}, None, lay.positional,
                    {r: c for r, c in plan.roles.items()}, plan=plan, bad_lines=stats["bad"],
                    first_bad=stats["first"], dt_meta=lay.dt)
