"""The :class:`ReaderSpec` dataclass and its checks: how a rig writes its records (columns, units, sampling rate,
signs, text layout, test ids, computed channels, segments, offsets, covariates).

:mod:`chainid.records.spec` is the public face (profiles, command-line options) and re-exports these names; the
keys and the order of the transformations are described there.
"""
from __future__ import annotations

import math
import re
import string
from dataclasses import dataclass, field, replace
from typing import Any, Mapping

from chainid.records.derive import parse_derived
from chainid.records.patterns import check_pattern

__all__ = ["ReaderSpec", "ROLES", "COLUMN_ROLES", "FORMATS", "BAD_LINES", "ZERO_FORMS", "REDUCERS", "FILE_KEYS",
           "TABLE_KEYS", "apply_keys", "parse_reduce", "parse_zero"]

#: The roles a column can play: test id, time [s], elongation [mm], tension [N].
ROLES = ("test", "t", "x", "F")
#: Roles ``columns`` may map: the four above and ``events`` (the text column searched by ``split_events``).
COLUMN_ROLES = ROLES + ("events",)
#: Accepted values of ``format`` (None = by the file suffix).
FORMATS = ("text", "json", "mat", "hdf5", "tdms", "parquet")
#: What to do with a bad data line (more fields than the column names, or an unreadable value in a used column).
BAD_LINES = ("error", "warn", "skip")
#: Statistics a covariate can reduce a column to (per test/segment).
REDUCERS = ("mean", "median", "first", "last", "min", "max")
_DELIMITERS = {",": ",", ";": ";", "tab": "\t", "\t": "\t", "\\t": "\t", "|": "|", "whitespace": " ", "space": " ",
               " ": " "}
_TEMPLATE_FIELDS = ("stem", "id", "segment", "label")
_ZERO = re.compile(r"(first|mean|median)(?::(\d+))?\Z")
_REDUCE = re.compile(r"\s*(\w+)\s*\(\s*([A-Za-z_][A-Za-z0-9_]*)\s*\)\s*\Z")
ZERO_FORMS = "first (the first sample), first:N (the mean of the first N samples), mean, median"


def parse_zero(text: str, what: str = "zero") -> tuple[str, int]:
    """``"first:20"`` -> ``("first", 20)``; ``"first"`` -> ``("first", 1)``; ``"mean"`` -> ``("mean", 0)``."""
    m = _ZERO.match(str(text).strip())
    if not m or (m.group(1) != "first" and m.group(2)) or (m.group(2) is not None and int(m.group(2)) < 1):
        raise ValueError(f"{what} = {text!r} is invalid; valid: {ZERO_FORMS}")
    how = m.group(1)
    return how, (int(m.group(2) or 1) if how == "first" else 0)


def parse_reduce(text: str, what: str = "reduce") -> tuple[str, str]:
    """``"mean(p)"`` -> ``("mean", "p")`` (a covariate from a column, per test/segment)."""
    m = _REDUCE.match(str(text))
    if not m or m.group(1) not in REDUCERS:
        raise ValueError(f"{what} = {text!r} is invalid; valid: STAT(COLUMN) with STAT one of {list(REDUCERS)}, "
                         "e.g. mean(p) or median(c6)")
    return m.group(1), m.group(2)


def _float_or_nan(v: Any) -> float:
    try:
        return float(v)
    except (TypeError, ValueError):
        return float("nan")


@dataclass(frozen=True)
class ReaderSpec:
    """How to read a rig's record files into chainid's records (t s, x mm, F N).

    Attributes
    ----------
    columns : dict
        Role (``test``, ``t``, ``x``, ``F``, ``events``) -> the file's column/channel/dataset name, a computed
        column's name, or an int 1-based column position.  Unmapped roles are looked up by their own name.
    units : dict
        Role (``t``, ``x``, ``F``) -> unit string understood by pint (``ms``, ``in``, ``kip``, ...), default s, mm,
        N; a kept or reduced channel -> its unit, converted to chainid's unit of that dimension (mm, N, s, MPa,
        kg, A, mm/s, Hz).
    fs : float or None
        Sampling rate [Hz] for files without a time column (t = i / fs from 0 per test and per segment).  Without
        it, a text file's ``Sampling Interval`` [s] or ``Sampling Rate`` [Hz] header line is used.
    scale : dict
        Role or channel -> factor applied last (after units and zero; ``x = -1`` flips a sign).
    delimiter : str or None
        Text field separator: one character, or ``" "`` for runs of whitespace; None = sniffed.
    decimal : str
        Decimal mark of text files, ``"."`` or ``","``.
    skip_rows : int
        Physical lines (blank ones included) skipped at the top of a text file: the lines *above* the
        column-name line, or above the first data row of a file without names.  A ``Header Size: N`` line that
        counts the name line (N = skip_rows + 1) is checked against it.
    id_pattern : str or None
        Regular expression searched in the file name; the test id is its group ``id``, else its first group,
        else the whole match.  None: the file stem.
    format : str or None
        One of :data:`FORMATS`; None = by the file suffix.
    header : bool or None
        True: the first line after ``skip_rows`` holds the column names; False: it is data; None: names when a
        field is not a number (a line that looks like a data row is refused).  A list is refused (see ``names``).
    names : tuple of str or None
        The column names to use (for a file without a name line, or to replace the file's names).
    header_marker : str or None
        Regular expression: the column-name line is the first line (after ``skip_rows``, within the first 1000)
        that it matches.
    bad_lines : str
        ``error`` (default), ``warn`` or ``skip`` a data line with more fields than the names or an unreadable
        value in a used column; skipped lines are counted and reported.  Missing trailing fields are empty.
    derive : dict
        Name -> expression of a computed column (see :mod:`chainid.records.derive`), on the file's numbers.
    keep : tuple of str
        Columns kept on each record as extra per-sample channels (:attr:`Record.channels`).
    reduce : dict
        Covariate name -> ``STAT(COLUMN)`` (STAT in :data:`REDUCERS`), per test/segment.
    covariates : dict
        Covariate name -> regular expression searched in the test id (group ``value``, else group 1), a number.
    zero : dict
        Role or channel -> offset removed per test/segment: ``first``, ``first:N``, ``mean``, ``median``.
    split_events : str or None
        Regular expression: a row whose events cell matches ends its segment (one test per segment).
    split_gap : float or None
        Split where the time step exceeds this many seconds.
    segment_ids : tuple of str or None
        Labels of the segments, in order (their number must match).
    segment_id : str or None
        Template of a segment's test id from ``{stem}``, ``{id}`` (the file's id), ``{segment}`` (1-based) and
        ``{label}``; default ``{id}_{segment}`` (``{id}_{label}`` with labels).
    files : tuple of dict
        ``[[files]]`` rules: ``pattern`` (a glob on the file name) and keys overriding the top level.
    """

    columns: Mapping[str, str | int] = field(default_factory=dict)
    units: Mapping[str, str] = field(default_factory=dict)
    fs: float | None = None
    scale: Mapping[str, float] = field(default_factory=dict)
    delimiter: str | None = None
    decimal: str = "."
    skip_rows: int = 0
    id_pattern: str | None = None
    format: str | None = None
    header: bool | None = None
    names: tuple[str, ...] | None = None
    header_marker: str | None = None
    bad_lines: str = "error"
    derive: Mapping[str, str] = field(default_factory=dict)
    keep: tuple[str, ...] = ()
    reduce: Mapping[str, str] = field(default_factory=dict)
    covariates: Mapping[str, str] = field(default_factory=dict)
    zero: Mapping[str, str] = field(default_factory=dict)
    split_events: str | None = None
    split_gap: float | None = None
    segment_ids: tuple[str, ...] | None = None
    segment_id: str | None = None
    files: tuple[Mapping[str, Any], ...] = ()

    def __post_init__(self) -> None:
        for name in ("columns", "units", "scale", "derive", "reduce", "covariates", "zero"):
            v = getattr(self, name)
            if v is not None and not isinstance(v, Mapping):
                raise ValueError(f"reader {name} = {v!r} is invalid; give a table NAME = VALUE")
            object.__setattr__(self, name, dict(v or {}))
        self._check_lists()
        self._check_columns()
        self._check_channels()
        self._check_layout()
        self._check_segments()

    # -- checks ----------------------------------------------------------------------------------------------
    def _check_lists(self) -> None:
        if isinstance(self.header, (list, tuple)):
            raise ValueError(f"reader header = {list(self.header)!r} is a list; header is true or false (whether "
                             "the line after skip_rows holds the column names); give the names as names = [...]")
        if self.header is not None and not isinstance(self.header, bool):
            raise ValueError(f"reader header = {self.header!r} is invalid; valid: true or false")
        for name in ("names", "keep", "segment_ids"):
            v = getattr(self, name)
            if v is None:
                continue
            if isinstance(v, str) or not isinstance(v, (list, tuple)):
                raise ValueError(f"reader {name} = {v!r} is invalid; give a list, e.g. {name} = [\"a\", \"b\"]")
            items = tuple(str(s).strip() if not isinstance(s, float) else repr(s) for s in v)
            if any(not s for s in items) or len(set(items)) != len(items) or (not items and name != "keep"):
                raise ValueError(f"reader {name} = {list(v)!r} is invalid; give distinct non-empty entries")
            object.__setattr__(self, name, items)

    def _check_columns(self) -> None:
        bad = [k for k in self.columns if k not in COLUMN_ROLES]
        if bad:
            raise ValueError(f"reader columns: unknown role(s) {bad}; valid roles are {list(COLUMN_ROLES)} (another "
                             f"column: --keep it as a channel, or --derive '{bad[0]} = c6' to name it)")
        for k, v in self.columns.items():
            if isinstance(v, bool) or not isinstance(v, (str, int)) or (isinstance(v, int) and v < 1) \
                    or (isinstance(v, str) and not v.strip()):
                raise ValueError(f"reader columns: {k} = {v!r} is invalid; give a column name or a 1-based "
                                 "position >= 1")
        for k, v in self.derive.items():
            parse_derived(k, v, "reader derive")
        for k, v in self.reduce.items():
            if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", str(k)):
                raise ValueError(f"reader reduce: covariate name {k!r} must be an identifier (e.g. p_bar)")
            parse_reduce(v, f"reader reduce {k}")
        for k, v in self.covariates.items():
            if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", str(k)):
                raise ValueError(f"reader covariates: covariate name {k!r} must be an identifier (e.g. p_bar)")
            if k in self.reduce:
                raise ValueError(f"reader covariates: {k!r} is also a reduce covariate; give one source")
            rx = check_pattern(str(v), f"reader covariates {k}")
            if not rx.groups:
                raise ValueError(f"reader covariates {k} = {v!r} has no group; the value is group 'value' or "
                                 "group 1, e.g. '_([0-9.]+)bar$'")

    def channel_names(self) -> set[str]:
        """Names that take units, zero and scale besides the roles: kept channels and the columns reduced."""
        return set(self.keep) | {parse_reduce(v)[1] for v in self.reduce.values()}

    def _check_channels(self) -> None:
        chans = self.channel_names()
        for name in ("units", "scale", "zero"):
            d = getattr(self, name)
            bad = [k for k in d if k not in ROLES[1:] and k not in chans]
            if bad:
                raise ValueError(f"reader {name}: unknown role(s) {bad}; valid roles are {list(ROLES[1:])}"
                                 + (f" and the kept or reduced channels {sorted(chans)}" if chans else ""))
        for k, v in self.scale.items():
            f = _float_or_nan(v)
            if not math.isfinite(f) or f == 0.0:
                raise ValueError(f"reader scale: {k} = {v!r} is invalid; valid: a finite non-zero factor, e.g. -1")
            self.scale[k] = f  # type: ignore[index]
        for k, v in self.units.items():
            if not isinstance(v, str) or not v.strip():
                raise ValueError(f"reader units: {k} = {v!r} is invalid; give a unit such as s, ms, mm, in, N, kip")
        for k, v in self.zero.items():
            parse_zero(v, f"reader zero {k}")

    def _check_layout(self) -> None:
        if self.fs is not None:
            fs = _float_or_nan(self.fs)
            if not (math.isfinite(fs) and fs > 0):
                raise ValueError(f"reader fs = {self.fs!r} Hz is invalid; valid range fs > 0 Hz")
            object.__setattr__(self, "fs", fs)
        if self.delimiter is not None:
            if self.delimiter not in _DELIMITERS:
                raise ValueError(f"reader delimiter = {self.delimiter!r} is invalid; valid: ',', ';', '|', 'tab', "
                                 "'whitespace'")
            object.__setattr__(self, "delimiter", _DELIMITERS[self.delimiter])
        if self.decimal not in (".", ","):
            raise ValueError(f"reader decimal = {self.decimal!r} is invalid; valid: '.' or ','")
        if self.decimal == "," and self.delimiter == ",":
            raise ValueError("reader decimal = ',' needs another delimiter than ',' (e.g. ';' or 'tab')")
        if isinstance(self.skip_rows, bool) or not isinstance(self.skip_rows, int) or self.skip_rows < 0:
            raise ValueError(f"reader skip_rows = {self.skip_rows!r} is invalid; valid: an integer >= 0")
        for name in ("id_pattern", "header_marker", "split_events"):
            v = getattr(self, name)
            if v is not None:
                if not isinstance(v, str) or not v:
                    raise ValueError(f"reader {name} = {v!r} is invalid; give a regular expression")
                check_pattern(v, f"reader {name}")
        if self.format is not None and self.format not in FORMATS:
            raise ValueError(f"reader format = {self.format!r} is invalid; valid: {list(FORMATS)}")
        if self.bad_lines not in BAD_LINES:
            raise ValueError(f"reader bad_lines = {self.bad_lines!r} is invalid; valid: {list(BAD_LINES)}")

    def _check_segments(self) -> None:
        if self.split_gap is not None:
            g = _float_or_nan(self.split_gap)
            if isinstance(self.split_gap, bool) or not (math.isfinite(g) and g > 0):
                raise ValueError(f"reader split_gap = {self.split_gap!r} s is invalid; valid range > 0 s")
            object.__setattr__(self, "split_gap", g)
        if self.segment_id is not None:
            try:
                used = [f for _, f, _, _ in string.Formatter().parse(str(self.segment_id)) if f is not None]
            except ValueError as exc:
                raise ValueError(f"reader segment_id = {self.segment_id!r} is not a template ({exc})") from None
            bad = [f for f in used if f not in _TEMPLATE_FIELDS]
            if bad or not used:
                raise ValueError(f"reader segment_id = {self.segment_id!r}: valid fields are "
                                 f"{{{'}, {'.join(_TEMPLATE_FIELDS)}}} (e.g. '{{stem}}_i{{label}}')")
            if "label" in used and self.segment_ids is None:
                raise ValueError(f"reader segment_id = {self.segment_id!r} uses {{label}}: give segment_ids")
        splits = self.split_events is not None or self.split_gap is not None
        if (self.segment_ids is not None or self.segment_id is not None) and not splits:
            raise ValueError("reader segment_ids / segment_id name segments: give split_events or split_gap too")
        if self.files and (not isinstance(self.files, (list, tuple))
                           or not all(isinstance(r, Mapping) for r in self.files)):
            raise ValueError("reader files: give [[files]] tables, each with a pattern and reader keys")
        rules = tuple(dict(r) for r in self.files)
        for r in rules:
            if not isinstance(r.get("pattern"), str) or not r["pattern"]:
                raise ValueError(f"reader [[files]] table {r!r} has no pattern (a glob on the file name)")
            if "files" in r:
                raise ValueError(f"reader [[files]] pattern = {r['pattern']!r}: a rule cannot hold files")
        object.__setattr__(self, "files", rules)

    # -- use -------------------------------------------------------------------------------------------------
    @property
    def splits(self) -> bool:
        """True when files are cut into segments (``split_events`` or ``split_gap``)."""
        return self.split_events is not None or self.split_gap is not None

    @property
    def is_default(self) -> bool:
        """True when nothing differs from the canonical long CSV ``test,t,x,F`` in s, mm, N."""
        return self == ReaderSpec()

    def merged(self, **over: Any) -> "ReaderSpec":
        """A copy with the given fields replaced (None and empty values keep this spec's)."""
        keep = {k: v for k, v in over.items() if v is not None and v != {} and v != ()}
        return replace(self, **keep)

    def for_file(self, name: str) -> "ReaderSpec":
        """The spec of one file: the ``[[files]]`` rules whose ``pattern`` (a glob, case-sensitive) matches its
        name override the top level, in order; tables (columns, units, ...) key by key.

        Raises
        ------
        ValueError
            A rule's keys give an invalid spec for this file (naming the rule's pattern).
        """
        if not self.files:
            return self
        import fnmatch

        out = self
        for rule in self.files:
            if fnmatch.fnmatchcase(name, str(rule["pattern"])):
                over = {k: v for k, v in rule.items() if k != "pattern"}
                try:
                    out = apply_keys(out, over)
                except (TypeError, ValueError) as exc:
                    raise ValueError(f"reader [[files]] pattern = {rule['pattern']!r}: {exc}") from None
        return replace(out, files=())


#: Keys that are tables: merged key by key when a rule or an option overrides them.
TABLE_KEYS = ("columns", "units", "scale", "derive", "reduce", "covariates", "zero")
#: Keys a ``[[files]]`` rule may set (all but ``files``), besides its ``pattern``.
FILE_KEYS = tuple(f for f in ReaderSpec.__dataclass_fields__ if f != "files")


def apply_keys(spec: ReaderSpec, over: Mapping[str, Any]) -> ReaderSpec:
    """``spec`` with the keys of ``over`` applied: tables merged key by key, other keys replaced."""
    bad = sorted(set(over) - set(FILE_KEYS))
    if bad:
        raise ValueError(f"unknown key(s) {bad}; valid keys are {sorted(FILE_KEYS)}")
    kw = {}
    for k, v in over.items():
        kw[k] = {**getattr(spec, k), **dict(v)} if k in TABLE_KEYS and isinstance(v, Mapping) else v
    return replace(spec, **kw)
