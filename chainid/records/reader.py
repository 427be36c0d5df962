"""One entry point for every command that reads records: :func:`read_any` (a file, a directory or a glob of
one-file-per-test, in any supported format, mapped by a :class:`~chainid.records.spec.ReaderSpec`, per file by its
``[[files]]`` rules).

The canonical long CSV ``test,t,x,F`` in s, mm, N, given as a single file with no reader options, takes the
canonical reader (:mod:`.textcanon`: same records and errors as always, parsed fast).  Hidden files (a name
starting with ``.``: editor locks such as ``.~lock.A.csv#``, ``.junk.csv``) are never taken from a directory or a
glob.  What reading noticed without stopping (bad lines left out, a time column at odds with the file's stated
interval) goes to a :class:`ReadLog`.
"""
from __future__ import annotations

import glob
import stat
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Iterable, Sequence

from chainid.records.covariates import covariates_from_ids
from chainid.records.formats import SUFFIXES, format_of, read_container
from chainid.records.patterns import bounded_search, check_pattern
from chainid.records.readerspec import ReaderSpec
from chainid.records.record import Record
from chainid.records.select import matches, select_ids
from chainid.records.table import id_source, records_from_table
from chainid.records.textcanon import read_canonical_csv
from chainid.records.textread import read_text_table

__all__ = ["expand_paths", "test_id", "read_any", "RECORD_SUFFIXES", "ReadLog"]

#: Suffixes taken from a directory (other files there are ignored).
RECORD_SUFFIXES = (".csv", ".tsv", ".txt", ".dat", ".asc", ".tab", *SUFFIXES)
_KIND = ((stat.S_ISFIFO, "a FIFO (named pipe)"), (stat.S_ISCHR, "a character device"),
         (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket"))


def _kind(p: Path) -> str | None:
    """None for a regular file or a directory, else what the path is."""
    try:
        mode = p.stat().st_mode
    except OSError:
        return None
    for test, name in _KIND:
        if test(mode):
            return name
    return None


def expand_paths(paths: str | Path | Sequence[str | Path]) -> list[Path]:
    """The record files of the given paths: files as given, a directory's record files (sorted, by suffix
    :data:`RECORD_SUFFIXES`, hidden files skipped), a glob's matches (sorted).

    Raises
    ------
    ValueError
        A path that does not exist (and matches nothing as a glob), a FIFO, device or socket (refused by name:
        records are read twice by the fast reader's fallback), an empty directory, or no file at all.
    """
    items = [paths] if isinstance(paths, (str, Path)) else list(paths)
    out: list[Path] = []
    for item in items:
        p = Path(item)
        kind = _kind(p)
        if kind:
            raise ValueError(f"records path {str(p)!r} is {kind}, not a file; give a regular file, a directory "
                             "of files (one per test) or a glob")
        if p.is_dir():
            found = sorted(q for q in p.iterdir() if q.suffix.lower() in RECORD_SUFFIXES
                           and not q.name.startswith(".") and q.is_file())
            if not found:
                raise ValueError(f"records path {str(p)!r} is a directory with no record file (suffixes "
                                 f"{', '.join(RECORD_SUFFIXES)})")
            out += found
        elif p.is_file():
            out.append(p)
        elif any(ch in str(item) for ch in "*?["):
            found = sorted(Path(q) for q in glob.glob(str(item), recursive=True)
                           if Path(q).is_file() and not Path(q).name.startswith("."))
            if not found:
                raise ValueError(f"records glob {str(item)!r} matches no file")
            out += found
        elif p.exists():
            raise ValueError(f"records path {str(p)!r} is neither a file nor a directory")
        else:
            raise ValueError(f"records file {str(p)!r} does not exist")
    if not out:
        raise ValueError("no records file given")
    return out


def test_id(path: Path, id_pattern: str | None) -> str:
    """The test id of a file: the stem, or the ``id_pattern`` match in the file name (group ``id``, else the
    first group, else the whole match).

    Raises
    ------
    ValueError
        The pattern does not match the name.
    """
    if not id_pattern:
        return path.stem
    m = bounded_search(check_pattern(id_pattern, "--id-pattern"), path.name, "--id-pattern")
    if m is None:
        raise ValueError(f"--id-pattern {id_pattern!r} does not match the file name {path.name!r}")
    if "id" in m.re.groupindex:
        return m.group("id")
    return m.group(1) if m.re.groups else m.group(0)


@dataclass
class ReadLog:
    """What reading noticed without stopping: ``warnings`` (stderr, the JSON ``warnings``, errors under
    ``--strict``) and ``notes`` (stderr only)."""

    warnings: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)


_ADVICE = {
    "file": "give --id-pattern to take distinct ids from the file names",
    "segment": "give --segment-id with {stem} (e.g. '{stem}_{segment}') so that the segments of different files "
               "get different ids",
    "column": "the files' test columns repeat the id: make the ids unique in the files, or read the tests you "
              "need with --tests IDS",
    "container": "the files' groups are named alike: make them unique, or read the tests you need with --tests IDS",
}


def _duplicate(test: str, first: tuple[Path, str], f: Path, kind: str) -> ValueError:
    kinds = {first[1], kind}
    advice = _ADVICE["file"] if kinds == {"file"} else "; ".join(_ADVICE[k] for k in sorted(kinds - {"file"}))
    return ValueError(f"test id {test!r} appears in {str(first[0])!r} and {str(f)!r}; {advice}")


def _bad_lines(tab, spec: ReaderSpec, log: ReadLog | None) -> None:
    if log is None or not tab.bad_lines:
        return
    msg = (f"file {tab.source!r}: {tab.bad_lines} bad line(s) left out (--bad-lines {spec.bad_lines}); the first: "
           f"{tab.first_bad}")
    (log.warnings if spec.bad_lines == "warn" else log.notes).append(msg)


def read_any(paths: str | Path | Sequence[str | Path], spec: ReaderSpec | None = None,
             progress: Callable[[Iterable], Iterable] | None = None, log: ReadLog | None = None,
             tests: Sequence[str] | None = None) -> list[Record]:
    """Read records from files as a rig writes them; t [s], x [mm], F [N].

    Parameters
    ----------
    paths : str, Path or sequence of them
        A file, a directory (its record files, one per test), or a glob such as ``'tests/*.txt'``.
    spec : ReaderSpec or None
        Columns, units, fs, signs, text layout, test ids, computed columns, segments, offsets, covariates (None:
        the canonical ``test,t,x,F`` in s, mm, N).
    progress : callable or None
        Wraps the iteration over files (e.g. a progress bar); None = plain.
    log : ReadLog or None
        Receives what reading noticed without stopping (bad lines left out, ...).
    tests : sequence of str or None
        Keep only these test ids or fnmatch globs (``--tests``); each must match a test read.

    Returns
    -------
    list of Record
        Not validated; in file order, tests of a file in their order.

    Raises
    ------
    ValueError
        Every reading problem, naming the file (and line, column, value where there is one); a test id found
        in two files (with advice that fits where the ids came from); a ``tests`` item that matches nothing.
    """
    spec = spec or ReaderSpec()
    files = expand_paths(paths)
    if len(files) == 1 and spec.is_default and format_of(files[0], spec) == "text":
        recs = read_canonical_csv(files[0])
        if tests:
            keep = set(select_ids([r.test for r in recs], tests))
            recs = [r for r in recs if r.test in keep]
        return recs
    out: list[Record] = []
    seen: list[str] = []
    where: dict[str, tuple[Path, str]] = {}
    for f in (progress(files) if progress else files):
        fspec = spec.for_file(f.name)
        fmt = format_of(f, fspec)
        fid = test_id(f, fspec.id_pattern)
        tabs = [read_text_table(f, fspec)] if fmt == "text" else read_container(f, fmt, fspec, fid)
        for tab in tabs:
            recs = records_from_table(tab, fspec, fid, stem=f.stem, log=log)
            _bad_lines(tab, fspec, log)
            kind = id_source(tab, fspec)
            seen += [r.test for r in recs]
            if tests:
                recs = [r for r in recs if any(matches(it, r.test) for it in tests)]
            if fspec.covariates:
                covariates_from_ids(recs, fspec.covariates)
            for rec in recs:
                if rec.test in where:
                    raise _duplicate(rec.test, where[rec.test], f, kind)
                where[rec.test] = (f, kind)
                out.append(rec)
    if tests:
        select_ids(seen, tests)  # every item must match a test read
    return out
