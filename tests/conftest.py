"""Shared fixtures, and the order and grouping of the suite.  The repository root and the shared data are located
by tests/repo_paths.py."""
from __future__ import annotations

from pathlib import Path

import numpy  # noqa: F401  (loads numpy's and scipy's BLAS, so that the limit below reaches them)
import pytest
import scipy.linalg  # noqa: F401
import sklearn.ensemble  # noqa: F401  (loads scikit-learn's OpenMP runtime, for the same reason)
import threadpoolctl

from repo_paths import REPO

# Every test process (each xdist worker) runs numpy's BLAS and scikit-learn's OpenMP on one thread, as the diagnosis
# does (chainid.infra.threads): two workers with two threads each would spin against each other.
threadpoolctl.threadpool_limits(limits=1, user_api="blas")
threadpoolctl.threadpool_limits(limits=1, user_api="openmp")


@pytest.fixture(scope="session")
def repo() -> Path:
    return REPO


@pytest.fixture(scope="session")
def verify_checks():
    """Run the SymPy verification once per test session (~4 s on 2 cores)."""
    from chainid.derive import verify

    return {c.equation: c for c in verify.run_checks()}


# Under pytest-xdist (``-n auto --dist loadfile`` in pyproject.toml) each test file goes to one worker as a whole,
# so a module-scoped fixture (a simulation, a diagnosis) is built once, not once per worker.  The files that run
# SymPy in the test process go to one worker together: the verification is cached for the process
# (chainid.derive.verify.run_checks) and the derivation's expressions too (lru_cache), so the emission after the
# verification takes ~0.4 s instead of ~3 s, and `chainid report`'s own check of the paper none instead of ~4 s.
# (xdist's ``loadgroup`` does not group under pytest 9: it renames node ids through ``item._nodeid``, which
# pytest 9 no longer reads.)
SAME_WORKER = {  # path under the repository (a folder ends with /) -> the unit it runs in
    "tests/derive/": "sympy",
    "tests/report/test_report_command.py": "sympy",
    "tests/cli/test_cli_generate.py": "sympy",
    "tests/model/test_practice.py": "sympy",
}


def _unit(path: str) -> str:
    """The scheduling unit of a test file given by its path relative to the repository: its SAME_WORKER group or
    the file itself."""
    return next((g for p, g in SAME_WORKER.items() if path == p or (p.endswith("/") and path.startswith(p))), path)


def _group_path(item: pytest.Item) -> str:
    return Path(str(item.path)).relative_to(REPO).as_posix()


def _group(item: pytest.Item) -> str:
    return _unit(_group_path(item))


@pytest.hookimpl(tryfirst=True, optionalhook=True)
def pytest_xdist_make_scheduler(config: pytest.Config, log):  # noqa: ANN001, ANN201
    """``--dist loadfile`` with each SAME_WORKER group as one unit; the units in collection order."""
    if config.getvalue("dist") != "loadfile":
        return None
    from xdist.scheduler import LoadFileScheduling

    class FileGroups(LoadFileScheduling):
        def _split_scope(self, nodeid: str) -> str:
            return _unit(nodeid.split("::", 1)[0])

    return FileGroups(config, log)


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """The units (files, or a SAME_WORKER group) that hold slow tests go first, the SymPy one before all: under xdist
    the long tests start while the short ones fill the other worker, so no worker is left alone with a long test
    at the end.  The order within a file is kept."""
    groups: dict[str, list[pytest.Item]] = {}
    for it in items:
        groups.setdefault(_group(it), []).append(it)

    def rank(g: str) -> tuple[int, int]:
        slow = sum(1 for it in groups[g] if it.get_closest_marker("slow"))
        return (0 if g == "sympy" else 1 if slow else 2), -slow

    if "sympy" in groups:  # the verification first: the others then find SymPy's results cached
        groups["sympy"].sort(key=lambda it: not _group_path(it).startswith("tests/derive/"))
    items[:] = [it for g in sorted(groups, key=rank) for it in groups[g]]
