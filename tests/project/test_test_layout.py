"""The tests mirror the package: tests/<package>/test_<behaviour>.py (tests/gap/<sub-package>/ for chainid.gap's
sub-packages), plus tests/derive/ and tests/project/; every test file's basename is unique across the tree (pytest
imports test files by basename: two of the same name break collection); no ``__init__.py``; the root of tests/
holds only the shared helpers and conftest.py."""
from __future__ import annotations

from collections import Counter

from repo_paths import REPO

TESTS = REPO / "tests"
PKG = REPO / "chainid"
EXTRA = {"derive", "project"}  # SymPy derivation and generated/; layers, README, notebooks, this layout


def _subpackages(folder):
    return {p.name for p in folder.iterdir() if (p / "__init__.py").is_file()}


def test_test_files_sit_in_a_folder_of_their_package():
    allowed = _subpackages(PKG) | EXTRA
    bad = []
    for f in sorted(TESTS.rglob("test_*.py")):
        parts = f.relative_to(TESTS).parts
        if len(parts) == 1 or parts[0] not in allowed:
            bad.append(str(f.relative_to(REPO)))
        elif len(parts) > 2 and not (PKG / parts[0] / parts[1] / "__init__.py").is_file():
            bad.append(str(f.relative_to(REPO)))  # a sub-folder must mirror a sub-package
    assert bad == []


def test_test_file_basenames_are_unique():
    names = Counter(f.name for f in TESTS.rglob("test_*.py"))
    assert sorted(n for n, k in names.items() if k > 1) == []


def test_no_init_py_under_tests():
    assert sorted(str(f.relative_to(REPO)) for f in TESTS.rglob("__init__.py")) == []
