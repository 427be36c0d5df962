"""Reader options shared by every command that reads records (identify, diagnose incl. --validate, predict,
audit --data, report --data, convert): one helper adds them, one builds the
:class:`~chainid.records.spec.ReaderSpec`, one reads (with progress, covariates, the test selection and the
unit-slip warnings)."""
from __future__ import annotations

import argparse
import sys
from typing import Any

__all__ = ["add_reader_options", "reader_spec", "load_records", "chain_for_checks"]

_FORMATS = ("text", "json", "mat", "hdf5", "tdms", "parquet")


def add_reader_options(p: argparse.ArgumentParser, strict: bool = False, quiet: bool = False,
                       tests: bool = True) -> None:
    """Add the reading options (``--reader --columns --units --fs --scale --delimiter --decimal --skip-rows
    --id-pattern --format``, the DAQ options, computed columns, segments, covariates, ``--tests``) and
    ``--strict`` / ``--quiet`` where the command has none of its own."""
    g = p.add_argument_group("reading records (files as the rig writes them; see README 'Your own data')")
    g.add_argument("--reader", metavar="PROFILE.toml",
                   help="reader profile: the keys below in a TOML file (options given here override it)")
    g.add_argument("--columns", metavar="ROLE=COL,...",
                   help="which column is t, x, F, test, events: names (t=Time,x=Disp,F=Load,test=Specimen), "
                        "computed names, or 1-based positions (F=1,x=2); default: columns named test,t,x,F")
    g.add_argument("--units", metavar="NAME=UNIT,...",
                   help="units of the columns, converted by pint (t=ms,x=in,F=kip; a kept channel p=bar -> MPa); "
                        "default s, mm, N")
    g.add_argument("--fs", type=float, metavar="HZ", help="sampling rate [Hz] of files without a time column "
                                                          "(default: the file's Sampling Interval/Rate line)")
    g.add_argument("--scale", metavar="NAME=FACTOR,...",
                   help="gains applied last (after units and --zero), e.g. x=-1 when the rig reports compression "
                        "positive")
    g.add_argument("--zero", metavar="NAME=HOW,...",
                   help="offsets removed per test/segment after the units, before --scale: first, first:N (mean of "
                        "the first N samples), mean, median (x=first:20)")
    g.add_argument("--derive", action="append", metavar="'NAME = EXPR'",
                   help="a computed column over the file's numbers (F = c7 - c6*51.875; cN = column N, names, "
                        "+ - * / ** abs sqrt exp log sin cos ... where); repeatable")
    g.add_argument("--keep", metavar="NAME,...", help="columns kept on the records as extra channels (p,T)")
    g.add_argument("--reduce", metavar="COV=STAT(COL),...",
                   help="covariates from a column per test/segment: mean, median, first, last, min, max "
                        "(p_mean=mean(c6))")
    g.add_argument("--covariate", action="append", metavar="'NAME=REGEX'",
                   help="a covariate from the test id: group 'value' or group 1, a number (p_bar=_([0-9.]+)bar$); "
                        "repeatable")
    g.add_argument("--covariates", metavar="FILE.csv", help="covariates side file test,name,value")
    g.add_argument("--delimiter", metavar="D", help="field separator: ',', ';', '|', tab, whitespace (default: sniffed)")
    g.add_argument("--decimal", choices=(".", ","), help="decimal mark (default '.')")
    g.add_argument("--skip-rows", dest="skip_rows", type=int, metavar="N",
                   help="physical lines above the column-name line (or above the first data row); a 'Header Size: "
                        "N' line counts the name line too, so it means --skip-rows N-1")
    g.add_argument("--header-marker", dest="header_marker", metavar="REGEX",
                   help="the column-name line is the first line matching REGEX (instead of --skip-rows)")
    g.add_argument("--names", metavar="A,B,...", help="column names for a file without a name line (or to replace it)")
    g.add_argument("--bad-lines", dest="bad_lines", choices=("error", "warn", "skip"),
                   help="a data line with more fields than the names or an unreadable used value: stop there with an "
                        "error (the reader's default), or leave it out and count it (warn: a warning; skip: a note)")
    g.add_argument("--split-events", dest="split_events", metavar="REGEX",
                   help="one test per segment: a row whose events cell matches ends its segment ('DAQ Pause')")
    g.add_argument("--split-gap", dest="split_gap", type=float, metavar="S",
                   help="one test per segment: cut where the time step exceeds S seconds")
    g.add_argument("--segment-ids", dest="segment_ids", metavar="L1,L2,...",
                   help="labels of the segments in order (their count must match)")
    g.add_argument("--segment-id", dest="segment_id", metavar="TEMPLATE",
                   help="test id of a segment from {stem} {id} {segment} {label} (default {id}_{segment}, "
                        "{id}_{label} with labels)")
    g.add_argument("--id-pattern", dest="id_pattern", metavar="REGEX",
                   help="test id from the file name: group 'id', else group 1 (default: the file stem)")
    g.add_argument("--format", dest="reader_format", choices=_FORMATS, help="file format (default: by suffix)")
    if tests:
        g.add_argument("--tests", metavar="IDS|GLOBS",
                       help="only these tests: test ids or fnmatch globs, comma separated (T1,T2 or 'ME2mm*')")
    if strict:
        g.add_argument("--strict", action="store_true", help="plausibility warnings (unit slips) are errors")
    if quiet:
        g.add_argument("--quiet", action="store_true", help="no progress bar")


def reader_spec(args: argparse.Namespace) -> Any:
    """The :class:`ReaderSpec` of the command line (``--reader`` profile overridden by the options)."""
    from chainid.records.spec import spec_from_options

    if args.skip_rows is not None and args.skip_rows < 0:
        raise ValueError(f"--skip-rows = {args.skip_rows} is invalid; valid range >= 0")
    opt = {k: getattr(args, k, None) for k in ("names", "header_marker", "bad_lines", "derive", "keep", "reduce",
                                              "zero", "split_events", "split_gap", "segment_ids", "segment_id")}
    return spec_from_options(args.reader, columns=args.columns, units=args.units, fs=args.fs, scale=args.scale,
                             delimiter=args.delimiter, decimal=args.decimal, skip_rows=args.skip_rows,
                             id_pattern=args.id_pattern, format=args.reader_format,
                             covariates=getattr(args, "covariate", None), **opt)


def chain_for_checks(args: argparse.Namespace) -> Any:
    """The chain the records are read for (``--model chain``, the default), or None (a linear model, a file)."""
    if getattr(args, "model", "chain") != "chain":
        return None
    from chainid.chain.spec import load_chain

    return load_chain(getattr(args, "chain", None))


def _chain_defaulted(args: argparse.Namespace) -> bool:
    """True when the chain is the built-in default (``--model chain`` without ``--chain``)."""
    return getattr(args, "model", "chain") == "chain" and hasattr(args, "chain") and args.chain is None


def load_records(args: argparse.Namespace, paths: Any, chain: Any = None, doc: dict | None = None,
                 check: Any = None, select: bool = True) -> list:
    """Read records as the options say; print the plausibility warnings (``--strict``: raise them).

    Parameters
    ----------
    args : Namespace
        With the options of :func:`add_reader_options`.
    paths : str or list of str
        File, directory or glob (or several).
    chain : ChainSpec or None
        Check amplitudes, forces and stiffness against this chain's elastic range.  When it is the built-in
        default (no ``--chain``) and the records cannot be a chain's
        (:func:`chainid.records.plausible.not_a_chain`), one line suggests ``--model linear`` instead of the
        chain checks, and ``args.not_a_chain`` is set (the command then skips its chain load warnings too).
    doc : dict or None
        The command's JSON result: warnings are added to ``doc["warnings"]``.
    check : callable, optional
        The command's own hard checks of the records (raising ValueError), run before the plausibility
        warnings, so that a record the command refuses gets its one error line and no warnings first.
    select : bool
        Apply ``--tests`` (False for a second data set such as ``diagnose --validate``).
    """
    from chainid.infra.progress import progress_iter
    from chainid.records.covariates import apply_covariates, read_covariates
    from chainid.records.plausible import grouped, not_a_chain, plausibility_warnings
    from chainid.records.reader import ReadLog, read_any
    from chainid.records.select import matches, parse_tests

    spec = reader_spec(args)
    quiet = bool(getattr(args, "quiet", False))
    log = ReadLog()
    tests = parse_tests(getattr(args, "tests", None)) if select else None
    recs = read_any(paths, spec, progress=lambda files: progress_iter(files, "reading", len(files), quiet, "file"),
                    log=log, tests=tests)
    if getattr(args, "covariates", None):
        table = read_covariates(args.covariates)
        if tests:  # ids left out by --tests are not "not read"
            table = {k: v for k, v in table.items() if any(matches(it, k) for it in tests)}
        log.warnings += apply_covariates(recs, table, args.covariates)
    if check is not None:
        check(recs)
    extra = []
    if chain is not None and _chain_defaulted(args):
        why = not_a_chain(recs)
        if why:
            chain = None
            args.not_a_chain = why
            extra = [f"these records do not look like a chain's: {why}; the chain's unit-slip and load checks are "
                     "skipped: for a seal, a damper or another part use --model linear (or give --chain for a chain)"]
    msgs = extra + plausibility_warnings(recs, chain, getattr(args, "variant", "paper") or "paper") \
        + grouped(log.warnings)
    if msgs and getattr(args, "strict", False):
        raise ValueError("--strict: implausible records: " + "; ".join(msgs))
    from chainid.infra.runlog import note, warn

    for m in grouped(log.notes):
        note(m)
    for m in msgs:
        warn(m)  # on stderr and in the run's JSON warnings
    if doc is not None and msgs:
        doc.setdefault("warnings", []).extend(msgs)
    return recs
