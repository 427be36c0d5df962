"""Shared fixtures, and the order and grouping of the suite.  The repository root and the shared data are located
by tests/repo_paths.py."""
from __future__ import annotations

from pathlib import Path

import pytest

from repo_paths import REPO


@pytest.fixture(scope="session")
def repo() -> Path:
    return REPO


@pytest.fixture(scope="session")
def verify_checks():
    """Run the SymPy verification once per test session (~100 s)."""
    from chainid.derive import verify

    return {c.equation: c for c in verify.run_checks()}


# Under pytest-xdist (``--dist loadgroup`` in pyproject.toml) each test file goes to one worker as a whole, so a
# module-scoped fixture (a simulation, a diagnosis) is built once, not once per worker.  The SymPy files of
# tests/derive/ form one group: the verification and the emission share SymPy's caches in one process (the
# emission after the verification takes ~1 s instead of ~30 s).
SAME_WORKER = {"derive": "derive"}


def _group(item: pytest.Item) -> str:
    rel = Path(str(item.path)).relative_to(REPO / "tests")
    return SAME_WORKER.get(rel.parts[0], rel.as_posix())


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Each test file is one xdist group (tests/derive/ one together), and the groups that hold slow tests go first,
    the SymPy group before all: the long tests start while the short ones fill the other worker, so no worker is
    left alone with a long test at the end.  The order within a group is kept."""
    groups = {}
    for it in items:
        groups.setdefault(_group(it), []).append(it)
    if config.pluginmanager.hasplugin("xdist") and config.getoption("dist", "no") == "loadgroup":
        for g, its in groups.items():
            for it in its:
                if it.get_closest_marker("xdist_group") is None:
                    it.add_marker(pytest.mark.xdist_group(g))

    def rank(g: str) -> tuple[int, int]:
        slow = sum(1 for it in groups[g] if it.get_closest_marker("slow"))
        return (0 if g == "derive" else 1 if slow else 2), -slow

    items[:] = [it for g in sorted(groups, key=rank) for it in groups[g]]
