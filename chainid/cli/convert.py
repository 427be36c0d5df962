"""CLI: ``chainid convert IN... --to OUT.csv|OUT.parquet|-``: records in the rig's layout -> the canonical long
format ``test,t,x,F`` (s, mm, N), written atomically.

Covariates of the tests (``--reduce``, ``--covariate``, ``--covariates``) go to a side file ``test,name,value``
beside the output, ``OUT.covariates.csv`` (``run.csv`` -> ``run.covariates.csv``; ``--covariates-to`` names
another); the canonical file stays ``test,t,x,F``.  Kept channels (``--keep``) are not written (they are for the
commands that read the records directly).  The output is never an input (the same file, through any link, is
refused before reading); ``--to -`` writes the CSV to stdout, and a character device or FIFO (``/dev/null``) is
written through whatever its name.
"""
from __future__ import annotations

import argparse
import errno
import os
import sys
from typing import Any

from chainid.infra.runlog import note

__all__ = ["cmd_convert", "add_subparsers"]


def _targets(args: argparse.Namespace) -> tuple[str | None, Any]:
    """Check the outputs before reading: the format of ``--to`` and the covariates side file's path."""
    from chainid.infra.fileio import check_inputs_not_outputs, check_output_file
    from chainid.records.covariates import covariates_path
    from chainid.records.reader import expand_paths
    from chainid.records.writer import OUTPUT_FORMATS

    ins = []
    for item in args.inputs:  # the inputs that exist (a missing one is the reader's error, after these checks)
        try:
            ins += [("IN", str(p)) for p in expand_paths(item)]
        except ValueError:
            continue
    if args.to == "-":
        st = os.fstat(sys.stdout.fileno())
        for _, p in ins:
            if os.path.samestat(st, os.stat(p)):
                raise ValueError(f"--to -: stdout is the input {p!r}; refusing to overwrite an input")
        return "csv", args.covariates_to
    check_inputs_not_outputs([("--to", args.to)], ins)
    special = os.path.exists(args.to) and not os.path.isfile(args.to) and not os.path.isdir(args.to)
    suffix = "." + args.to.rsplit(".", 1)[-1].lower() if "." in os.path.basename(args.to) else ""
    if suffix not in OUTPUT_FORMATS and not special:
        raise ValueError(f"--to {args.to!r}: unknown output suffix {suffix or '(none)'!r}; valid: "
                         f"{', '.join(OUTPUT_FORMATS)}")
    check_output_file(args.to, force=args.force, what="--to")
    side = args.covariates_to or (None if special else str(covariates_path(args.to)))
    if side:
        check_inputs_not_outputs([("--covariates-to", side)], ins + [("--to", args.to)])
        check_output_file(side, force=args.force, what="covariates file")
    return OUTPUT_FORMATS.get(suffix, "csv"), side


def cmd_convert(args: argparse.Namespace) -> int:
    """``chainid convert``: read with the reading options, warn on unit slips, write ``test,t,x,F`` (and the
    covariates side file)."""
    from chainid.cli.readopts import load_records
    from chainid.records.covariates import write_covariates
    from chainid.records.writer import write_canonical, write_canonical_to

    try:
        fmt, side = _targets(args)
        chain = None
        if args.chain:
            from chainid.chain.spec import load_chain

            chain = load_chain(args.chain)
        recs = load_records(args, args.inputs, chain)
        n = sum(r.t.size for r in recs)
        if args.to == "-":
            try:
                write_canonical_to(sys.stdout.buffer, recs)
                sys.stdout.flush()
            except OSError as exc:  # the reader of the pipe left (| head): stop quietly, as cat does
                if getattr(exc, "errno", None) != errno.EPIPE and "Broken pipe" not in str(exc):
                    raise
                os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
                return 141
        else:
            write_canonical(args.to, recs, overwrite=args.force, fmt=fmt)
        where = "stdout" if args.to == "-" else args.to
        print(f"wrote {where}: {len(recs)} test(s), {n} rows (test,t,x,F in s, mm, N)",
              file=sys.stderr if args.to == "-" else sys.stdout)
        if any(r.covariates for r in recs):
            if side:
                write_covariates(side, recs, overwrite=args.force)
                print(f"wrote {side}: covariates of {sum(bool(r.covariates) for r in recs)} test(s) "
                      "(test,name,value)", file=sys.stderr if args.to == "-" else sys.stdout)
            else:
                note("the covariates are not written (give --covariates-to FILE)")
        if any(r.channels for r in recs):
            note("kept channels (--keep) are not part of the canonical test,t,x,F and are not written")
    except ValueError as exc:
        print(f"chainid convert: error: {exc}", file=sys.stderr)
        return 2
    return 0


def add_subparsers(subparsers: Any) -> None:
    """Register ``chainid convert``."""
    from chainid.cli.readopts import add_reader_options

    p = subparsers.add_parser("convert", help="records in a rig's layout/format -> canonical test,t,x,F (CSV/Parquet)",
                              description=cmd_convert.__doc__)
    p.add_argument("inputs", nargs="+", metavar="IN", help="record files, directories or globs")
    p.add_argument("--to", required=True, metavar="OUT.csv|OUT.parquet|-",
                   help="output file (canonical long format), - for CSV on stdout")
    p.add_argument("--covariates-to", dest="covariates_to", metavar="FILE.csv",
                   help="covariates side file test,name,value (default OUT.covariates.csv beside --to)")
    p.add_argument("--chain", metavar="FILE.toml|PRESET",
                   help="check amplitudes, forces and stiffness against this chain (unit-slip warnings)")
    p.add_argument("--force", action="store_true", help="overwrite an existing output file")
    add_reader_options(p, strict=True, quiet=True)
    p.set_defaults(func=cmd_convert)
