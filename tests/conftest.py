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


# Under pytest-xdist (``-n auto --dist loadfile`` in pyproject.toml) each test file goes to one worker as a whole,
# so a module-scoped fixture (a simulation, a diagnosis) is built once, not once per worker, and tests/derive/ goes
# to one worker as a whole: the SymPy verification and emission share SymPy's caches in one process (the emission
# after the verification takes ~1 s instead of ~30 s).  (xdist's own ``loadgroup`` does not group under pytest 9:
# it renames node ids through ``item._nodeid``, which pytest 9 no longer reads.)
SAME_WORKER = {"derive": "derive"}


def _group(item: pytest.Item) -> str:
    rel = Path(str(item.path)).relative_to(REPO / "tests")
    return SAME_WORKER.get(rel.parts[0], rel.as_posix())


@pytest.hookimpl(tryfirst=True, optionalhook=True)
def pytest_xdist_make_scheduler(config: pytest.Config, log):  # noqa: ANN001, ANN201
    """``--dist loadfile`` with the folders of SAME_WORKER as one unit each; the units in collection order."""
    if config.getvalue("dist") != "loadfile":
        return None
    from xdist.scheduler import LoadFileScheduling

    class FileGroups(LoadFileScheduling):
        def _split_scope(self, nodeid: str) -> str:
            path = nodeid.split("::", 1)[0]
            parts = path.split("/")
            if len(parts) > 2 and parts[0] == "tests" and parts[1] in SAME_WORKER:
                return SAME_WORKER[parts[1]]
            return path

    return FileGroups(config, log)


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """The test files (tests/derive/ as one) that hold slow tests go first, the SymPy ones before all: under xdist
    the long tests start while the short ones fill the other worker, so no worker is left alone with a long test
    at the end.  The order within a file is kept."""
    groups: dict[str, list[pytest.Item]] = {}
    for it in items:
        groups.setdefault(_group(it), []).append(it)

    def rank(g: str) -> tuple[int, int]:
        slow = sum(1 for it in groups[g] if it.get_closest_marker("slow"))
        return (0 if g == "derive" else 1 if slow else 2), -slow

    items[:] = [it for g in sorted(groups, key=rank) for it in groups[g]]
