"""The two paths of the text reader side by side, for the tests that check they agree: the fast path (numpy's
loadtxt for whitespace, else pyarrow) and the line-by-line scan."""
from __future__ import annotations

from pathlib import Path


def fast_and_scan(path: Path, spec) -> tuple[object, dict | None, dict]:  # noqa: ANN001
    """(layout, the fast path's columns or None, the scan's columns) of a text file read with ``spec``
    (t, x, F roles; no test column)."""
    from chainid.records.table import resolve_roles
    from chainid.records.textread import _fast, scan_strict, text_layout

    lay = text_layout(path, spec)
    use = resolve_roles(lay.names, spec, str(path), lay.positional, skip_test=True)
    return lay, _fast(path, lay, use, "."), scan_strict(path, lay, use, ".")
