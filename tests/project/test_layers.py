"""The floors of chainid: the import-linter layers contract, no import circles, no private name imported across
modules, rooms small.  A deliberate upward import in a copy of the package must break the contract (the check can
fail)."""
from __future__ import annotations

import ast
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from repo_paths import REPO as ROOT

PKG = ROOT / "chainid"
pytest.importorskip("importlinter")
grimp = pytest.importorskip("grimp")


def _lint(cwd: Path) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(cwd)}
    code = "import sys; from importlinter.cli import lint_imports_command; sys.exit(lint_imports_command())"
    return subprocess.run([sys.executable, "-c", code, "--no-cache"], cwd=cwd, env=env, capture_output=True,
                          text=True, timeout=300)


def test_layers_contract_is_kept():
    res = _lint(ROOT)
    assert res.returncode == 0, res.stdout + res.stderr
    assert "chainid floors KEPT" in res.stdout


def test_an_upward_import_breaks_the_contract(tmp_path):
    """infra (floor 0) importing the cli (floor 7) must fail the contract."""
    shutil.copytree(PKG, tmp_path / "chainid", ignore=shutil.ignore_patterns("__pycache__"))
    shutil.copy(ROOT / "pyproject.toml", tmp_path / "pyproject.toml")
    f = tmp_path / "chainid" / "infra" / "fileio.py"
    f.write_text(f.read_text() + "\n\ndef _upward():\n    from chainid.cli import parser  # noqa: F401\n")
    res = _lint(tmp_path)
    assert res.returncode == 1, res.stdout + res.stderr
    assert "chainid floors BROKEN" in res.stdout
    assert "chainid.infra.fileio -> chainid.cli.parser" in res.stdout


def _graph() -> dict[str, set[str]]:
    sys.path.insert(0, str(ROOT))
    try:
        g = grimp.build_graph("chainid", cache_dir=None)
    finally:
        sys.path.remove(str(ROOT))
    return {m: {x for x in g.find_modules_directly_imported_by(m)} for m in g.modules}


def _cycles(adj: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan, iterative)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out: list[list[str]] = []
    counter = 0
    for root in sorted(adj):
        if root in index:
            continue
        work = [(root, iter(sorted(adj[root])))]
        index[root] = low[root] = counter
        counter += 1
        stack.append(root)
        on.add(root)
        while work:
            v, it = work[-1]
            w = next(it, None)
            if w is not None:
                if w not in adj:
                    continue
                if w not in index:
                    index[w] = low[w] = counter
                    counter += 1
                    stack.append(w)
                    on.add(w)
                    work.append((w, iter(sorted(adj[w]))))
                elif w in on:
                    low[v] = min(low[v], index[w])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
            if low[v] == index[v]:
                comp = []
                while True:
                    w = stack.pop()
                    on.discard(w)
                    comp.append(w)
                    if w == v:
                        break
                if len(comp) > 1:
                    out.append(sorted(comp))
    return out


def test_cycle_finder_finds_a_cycle():
    assert _cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert _cycles({"a": {"b"}, "b": set()}) == []


def test_no_import_circles():
    adj = _graph()
    # a package importing its own submodules (its lazy public API) is not a circle between modules
    adj = {m: {x for x in deps if not x.startswith(m + ".")} for m, deps in adj.items()}
    assert _cycles(adj) == []


def test_no_private_name_imported_across_modules():
    bad = []
    for f in PKG.rglob("*.py"):
        for node in ast.walk(ast.parse(f.read_text())):
            if isinstance(node, ast.ImportFrom) and (node.level or (node.module or "").startswith("chainid")):
                bad += [f"{f.relative_to(ROOT)}: {a.name}" for a in node.names
                        if a.name.startswith("_") and not a.name.startswith("__")]
    assert bad == []


@pytest.mark.slow
def test_tests_import_their_helpers_by_module_name():
    """The README's test command is a bare ``pytest -q``, which puts ``tests/`` (not the checkout) on sys.path:
    a test that imports ``tests.x`` passes under ``python -m pytest`` and fails in CI (it did, twice)."""
    bad = []
    for f in (ROOT / "tests").rglob("*.py"):
        for node in ast.walk(ast.parse(f.read_text())):
            mods = ([node.module or ""] if isinstance(node, ast.ImportFrom) and not node.level else
                    [a.name for a in node.names] if isinstance(node, ast.Import) else [])
            bad += [f"{f.relative_to(ROOT)}: {m}" for m in mods if m == "tests" or m.startswith("tests.")]
    assert bad == []


def test_rooms_small():
    big = [f"{f.relative_to(ROOT)}: {n}" for f in PKG.rglob("*.py")
           if (n := len(f.read_text().splitlines())) > 500]
    assert big == []


def test_every_package_says_what_it_is_for_and_lists_its_api():
    for d in sorted(p for p in PKG.iterdir() if (p / "__init__.py").is_file()):
        mod = ast.parse((d / "__init__.py").read_text())
        assert ast.get_docstring(mod), d.name
        names = {t.id for n in mod.body if isinstance(n, (ast.Assign, ast.AnnAssign))
                 for t in (n.targets if isinstance(n, ast.Assign) else [n.target]) if isinstance(t, ast.Name)}
        assert "__all__" in names, d.name


def test_no_public_name_shadows_a_submodule():
    """``from chainid.damping import audit`` must give the module, not a function of the same name."""
    for d in sorted(p for p in PKG.iterdir() if (p / "__init__.py").is_file()):
        mods = {f.stem for f in d.glob("*.py")} | {p.name for p in d.iterdir() if (p / "__init__.py").is_file()}
        mod = ast.parse((d / "__init__.py").read_text())
        lazy = next((ast.literal_eval(n.value) for n in mod.body if isinstance(n, ast.Assign)
                     and any(getattr(t, "id", "") == "_LAZY" for t in n.targets)), {})
        assert not set(lazy) & mods, (d.name, set(lazy) & mods)
