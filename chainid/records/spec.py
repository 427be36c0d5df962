"""How a rig writes its records: the :class:`ReaderSpec` (columns, units, sampling rate, signs, text layout, test ids).

A spec is built from command-line options or a TOML *reader profile* (the same keys), options overriding the
profile, so that a lab writes the mapping of its rig once::

    # mts.toml: an MTS export with a 7-line header block, its own names, inches and kips
    format = "text"          # text | json | mat | hdf5 | tdms | parquet (default: by the file suffix)
    skip_rows = 7            # lines before the header (or the first data row)
    delimiter = ","          # "," ";" "tab" "whitespace" (default: sniffed)
    decimal = "."            # "." or ","
    id_pattern = 'run(\\d+)'  # test id from the file name (first group, or the group named id)
    fs = 10240.0             # Hz, for files without a time column
    [columns]                # chainid role = the rig's column name (or 1-based position)
    t = "Time"
    x = "Axial Displacement"
    F = "Axial Force"
    [units]                  # anything pint knows with the right dimension
    t = "s"
    x = "in"
    F = "kip"
    [scale]                  # sign conventions: factor applied after the unit conversion
    x = -1

Roles: ``test`` (id string), ``t`` time, ``x`` elongation, ``F`` tension.  Inside chainid the units are always
s, mm, N (:mod:`chainid.records.units` converts).
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass, field, fields, replace
from pathlib import Path
from typing import Any, Mapping

__all__ = ["ReaderSpec", "ROLES", "FORMATS", "parse_assignments", "load_profile", "spec_from_options"]

#: The roles a column can play: test id, time [s], elongation [mm], tension [N].
ROLES = ("test", "t", "x", "F")
#: Accepted values of ``format`` (None = by the file suffix).
FORMATS = ("text", "json", "mat", "hdf5", "tdms", "parquet")
_DELIMITERS = {",": ",", ";": ";", "tab": "\t", "\t": "\t", "\\t": "\t", "|": "|", "whitespace": " ", "space": " ",
               " ": " "}


@dataclass(frozen=True)
class ReaderSpec:
    """How to read a rig's record files into chainid's records (t s, x mm, F N).

    Attributes
    ----------
    columns : dict
        Role (``test``, ``t``, ``x``, ``F``) -> the file's column/channel/dataset name, or an int 1-based
        column position (headerless text).  Unmapped roles are looked up by their own name.
    units : dict
        Role (``t``, ``x``, ``F``) -> unit string understood by pint (``ms``, ``in``, ``kip``, ...).  Default
        s, mm, N.
    fs : float or None
        Sampling rate [Hz] for files without a time column (t = i / fs from 0 per test).
    scale : dict
        Role (``t``, ``x``, ``F``) -> factor applied after the unit conversion (``x = -1`` flips a sign).
    delimiter : str or None
        Text field separator: one character, or ``" "`` for runs of whitespace; None = sniffed.
    decimal : str
        Decimal mark of text files, ``"."`` or ``","``.
    skip_rows : int
        Lines to skip at the top of a text file (a header block) before the header or the first data row.
    id_pattern : str or None
        Regular expression searched in the file name (stem); the test id is its group ``id``, else its first
        group, else the whole match.  None: the file stem.
    format : str or None
        One of :data:`FORMATS`; None = by the file suffix.
    header : bool or None
        Whether the first line after ``skip_rows`` is a header; None = a header when a field is not a number.
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

    def __post_init__(self) -> None:
        for name in ("columns", "units", "scale"):
            d = dict(getattr(self, name) or {})
            allowed = ROLES if name == "columns" else ROLES[1:]
            bad = [k for k in d if k not in allowed]
            if bad:
                raise ValueError(f"reader {name}: unknown role(s) {bad}; valid roles are {list(allowed)}")
            object.__setattr__(self, name, d)
        for k, v in self.columns.items():
            if isinstance(v, bool) or not isinstance(v, (str, int)) or (isinstance(v, int) and v < 1) \
                    or (isinstance(v, str) and not v.strip()):
                raise ValueError(f"reader columns: {k} = {v!r} is invalid; give a column name or a 1-based "
                                 "position >= 1")
        for k, v in self.scale.items():
            try:
                f = float(v)
            except (TypeError, ValueError):
                f = float("nan")
            if not math.isfinite(f) or f == 0.0:
                raise ValueError(f"reader scale: {k} = {v!r} is invalid; valid: a finite non-zero factor, e.g. -1")
            self.scale[k] = f  # type: ignore[index]
        for k, v in self.units.items():
            if not isinstance(v, str) or not v.strip():
                raise ValueError(f"reader units: {k} = {v!r} is invalid; give a unit such as s, ms, mm, in, N, kip")
        if self.fs is not None:
            try:
                fs = float(self.fs)
            except (TypeError, ValueError):
                fs = float("nan")
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
        if self.id_pattern is not None:
            try:
                re.compile(self.id_pattern)
            except re.error as exc:
                raise ValueError(f"reader id_pattern = {self.id_pattern!r} is not a regular expression ({exc})") \
                    from None
        if self.format is not None and self.format not in FORMATS:
            raise ValueError(f"reader format = {self.format!r} is invalid; valid: {list(FORMATS)}")

    @property
    def is_default(self) -> bool:
        """True when nothing differs from the canonical long CSV ``test,t,x,F`` in s, mm, N."""
        return self == ReaderSpec()

    def merged(self, **over: Any) -> "ReaderSpec":
        """A copy with the given fields replaced (None and empty values keep this spec's)."""
        keep = {k: v for k, v in over.items() if v is not None and v != {}}
        return replace(self, **keep)


def parse_assignments(text: str | None, what: str, numeric: bool = False) -> dict[str, Any]:
    """Parse ``"t=Time,x=Disp"`` into ``{"t": "Time", "x": "Disp"}``.

    Integers become 1-based positions for ``--columns`` (``F=1``) and floats for ``--scale`` (``numeric``).

    Raises
    ------
    ValueError
        Naming the option and the bad item.
    """
    out: dict[str, Any] = {}
    if text is None:
        return out
    for item in (s for s in text.split(",") if s.strip()):
        key, eq, val = item.partition("=")
        key, val = key.strip(), val.strip()
        if not eq or not key or not val:
            raise ValueError(f"{what} {text!r}: item {item!r} is not ROLE=VALUE (e.g. t=Time,x=Disp,F=Load)")
        if key in out:
            raise ValueError(f"{what} {text!r}: role {key!r} is given twice")
        if numeric:
            try:
                out[key] = float(val)
            except ValueError:
                raise ValueError(f"{what} {text!r}: {key} = {val!r} is not a number") from None
        elif what == "--columns" and re.fullmatch(r"\d+", val):
            out[key] = int(val)
        else:
            out[key] = val
    return out


def load_profile(path: str | Path) -> ReaderSpec:
    """Read a TOML reader profile (keys of :class:`ReaderSpec`; see the module docstring).

    Raises
    ------
    ValueError
        A missing or unreadable file, unknown keys, or invalid values (naming the key and the valid range).
    """
    try:
        import tomllib
    except ModuleNotFoundError:  # pragma: no cover - Python 3.10
        import tomli as tomllib  # type: ignore[no-redef]

    p = Path(path)
    if not p.is_file():
        raise ValueError(f"--reader {str(p)!r}: no such profile file")
    try:
        doc = tomllib.loads(p.read_text(encoding="utf-8"))
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise ValueError(f"--reader {str(p)!r}: not a TOML file ({exc})") from None
    names = {f.name for f in fields(ReaderSpec)}
    unknown = sorted(set(doc) - names)
    if unknown:
        raise ValueError(f"--reader {str(p)!r}: unknown key(s) {unknown}; valid keys are {sorted(names)}")
    try:
        return ReaderSpec(**doc)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"--reader {str(p)!r}: {exc}") from None


def spec_from_options(profile: str | Path | None = None, *, columns: str | None = None, units: str | None = None,
                      fs: float | None = None, scale: str | None = None, delimiter: str | None = None,
                      decimal: str | None = None, skip_rows: int | None = None, id_pattern: str | None = None,
                      format: str | None = None) -> ReaderSpec:
    """The spec of a command line: the ``--reader`` profile (if any) with the given options overriding it.

    ``columns``, ``units`` and ``scale`` are ``ROLE=VALUE`` lists as on the command line; an option given on the
    command line replaces the profile's role by role (``--units x=m`` keeps the profile's ``t`` and ``F`` units).
    """
    base = load_profile(profile) if profile else ReaderSpec()
    cols = {**base.columns, **parse_assignments(columns, "--columns")}
    uns = {**base.units, **parse_assignments(units, "--units")}
    scl = {**base.scale, **parse_assignments(scale, "--scale", numeric=True)}
    return replace(base, columns=cols, units=uns, scale=scl).merged(
        fs=fs, delimiter=delimiter, decimal=decimal, skip_rows=skip_rows, id_pattern=id_pattern, format=format)
