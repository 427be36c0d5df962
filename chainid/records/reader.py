"""One entry point for every command that reads records: :func:`read_any` (a file, a directory or a glob of
one-file-per-test, in any supported format, mapped by a :class:`~chainid.records.spec.ReaderSpec`).

The canonical long CSV ``test,t,x,F`` in s, mm, N, given as a single file with no reader options, takes the
canonical reader (:mod:`.textcanon`: same records and errors as always, parsed fast).
"""
from __future__ import annotations

import glob
import re
import stat
from pathlib import Path
from typing import Callable, Iterable, Sequence

from chainid.records.formats import SUFFIXES, format_of, read_container
from chainid.records.record import Record
from chainid.records.spec import ReaderSpec
from chainid.records.table import records_from_table
from chainid.records.textcanon import read_canonical_csv
from chainid.records.textread import read_text_table

__all__ = ["expand_paths", "test_id", "read_any", "RECORD_SUFFIXES"]

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
            found = sorted(Path(q) for q in glob.glob(str(item), recursive=True) if Path(q).is_file())
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
    m = re.search(id_pattern, path.name)
    if m is None:
        raise ValueError(f"--id-pattern {id_pattern!r} does not match the file name {path.name!r}")
    if "id" in m.re.groupindex:
        return m.group("id")
    return m.group(1) if m.re.groups else m.group(0)


def read_any(paths: str | Path | Sequence[str | Path], spec: ReaderSpec | None = None,
             progress: Callable[[Iterable], Iterable] | None = None) -> list[Record]:
    """Read records from files as a rig writes them; t [s], x [mm], F [N].

    Parameters
    ----------
    paths : str, Path or sequence of them
        A file, a directory (its record files, one per test), or a glob such as ``'tests/*.txt'``.
    spec : ReaderSpec or None
        Columns, units, fs, signs, text layout, test ids (None: the canonical ``test,t,x,F`` in s, mm, N).
    progress : callable or None
        Wraps the iteration over files (e.g. a progress bar); None = plain.

    Returns
    -------
    list of Record
        Not validated; in file order, tests of a file in their order.

    Raises
    ------
    ValueError
        Every reading problem, naming the file (and line, column, value where there is one); a test id found
        in two files.
    """
    spec = spec or ReaderSpec()
    files = expand_paths(paths)
    if len(files) == 1 and spec.is_default and format_of(files[0], spec) == "text":
        return read_canonical_csv(files[0])
    out: list[Record] = []
    where: dict[str, Path] = {}
    for f in (progress(files) if progress else files):
        fmt = format_of(f, spec)
        fid = test_id(f, spec.id_pattern)
        tabs = [read_text_table(f, spec)] if fmt == "text" else read_container(f, fmt, spec, fid)
        for tab in tabs:
            for rec in records_from_table(tab, spec, fid):
                if rec.test in where:
                    raise ValueError(f"test id {rec.test!r} appears in {str(where[rec.test])!r} and {str(f)!r}; "
                                     "give --id-pattern to take distinct ids from the file names")
                where[rec.test] = f
                out.append(rec)
    return out
