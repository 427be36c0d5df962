"""``chainid generate``: one line per generated file with its status; --check exits 0 on fresh files and names the
SymPy of a stale one."""
from __future__ import annotations

import pytest

from chainid.cli import main


@pytest.mark.parametrize("stamp, note", [("1.11.1", True), (None, False), ("same", False)])
def test_generate_check_names_the_sympy_of_a_stale_file(tmp_path, capsys, monkeypatch, stamp, note):
    """``generate --check`` on a stale file names the SymPy that wrote it (the last word of its
    ``# generator: SymPy X`` header line) when that is not the SymPy this generator needs. The emitter is
    stubbed: the CLI's own reading of the header is under test."""
    from chainid.derive import emit

    stamp = emit.REQUIRED_SYMPY if stamp == "same" else stamp
    out = tmp_path / "gen"
    out.mkdir()
    head = ["# GENERATED FILE - DO NOT EDIT.", "# variant: paper"] + ([f"# generator: SymPy {stamp}"] if stamp else [])
    (out / "stiffness_paper.py").write_text("\n".join(head + ["x = 1"]) + "\n")
    monkeypatch.setattr(emit, "generate", lambda o, check=False: {"stiffness_paper.py": "stale", "b.py": "unchanged"})
    assert main(["generate", "--check", "--out", str(out)]) == 1
    err = capsys.readouterr().err.strip()
    assert err.startswith("generated/ is stale: stiffness_paper.py")
    extra = f" (the file was generated with SymPy {stamp}; this generator needs {emit.REQUIRED_SYMPY})"
    assert (extra in err) is note
    assert err.endswith("; run `chainid generate` and commit")


def test_generate_check_on_fresh_files_exits_0(tmp_path, capsys, monkeypatch):
    """``generate --check`` exits 0 and says "fresh" with the source hash when every generated file is unchanged
    (the documented exit codes: 0 fresh, 1 stale, 2 a SymPy mismatch).  The emitter is stubbed: the CLI's exit code
    is under test."""
    from chainid.derive import emit

    out = tmp_path / "gen"
    out.mkdir()
    monkeypatch.setattr(emit, "generate", lambda o, check=False: {"a.py": "unchanged", "b.py": "unchanged"})
    monkeypatch.setattr(emit, "source_hash", lambda: "abc123")
    assert main(["generate", "--check", "--out", str(out)]) == 0
    cap = capsys.readouterr()
    assert cap.out.strip().splitlines()[-1] == "generated/ is fresh (source hash abc123)" and cap.err == ""


def test_generate_lists_every_file_with_its_status_and_a_stale_check_exits_1(tmp_path, capsys, monkeypatch):
    """``generate`` prints one line per generated file, its status right-aligned in 9 columns then the path; with
    ``--check`` a file that is not unchanged makes generated/ stale: exit 1 and one stderr line naming it (README:
    --check exits 1 when stale).  The emitter is stubbed (the CLI is under test)."""
    from chainid.derive import emit

    out = tmp_path / "gen"
    out.mkdir()
    monkeypatch.setattr(emit, "generate", lambda o, check=False: {"a.py": "unchanged", "b.py": "written"})
    assert main(["generate", "--check", "--out", str(out)]) == 1
    cap = capsys.readouterr()
    assert cap.out.splitlines() == [f"unchanged  {out / 'a.py'}", f"  written  {out / 'b.py'}"]
    assert cap.err == "generated/ is stale: b.py; run `chainid generate` and commit\n"
