"""The notebooks (jupytext percent format) run top to bottom."""
from __future__ import annotations


import pytest
from repo_paths import REPO

pytestmark = pytest.mark.slow  # each notebook runs in its own kernel (5-45 s)

NOTEBOOKS = sorted((REPO / "notebooks").glob("*.py"))


@pytest.mark.parametrize("path", NOTEBOOKS, ids=[p.stem for p in NOTEBOOKS])
def test_notebook_executes_and_removes_its_scratch_folders(path, tmp_path, monkeypatch):
    monkeypatch.setenv("CHAINID_REPO", str(REPO))  # the kernel inherits it: notebooks that read examples/ find them
    scratch = tmp_path / "tmp"
    scratch.mkdir()
    monkeypatch.setenv("TMPDIR", str(scratch))  # the kernel's tempfile.mkdtemp() lands here
    jupytext = pytest.importorskip("jupytext")
    nbclient = pytest.importorskip("nbclient")
    nb = jupytext.read(path)
    client = nbclient.NotebookClient(nb, timeout=600, kernel_name="python3",
                                     resources={"metadata": {"path": str(tmp_path)}})
    client.execute()
    errors = [o for c in nb.cells if c.cell_type == "code" for o in c.get("outputs", []) if o.output_type == "error"]
    assert not errors
    assert sorted(p.name for p in scratch.glob("chainid_nb*")) == []


def test_there_are_notebooks():
    assert len(NOTEBOOKS) >= 2
