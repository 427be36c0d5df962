"""Markdown tables of the report (chainid.report.common) escape the bars in cells."""
from __future__ import annotations

from chainid.report.common import md_table


def test_md_table_escapes_bars():
    assert md_table(["a", "b"], [[1, "x|y"], [2.5, None]]) == (
        "| a | b |\n|---|---|\n| 1 | x/y |\n| 2.5 | None |")
