"""Helpers every report step shares: the JSON dump into ``json/``, a markdown table, the progress type."""
from __future__ import annotations

from pathlib import Path
from typing import Any, Callable

__all__ = ["Progress", "dump_json", "md_table"]

#: A progress callback: one line of text.
Progress = Callable[[str], None]


def dump_json(folder: Path, name: str, doc: Any) -> str:
    """Write ``folder/json/name`` as strict JSON (NaN/inf → null); returns the relative path."""
    from chainid.infra.fileio import atomic_write_text, dumps_json
    from chainid.infra.runlog import merge_warnings

    atomic_write_text(folder / "json" / name, dumps_json(merge_warnings(doc)) + "\n", force=True, what="report")
    return f"json/{name}"


def md_table(headers: list[str], rows: list[list[Any]]) -> str:
    """A markdown table (``|`` inside a cell becomes ``/``)."""
    out = ["| " + " | ".join(headers) + " |", "|" + "|".join("---" for _ in headers) + "|"]
    for r in rows:
        out.append("| " + " | ".join(str(c).replace("|", "/") for c in r) + " |")
    return "\n".join(out)
