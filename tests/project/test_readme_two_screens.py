"""The README fits two screens and stays true: at most 150 lines, the two set-up commands (the test command is the
one CI runs), a tour whose commands the CLI accepts, headline numbers that are the documentation's, links that
resolve."""
from __future__ import annotations

import re
import shlex
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
README = (REPO / "README.md").read_text(encoding="utf-8")


def _section(title: str) -> str:
    start = README.index(f"\n## {title}")
    end = README.find("\n## ", start + 1)
    return README[start:end if end > 0 else None]


def test_the_readme_is_at_most_150_lines():
    assert len(README.splitlines()) <= 150


def test_the_readme_gives_the_main_job_and_the_ci_test_command():
    """The two set-up commands; the test command is character for character the one `.ci/run` runs."""
    setup = _section("Set-up: two commands")
    commands = [ln.split("#")[0].strip() for ln in re.search(r"```bash\n(.*?)```", setup, re.S).group(1).splitlines()]
    assert commands == ['pip install . && chainid report', 'pip install ".[test]" && pytest -q']
    ci = (REPO / ".ci" / "run").read_text(encoding="utf-8").splitlines()
    assert commands[1] in [ln.strip() for ln in ci]


def test_every_command_of_the_tour_is_accepted_by_the_cli():
    """Ten commands, each parsed by chainid's own parser (an unknown option or command exits 2)."""
    from chainid.cli.parser import build_parser

    block = re.search(r"```bash\n(.*?)```", _section("A tour in ten commands"), re.S).group(1)
    lines = [ln.split("  #")[0].strip() for ln in block.splitlines()]
    assert len(lines) == 10 and all(ln.startswith("chainid ") for ln in lines)
    parser = build_parser()
    for ln in lines:
        args = parser.parse_args(shlex.split(ln)[1:])
        assert callable(getattr(args, "func", None)), ln


def test_the_headline_numbers_are_the_documentations():
    """Every number the three headline results quote appears in the documentation (docs/ or the benchmarks' results
    files), so a refreshed number that the README still quotes the old way fails here."""
    results = _section("Three results, each with its command")
    prose = re.sub(r"```.*?```", "", results, flags=re.S)
    prose = re.sub(r"`[^`]*`", "", prose)  # commands and file names
    numbers = set(re.findall(r"(?<![\w.])\d+(?:\.\d+)?(?: %)?(?![\w.])", prose))
    corpus = "\n".join(p.read_text(encoding="utf-8") for p in
                       [*(REPO / "docs").rglob("*.md"), *(REPO / "benchmarks").glob("RESULTS*.md")])
    assert len(numbers) >= 25
    assert sorted(n for n in numbers if n not in corpus) == []


def test_the_readme_links_resolve():
    links = re.findall(r"\]\(([^)#]+)(?:#[^)]*)?\)", README)
    assert len(links) >= 10
    assert [ln for ln in links if not ln.startswith("http") and not (REPO / ln).is_file()] == []
