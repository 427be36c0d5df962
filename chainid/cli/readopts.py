"""Reader options shared by every command that reads records (identify, diagnose incl. --validate, predict,
report --data, convert): one helper adds them, one builds the :class:`~chainid.records.spec.ReaderSpec`, one
reads (with progress and the unit-slip warnings)."""
from __future__ import annotations

import argparse
from typing import Any

__all__ = ["add_reader_options", "reader_spec", "load_records", "chain_for_checks"]

_FORMATS = ("text", "json", "mat", "hdf5", "tdms", "parquet")


def add_reader_options(p: argparse.ArgumentParser, strict: bool = False, quiet: bool = False) -> None:
    """Add ``--reader --columns --units --fs --scale --delimiter --decimal --skip-rows --id-pattern --format``
    (and ``--strict`` / ``--quiet`` where the command has none of its own)."""
    g = p.add_argument_group("reading records (files as the rig writes them; see README 'Your own data')")
    g.add_argument("--reader", metavar="PROFILE.toml",
                   help="reader profile: the keys below in a TOML file (options given here override it)")
    g.add_argument("--columns", metavar="ROLE=COL,...",
                   help="which column is t, x, F, test: names (t=Time,x=Disp,F=Load,test=Specimen) or 1-based "
                        "positions for headerless files (F=1,x=2); default: columns named test,t,x,F")
    g.add_argument("--units", metavar="ROLE=UNIT,...",
                   help="units of the columns, converted by pint (t=ms,x=in,F=kip); default s, mm, N")
    g.add_argument("--fs", type=float, metavar="HZ", help="sampling rate [Hz] of files without a time column")
    g.add_argument("--scale", metavar="ROLE=FACTOR,...",
                   help="factors after the unit conversion, e.g. x=-1 when the rig reports compression positive")
    g.add_argument("--delimiter", metavar="D", help="field separator: ',', ';', '|', tab, whitespace (default: sniffed)")
    g.add_argument("--decimal", choices=(".", ","), help="decimal mark (default '.')")
    g.add_argument("--skip-rows", dest="skip_rows", type=int, metavar="N",
                   help="lines of a header block before the column names (or the first data row)")
    g.add_argument("--id-pattern", dest="id_pattern", metavar="REGEX",
                   help="test id from the file name: group 'id', else group 1 (default: the file stem)")
    g.add_argument("--format", dest="reader_format", choices=_FORMATS, help="file format (default: by suffix)")
    if strict:
        g.add_argument("--strict", action="store_true", help="plausibility warnings (unit slips) are errors")
    if quiet:
        g.add_argument("--quiet", action="store_true", help="no progress bar")


def reader_spec(args: argparse.Namespace) -> Any:
    """The :class:`ReaderSpec` of the command line (``--reader`` profile overridden by the options)."""
    from chainid.records.spec import spec_from_options

    if args.skip_rows is not None and args.skip_rows < 0:
        raise ValueError(f"--skip-rows = {args.skip_rows} is invalid; valid range >= 0")
    return spec_from_options(args.reader, columns=args.columns, units=args.units, fs=args.fs, scale=args.scale,
                             delimiter=args.delimiter, decimal=args.decimal, skip_rows=args.skip_rows,
                             id_pattern=args.id_pattern, format=args.reader_format)


def chain_for_checks(args: argparse.Namespace) -> Any:
    """The chain the records are read for (``--model chain``, the default), or None (a linear model, a file)."""
    if getattr(args, "model", "chain") != "chain":
        return None
    from chainid.chain.spec import load_chain

    return load_chain(getattr(args, "chain", None))


def load_records(args: argparse.Namespace, paths: Any, chain: Any = None, doc: dict | None = None,
                 check: Any = None) -> list:
    """Read records as the options say; print the plausibility warnings (``--strict``: raise them).

    Parameters
    ----------
    args : Namespace
        With the options of :func:`add_reader_options`.
    paths : str or list of str
        File, directory or glob (or several).
    chain : ChainSpec or None
        Check amplitudes, forces and stiffness against this chain's elastic range.
    doc : dict or None
        The command's JSON result: warnings are added to ``doc["warnings"]``.
    check : callable, optional
        The command's own hard checks of the records (raising ValueError), run before the plausibility
        warnings, so that a record the command refuses gets its one error line and no warnings first.
    """
    from chainid.infra.progress import progress_iter
    from chainid.records.plausible import plausibility_warnings
    from chainid.records.reader import read_any

    spec = reader_spec(args)
    quiet = bool(getattr(args, "quiet", False))
    recs = read_any(paths, spec, progress=lambda files: progress_iter(files, "reading", len(files), quiet, "file"))
    if check is not None:
        check(recs)
    msgs = plausibility_warnings(recs, chain, getattr(args, "variant", "paper") or "paper")
    if msgs and getattr(args, "strict", False):
        raise ValueError("--strict: implausible records: " + "; ".join(msgs))
    from chainid.infra.runlog import warn

    for m in msgs:
        warn(m)  # on stderr and in the run's JSON warnings
    if doc is not None and msgs:
        doc.setdefault("warnings", []).extend(msgs)
    return recs
