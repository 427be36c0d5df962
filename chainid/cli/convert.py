"""CLI: ``chainid convert IN... --to OUT.csv|.parquet``: records in the rig's layout -> the canonical long format
``test,t,x,F`` (s, mm, N), written atomically."""
from __future__ import annotations

import argparse
import sys
from typing import Any

__all__ = ["cmd_convert", "add_subparsers"]


def cmd_convert(args: argparse.Namespace) -> int:
    """``chainid convert``: read with the reading options, warn on unit slips, write ``test,t,x,F``."""
    from chainid.cli.readopts import load_records
    from chainid.infra.fileio import check_output_file
    from chainid.records.writer import OUTPUT_FORMATS, write_canonical

    try:
        suffix = "." + args.to.rsplit(".", 1)[-1].lower() if "." in args.to else ""
        if suffix not in OUTPUT_FORMATS:
            raise ValueError(f"--to {args.to!r}: unknown output suffix {suffix or '(none)'!r}; valid: "
                             f"{', '.join(OUTPUT_FORMATS)}")
        check_output_file(args.to, force=args.force, what="--to")  # before reading
        chain = None
        if args.chain:
            from chainid.chain.spec import load_chain

            chain = load_chain(args.chain)
        recs = load_records(args, args.inputs, chain)
        write_canonical(args.to, recs, overwrite=args.force)
        n = sum(r.t.size for r in recs)
        print(f"wrote {args.to}: {len(recs)} test(s), {n} rows (test,t,x,F in s, mm, N)")
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
    p.add_argument("--to", required=True, metavar="OUT.csv|OUT.parquet", help="output file (canonical long format)")
    p.add_argument("--chain", metavar="FILE.toml|PRESET",
                   help="check amplitudes, forces and stiffness against this chain (unit-slip warnings)")
    p.add_argument("--force", action="store_true", help="overwrite an existing output file")
    add_reader_options(p, strict=True, quiet=True)
    p.set_defaults(func=cmd_convert)
