"""How a rig writes its records: the :class:`ReaderSpec` (columns, units, sampling rate, signs, text layout, test ids,
computed channels, segments, offsets, covariates), built from command-line options or a TOML *reader profile* (the
same keys), options overriding the profile, so that a lab writes the mapping of its rig once::

    # mts.toml: an MTS export with a 7-line block above the column names, its own names, inches and kips
    format = "text"          # text | json | mat | hdf5 | tdms | parquet (default: by the file suffix)
    skip_rows = 7            # physical lines above the column-name line (or above the first data row)
    delimiter = ","          # "," ";" "|" "tab" "whitespace" (default: sniffed)
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
    [scale]                  # factors applied last (after the unit conversion and the zero offset)
    x = -1

and, for DAQ files as written (every key is an attribute of :class:`ReaderSpec`)::

    header_marker = '^Sample Number'   # the column-name line is the first line matching this
    bad_lines = "warn"                 # error | warn | skip a bad data line (counted and reported)
    split_events = 'DAQ Pause'         # a row whose Events cell matches ends its segment (one test each)
    segment_ids = ["0", "0.25", "0.5"] # labels of the segments in order
    segment_id = "{stem}_i{label}"     # the test id of a segment ({stem} {id} {segment} {label})
    keep = ["p"]                       # extra per-sample channels kept on the records
    [derive]                           # computed columns, on the file's numbers (numexpr, whitelisted)
    F = "c7 - c6*51.875"
    [reduce]                           # covariates from a column, per test/segment
    p_mean = "mean(c6)"
    [covariates]                       # covariates from the test id (group 1 or group 'value')
    p_bar = '_([0-9.]+)bar$'
    [zero]                             # offsets removed per test/segment: first, first:N, mean, median
    x = "first:20"
    [[files]]                          # keys for the files whose name matches the glob
    pattern = "*_1ms*.txt"
    columns = {x = "CHANNEL0", F = "CHANNEL1"}

Roles: ``test`` (id string), ``t`` time, ``x`` elongation, ``F`` tension, ``events`` (the text column
``split_events`` searches; default a column named Events or Event).  Inside chainid the units are always s, mm, N
(:mod:`chainid.records.units` converts).

**Order of the transformations** (per column, per test or segment): the numbers as written in the file ->
computed columns (``derive``) -> split into tests/segments -> ``units`` (to s, mm, N) -> ``zero`` (subtract this
test's/segment's offset) -> ``scale`` (a gain).  So x = 10·(V − V_rest), V_rest the mean of the first 20 samples,
is ``--zero x=first:20 --scale x=10``.

Precedence: an option on the command line > a matching ``[[files]]`` rule > the profile's top level (tables role
by role: ``--units x=m`` keeps the profile's t and F units).
"""
from __future__ import annotations

import re
from dataclasses import fields, replace
from pathlib import Path
from typing import Any, Sequence

from chainid.records.readerspec import (BAD_LINES, COLUMN_ROLES, FORMATS, REDUCERS, ROLES, ZERO_FORMS, ReaderSpec,
                                        apply_keys, parse_reduce, parse_zero)

__all__ = ["ReaderSpec", "ROLES", "COLUMN_ROLES", "FORMATS", "BAD_LINES", "REDUCERS", "ZERO_FORMS", "parse_zero",
           "parse_reduce", "parse_assignments", "parse_list", "load_profile", "spec_from_options"]


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
        key, val = _pair(item, text, what)
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


def _pair(item: str, text: str, what: str) -> tuple[str, str]:
    key, eq, val = item.partition("=")
    key, val = key.strip(), val.strip()
    if not eq or not key or not val:
        raise ValueError(f"{what} {text!r}: item {item!r} is not ROLE=VALUE (e.g. t=Time,x=Disp,F=Load)")
    return key, val


def _pairs(items: Sequence[str] | None, what: str) -> dict[str, str]:
    """Repeated ``NAME=VALUE`` options whose values may hold commas (regular expressions, expressions)."""
    out: dict[str, str] = {}
    for item in items or ():
        key, val = _pair(item, item, what)
        if key in out:
            raise ValueError(f"{what}: {key!r} is given twice")
        out[key] = val
    return out


def parse_list(text: str | None) -> tuple[str, ...] | None:
    """``"a, b,c"`` -> ``("a", "b", "c")``; None stays None."""
    if text is None:
        return None
    return tuple(s.strip() for s in text.split(",") if s.strip())


def load_profile(path: str | Path) -> ReaderSpec:
    """Read a TOML reader profile (keys of :class:`ReaderSpec`; see the module docstring).

    Raises
    ------
    ValueError
        A missing or unreadable file, unknown keys, or invalid values (naming the key and the valid range); a
        ``[[files]]`` rule is checked against the top level too.
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
        spec = ReaderSpec(**doc)
        for rule in spec.files:
            try:
                apply_keys(replace(spec, files=()), {k: v for k, v in rule.items() if k != "pattern"})
            except (TypeError, ValueError) as exc:
                raise ValueError(f"[[files]] pattern = {rule['pattern']!r}: {exc}") from None
        return spec
    except (TypeError, ValueError) as exc:
        raise ValueError(f"--reader {str(p)!r}: {exc}") from None


def spec_from_options(profile: str | Path | None = None, *, columns: str | None = None, units: str | None = None,
                      fs: float | None = None, scale: str | None = None, delimiter: str | None = None,
                      decimal: str | None = None, skip_rows: int | None = None, id_pattern: str | None = None,
                      format: str | None = None, names: str | None = None, header_marker: str | None = None,
                      bad_lines: str | None = None, derive: Sequence[str] | None = None, keep: str | None = None,
                      reduce: str | None = None, covariates: Sequence[str] | None = None, zero: str | None = None,
                      split_events: str | None = None, split_gap: float | None = None,
                      segment_ids: str | None = None, segment_id: str | None = None) -> ReaderSpec:
    """The spec of a command line: the ``--reader`` profile (if any) with the given options overriding it.

    ``columns``, ``units``, ``scale``, ``zero``, ``reduce`` are ``KEY=VALUE`` lists as on the command line;
    ``derive`` (``"NAME = EXPRESSION"``) and ``covariates`` (``"NAME=REGEX"``) are lists of repeated options;
    ``names``, ``keep``, ``segment_ids`` comma lists.  An option replaces the profile's key role by role
    (``--units x=m`` keeps the profile's ``t`` and ``F`` units), in the top level and in every ``[[files]]`` rule.
    """
    from chainid.records.derive import parse_derive_text

    base = load_profile(profile) if profile else ReaderSpec()
    tables = {"columns": parse_assignments(columns, "--columns"), "units": parse_assignments(units, "--units"),
              "scale": parse_assignments(scale, "--scale", numeric=True), "zero": parse_assignments(zero, "--zero"),
              "reduce": parse_assignments(reduce, "--reduce"), "covariates": _pairs(covariates, "--covariate"),
              "derive": dict(parse_derive_text(d) for d in derive or ())}
    scalars = {"fs": fs, "delimiter": delimiter, "decimal": decimal, "skip_rows": skip_rows, "id_pattern": id_pattern,
               "format": format, "names": parse_list(names), "header_marker": header_marker, "bad_lines": bad_lines,
               "keep": parse_list(keep), "split_events": split_events, "split_gap": split_gap,
               "segment_ids": parse_list(segment_ids), "segment_id": segment_id}
    scalars = {k: v for k, v in scalars.items() if v is not None}
    rules = []
    for rule in base.files:  # the command line overrides the rules too
        r = {k: v for k, v in rule.items() if k not in scalars}
        for k, given in tables.items():
            if k in r and given:
                r[k] = {kk: vv for kk, vv in dict(r[k]).items() if kk not in given}
        rules.append(r)
    top = {k: {**getattr(base, k), **v} for k, v in tables.items()}
    return replace(base, **top, **scalars, files=tuple(rules))

