"""Helpers shared by the command modules: JSON output and target checks, progress lines."""
from __future__ import annotations

import sys
from typing import Any

__all__ = ["write_json", "check_json_target", "progress"]

def write_json(doc: Any, target: str | None, force: bool = False, what: str = "--json") -> None:
    """Write ``doc`` as strict JSON to ``target`` ("-" = stdout) atomically; refuse to overwrite without ``force``.

    Non-finite numbers are written as ``null`` (see :func:`chainid.infra.fileio.write_json`).
    """
    from chainid.infra.fileio import write_json as _write

    _write(doc, target, force=force, what=what)


def check_json_target(target: str | None, force: bool, what: str = "--json") -> None:
    """Check a ``--json`` target before the work starts ("-" and None need no check)."""
    from chainid.infra.fileio import check_output_file

    if target is not None and target != "-":
        check_output_file(target, force=force, what=what)


def progress(msg: str) -> None:
    """One progress line on stderr."""
    print(f"  ... {msg}", file=sys.stderr, flush=True)
