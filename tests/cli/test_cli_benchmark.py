"""``chainid benchmark-gap`` exits 0 when the benchmark finished."""
from __future__ import annotations

from chainid.cli import main


def test_cli_benchmark_gap_exit_code(monkeypatch):
    """A finished benchmark exits 0 (the grid itself is replaced by a stand-in here).  Bug caught: rc 1."""
    import importlib

    bm = importlib.import_module("chainid.gap.benchmark.grid")
    monkeypatch.setattr(bm, "run_benchmark", lambda **kw: None)
    assert main(["benchmark-gap", "--small", "--no-progress"]) == 0
