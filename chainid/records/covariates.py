"""Covariates of a test (operating conditions: set pressure, coil current, pretension, temperature) from the
sources of the records contract, besides the per-segment reductions of :mod:`.table`:

* a pattern on the test id, ``--covariate 'NAME=REGEX'`` (group ``value``, else group 1, read as a float);
* a side file ``test,name,value`` (``--covariates FILE``), read by :func:`read_covariates` and written by
  :func:`write_covariates` (``chainid convert`` writes one beside its output).

A covariate given twice for one test by different sources is an error naming both; a test id of the side file
that no record has is a warning (the side file may cover more tests than were read).
"""
from __future__ import annotations

import csv
import math
from pathlib import Path
from typing import Iterable, Mapping, Sequence

from chainid.records.patterns import bounded_search, check_pattern
from chainid.records.record import Record

__all__ = ["covariates_from_ids", "read_covariates", "apply_covariates", "write_covariates", "covariates_path"]


def covariates_from_ids(records: Iterable[Record], patterns: Mapping[str, str]) -> None:
    """Set each record's covariates from its test id (in place).

    Raises
    ------
    ValueError
        A pattern that does not match a test id, a match that is not a number, or a covariate the record has
        already (from a column), naming the covariate, the pattern and the id.
    """
    for name, pat in patterns.items():
        rx = check_pattern(pat, f"--covariate {name}")
        for r in records:
            m = bounded_search(rx, r.test, f"--covariate {name}")
            if m is None:
                raise ValueError(f"--covariate {name}='{pat}' does not match the test id {r.test!r}")
            text = m.group("value") if "value" in rx.groupindex else m.group(1)
            try:
                v = float(text)
            except (TypeError, ValueError):
                v = float("nan")
            if not math.isfinite(v):
                raise ValueError(f"--covariate {name}='{pat}': test {r.test!r}: {text!r} is not a number")
            if name in r.covariates:
                raise ValueError(f"test {r.test!r}: covariate {name!r} comes from both the data ({r.covariates[name]:g})"
                                 f" and --covariate {pat!r} ({v:g}); give one source")
            r.covariates[name] = v


def read_covariates(path: str | Path) -> dict[str, dict[str, float]]:
    """A side file ``test,name,value`` -> ``{test: {name: value}}``.

    Raises
    ------
    ValueError
        A missing file or column, a value that is not a finite number, or a (test, name) pair given twice
        (naming the file and the line numbers).
    """
    p = Path(path)
    if not p.is_file():
        raise ValueError(f"--covariates {str(p)!r}: no such file")
    out: dict[str, dict[str, float]] = {}
    first: dict[tuple[str, str], int] = {}
    try:
        with p.open(newline="", encoding="utf-8-sig") as fh:
            reader = csv.DictReader(fh)
            cols = [c.strip() for c in (reader.fieldnames or [])]
            missing = [c for c in ("test", "name", "value") if c not in cols]
            if missing:
                raise ValueError(f"{p}: missing column(s) {missing}; a covariates file has the header test,name,value")
            for line_no, row in enumerate(reader, start=2):
                row = {(k or "").strip(): (v or "").strip() for k, v in row.items() if k is not None}
                test, name, text = row.get("test", ""), row.get("name", ""), row.get("value", "")
                if not test or not name:
                    raise ValueError(f"{p}, line {line_no}: empty test or name")
                try:
                    v = float(text)
                except ValueError:
                    v = float("nan")
                if not math.isfinite(v) or "_" in text:
                    raise ValueError(f"{p}, line {line_no}: test {test!r}: covariate {name!r} value {text!r} is not "
                                     "a finite number")
                if (test, name) in first:
                    raise ValueError(f"{p}, line {line_no}: test {test!r}, covariate {name!r} appears twice (line "
                                     f"{first[(test, name)]} too)")
                first[(test, name)] = line_no
                out.setdefault(test, {})[name] = v
    except UnicodeDecodeError:
        raise ValueError(f"{p}: not a UTF-8 text file") from None
    except csv.Error as exc:
        raise ValueError(f"{p}: not a readable CSV file ({exc})") from None
    return out


def apply_covariates(records: Sequence[Record], table: Mapping[str, Mapping[str, float]], source: str) -> list[str]:
    """Add a side file's covariates to the records (in place); returns warnings for ids no record has.

    Raises
    ------
    ValueError
        A covariate a record already has from another source (naming both values).
    """
    by_id = {r.test: r for r in records}
    for test, covs in table.items():
        r = by_id.get(test)
        if r is None:
            continue
        for name, v in covs.items():
            if name in r.covariates and r.covariates[name] != v:
                raise ValueError(f"test {test!r}: covariate {name!r} is {r.covariates[name]:g} from the data and "
                                 f"{v:g} in {source!r}; give one source")
            r.covariates[name] = v
    unknown = sorted(set(table) - set(by_id))
    if not unknown:
        return []
    shown = ", ".join(repr(t) for t in unknown[:10]) + (", ..." if len(unknown) > 10 else "")
    return [f"file {source!r}: covariates of {len(unknown)} test id(s) that were not read: {shown}"]


def covariates_path(out: str | Path) -> Path:
    """The covariates side file beside a records file: ``OUT.covariates.csv`` (``run.csv`` ->
    ``run.covariates.csv``, ``run.parquet`` -> ``run.covariates.csv``)."""
    p = Path(out)
    return p.with_name(f"{p.stem}.covariates.csv")


def write_covariates(path: str | Path, records: Iterable[Record], overwrite: bool = False) -> Path:
    """Write ``test,name,value`` (one row per test and covariate, ``repr`` of the float: exact) atomically."""
    from chainid.infra.fileio import atomic_open

    p = Path(path)
    with atomic_open(p, "w", force=overwrite, what="covariates file", newline="") as fh:
        fh.write("test,name,value\n")
        for r in records:
            for name, v in r.covariates.items():
                fh.write(f"{r.test},{name},{v!r}\n")
    return p
