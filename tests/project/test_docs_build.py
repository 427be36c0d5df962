"""The documentation site (mkdocs.yml, docs/): every page of the nav exists, every page is in the nav, every package
has an API page, every included snippet exists, and ``mkdocs build --strict`` succeeds (a broken link, a missing
page or a missing API page fails it)."""
from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

REPO = Path(__file__).resolve().parents[2]
DOCS = REPO / "docs"
NOTEBOOKS = REPO / "notebooks"


class _Loader(yaml.SafeLoader):
    """mkdocs.yml with MkDocs' own tags (``!relative``) read as plain text."""


_Loader.add_multi_constructor("!", lambda loader, suffix, node: loader.construct_scalar(node))


def _config() -> dict:
    return yaml.load((REPO / "mkdocs.yml").read_text(encoding="utf-8"), Loader=_Loader)


def _nav_pages(node) -> list[str]:
    """Every page path of a nav (nested lists of ``{title: path or list}``), in order."""
    if isinstance(node, str):
        return [node]
    if isinstance(node, list):
        return [p for item in node for p in _nav_pages(item)]
    if isinstance(node, dict):
        return [p for v in node.values() for p in _nav_pages(v)]
    raise AssertionError(f"unexpected nav entry {node!r}")


def _generated(page: str) -> bool:
    """A page the build hook writes: ``notebooks/<name>.md`` from ``notebooks/<name>.py``."""
    m = re.fullmatch(r"notebooks/([\w-]+)\.md", page)
    return bool(m) and (NOTEBOOKS / f"{m.group(1)}.py").is_file()


def test_every_nav_page_exists_and_every_docs_page_is_in_the_nav():
    nav = _nav_pages(_config()["nav"])
    assert len(nav) == len(set(nav)), "a page is listed twice"
    missing = [p for p in nav if not (DOCS / p).is_file() and not _generated(p)]
    assert missing == []
    on_disk = {p.relative_to(DOCS).as_posix() for p in DOCS.rglob("*.md")}
    assert sorted(on_disk - set(nav)) == []
    # every notebook is a page, and the hook writes no page that a docs/ file already is
    assert {f"notebooks/{p.stem}.md" for p in NOTEBOOKS.glob("*.py")} <= set(nav)
    assert not (DOCS / "notebooks").exists()


def test_every_package_has_an_api_page_in_the_nav():
    """A package of chainid/ without an API page (a ``::: chainid.x`` directive on a page of the nav) fails; so does
    a directive naming a package that does not exist."""
    nav = set(_nav_pages(_config()["nav"]))
    directives: dict[str, str] = {}
    for page in sorted(DOCS.glob("api/*.md")):
        assert page.relative_to(DOCS).as_posix() in nav, page.name
        for mod in re.findall(r"^::: ([\w.]+)$", page.read_text(encoding="utf-8"), flags=re.M):
            directives[mod] = page.name
    packages = {".".join(p.parent.relative_to(REPO).parts) for p in (REPO / "chainid").rglob("__init__.py")}
    assert sorted(packages - set(directives)) == []
    assert "derive" in directives  # the derivation, installed as chainid.derive
    for mod in directives:
        path = REPO.joinpath(*mod.split("."))
        assert (path / "__init__.py").is_file() or path.with_suffix(".py").is_file(), mod


def test_every_included_snippet_exists_with_its_section():
    """``--8<-- "file"``, ``"file:N"`` (from line N) and ``"file:section"`` (between the file's ``[start:section]``
    and ``[end:section]`` markers) name what exists, so the numbers of benchmarks/RESULTS*.md reach the pages."""
    found = 0
    for page in DOCS.rglob("*.md"):
        for target in re.findall(r'^--8<-- "([^"]+)"$', page.read_text(encoding="utf-8"), flags=re.M):
            name, _, part = target.partition(":")
            src = REPO / name
            assert src.is_file(), (page.name, target)
            text = src.read_text(encoding="utf-8")
            if part and not part.isdigit():
                assert f"--8<-- [start:{part}]" in text and f"--8<-- [end:{part}]" in text, (page.name, target)
            elif part:
                assert int(part) <= len(text.splitlines()), (page.name, target)
            found += 1
    assert found >= 10  # the RESULTS files, the contracts of pyproject.toml


@pytest.mark.slow
def test_the_site_builds_strictly(tmp_path):
    """``mkdocs build --strict`` from another folder succeeds, and the built site holds the API reference, the
    notebooks and the benchmark numbers included from benchmarks/RESULTS_gap.md."""
    site = tmp_path / "site"
    proc = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "-f", str(REPO / "mkdocs.yml"),
                           "-d", str(site)], cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr[-4000:]
    assert "AugmentedModel" in (site / "api" / "model" / "index.html").read_text(encoding="utf-8")
    assert (site / "notebooks" / "01_derivation" / "index.html").is_file()
    gap = (REPO / "benchmarks" / "RESULTS_gap.md").read_text(encoding="utf-8")
    pooled = re.search(r"\| \*\*pooled\*\* \| \*\*([\d.]+ %)\*\*", gap).group(1)
    assert pooled in (site / "guide" / "diagnosis-any-excitation" / "index.html").read_text(encoding="utf-8")


def test_the_benchmark_results_state_the_grid_the_command_runs():
    """benchmarks/RESULTS_gap.md (included by the diagnosis pages) states the case counts of today's
    ``chainid benchmark-gap``: the full grid and its excitations, and the grid moved onto a chain (``--chain``),
    counted here from the case list itself."""
    from collections import Counter

    from chainid.chain.spec import load_chain
    from chainid.gap.benchmark.grid import grid

    text = " ".join((REPO / "benchmarks" / "RESULTS_gap.md").read_text(encoding="utf-8").split())
    n = Counter(c["excitation"] for c in grid(seed=0))
    stated = re.search(r"runs (\d+) cases \((\d+) harmonic, (\d+) non-harmonic, (\d+) transfer\)", text)
    assert stated is not None
    assert tuple(map(int, stated.groups())) == (sum(n.values()), n["harmonic"],
                                                sum(n.values()) - n["harmonic"] - n["transfer"], n["transfer"])
    assert f"Checked on withheld effects** (`chainid benchmark-gap`, timed by `python benchmarks/gap_bench.py`): " \
           f"{n['harmonic']} simulated cases" in text
    on_chain = len(grid(seed=0, chain=load_chain("studless:76:grade=R4")))
    assert f"keeps one of its two chain slots ({on_chain} cases;" in text
