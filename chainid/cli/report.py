"""``chainid report``: the command (the work is :func:`chainid.report.run_report`)."""
from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from chainid.report import run_report

__all__ = ["cmd_report", "add_subparsers"]

def cmd_report(args: argparse.Namespace) -> int:
    from chainid.cli.readopts import load_records, reader_spec

    spec = reader_spec(args)
    if args.data:  # sampling warnings (--strict: errors) first; the report checks the chain itself (step 4)
        load_records(args, args.data)
    path = run_report(Path(args.out), args.chain, args.data, args.force, reader=None if spec.is_default else spec)
    print(f"report written: {path.resolve()}")
    return 0


def add_subparsers(subparsers: Any) -> None:
    """Register ``chainid report``."""
    p = subparsers.add_parser("report", help="the main job: verification, stiffness, damping and gap report")
    p.add_argument("--out", default="chainid-report", metavar="DIR", help="report folder (default ./chainid-report)")
    p.add_argument("--chain", metavar="FILE.toml", help="chain file or preset name, e.g. din22252:26x92 (default: the built-in 14x50 chain)")
    p.add_argument("--data", metavar="DATA.csv", help="run steps 3-4 on these records (header test,t,x,F; or a "
                                                      "file/directory/glob in the rig's layout with the reading options)")
    p.add_argument("--force", action="store_true",
                   help="re-run into an existing folder (replaces only the previous report's files)")
    from chainid.cli.readopts import add_reader_options

    add_reader_options(p, strict=True, quiet=True)
    p.set_defaults(func=cmd_report)
