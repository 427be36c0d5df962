"""MkDocs hook: the notebooks (``notebooks/*.py``, jupytext percent format) as pages ``notebooks/<name>.md``.

Each notebook is read with jupytext and written as Markdown: its Markdown cells as they are, its code cells as
Python blocks.  Nothing is executed in the build (the test suite executes every notebook; the pages show the
source a reader runs).  A notebook listed in the nav that does not exist fails the strict build as a missing page.
"""
from __future__ import annotations

from pathlib import Path

import jupytext
from mkdocs.structure.files import File, Files

REPO = Path(__file__).resolve().parents[1]
NOTEBOOKS = REPO / "notebooks"


def notebook_markdown(path: Path) -> str:
    """The Markdown page of one percent-format notebook: its cells in order, code as ``python`` blocks."""
    nb = jupytext.read(path, fmt="py:percent")
    parts = []
    for cell in nb.cells:
        src = cell.source.strip("\n")
        if not src:
            continue
        parts.append(src if cell.cell_type == "markdown" else f"```python\n{src}\n```")
    note = (f'!!! note "Source"\n    `notebooks/{path.name}` (jupytext percent format): open it with Jupyter and '
            f"jupytext, or run it as a script from the repository root. Shown here without its outputs; the test "
            f"suite executes it.")
    head, *rest = parts or [f"# {path.stem}"]
    return "\n\n".join([head, note, *rest]) + "\n"


def on_files(files: Files, config) -> Files:
    for path in sorted(NOTEBOOKS.glob("*.py")):
        files.append(File.generated(config, f"notebooks/{path.stem}.md", content=notebook_markdown(path)))
    return files
