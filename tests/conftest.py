"""Shared fixtures.  The repository root and ../shared are located relative to this file."""
from __future__ import annotations

from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
SHARED = REPO.parent / "shared"


@pytest.fixture(scope="session")
def repo() -> Path:
    return REPO


@pytest.fixture(scope="session")
def verify_checks():
    """Run the SymPy verification once per test session (~30 s)."""
    from chainid.derive import verify

    return {c.equation: c for c in verify.run_checks()}
