"""A subset of tests by id: ``--tests IDS|GLOB`` (a comma list of test ids or fnmatch globs, ``'T1,ME2mm*'``).

Every item must match at least one test read; an item that matches none is an error listing the valid ids.
The selection keeps the file order of the tests.
"""
from __future__ import annotations

import fnmatch
from typing import Sequence

__all__ = ["parse_tests", "matches", "select_ids"]


def parse_tests(text: str | None) -> list[str] | None:
    """``"A, B*"`` -> ``["A", "B*"]``; None or blank -> None.

    Raises
    ------
    ValueError
        A list with no item (``--tests ,``).
    """
    if text is None:
        return None
    items = [s.strip() for s in text.split(",") if s.strip()]
    if not items:
        raise ValueError(f"--tests {text!r}: give test ids or globs, comma separated (e.g. T1,T2 or 'ME2mm*')")
    return items


def matches(item: str, test: str) -> bool:
    """True when a ``--tests`` item (an id, or a glob with ``* ? [``) selects ``test``."""
    if any(ch in item for ch in "*?["):
        return fnmatch.fnmatchcase(test, item)
    return test == item


def select_ids(ids: Sequence[str], items: Sequence[str]) -> list[str]:
    """The ids (in their order) matched by any item.

    Raises
    ------
    ValueError
        An item that matches no id, naming it and listing the valid ids.
    """
    none = [it for it in items if not any(matches(it, t) for t in ids)]
    if none:
        shown = ", ".join(ids[:40]) + (f", ... ({len(ids)} in all)" if len(ids) > 40 else "")
        raise ValueError(f"--tests: {', '.join(repr(n) for n in none)} match(es) no test; valid ids: {shown}")
    return [t for t in ids if any(matches(it, t) for it in items)]
