"""Shared fixtures.  The repository root and the shared data are located by tests/repo_paths.py."""
from __future__ import annotations

from pathlib import Path

import pytest

from repo_paths import REPO


@pytest.fixture(scope="session")
def repo() -> Path:
    return REPO


@pytest.fixture(scope="session")
def verify_checks():
    """Run the SymPy verification once per test session (~30 s)."""
    from chainid.derive import verify

    return {c.equation: c for c in verify.run_checks()}
