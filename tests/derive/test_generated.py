"""generated/ is fresh, reproducible, and the runtime never imports SymPy."""
from __future__ import annotations

import subprocess
import sys

import pytest

from chainid.derive import emit

pytestmark = pytest.mark.slow  # the SymPy emission (~3 s) and subprocesses


_EXPECTED: dict[str, dict[str, str]] = {}
_EMIT_EXPECTED_FILES = emit.expected_files


def _expected_files_once() -> dict[str, str]:
    """emit.expected_files() computed once per session (the SymPy emission takes ~3 s)."""
    if "files" not in _EXPECTED:
        _EXPECTED["files"] = _EMIT_EXPECTED_FILES()
    return dict(_EXPECTED["files"])


def test_generated_is_fresh(repo, monkeypatch):
    monkeypatch.setattr(emit, "expected_files", _expected_files_once)
    res = emit.generate(repo / "generated", check=True)
    assert res and all(s == "unchanged" for s in res.values()), res


def test_generation_is_byte_for_byte_reproducible(tmp_path):
    a = emit.generate(tmp_path / "a")
    b = emit.generate(tmp_path / "b")
    assert set(a) == set(b)
    for f in a:
        assert (tmp_path / "a" / f).read_bytes() == (tmp_path / "b" / f).read_bytes()


def test_generated_headers(repo):
    for p in sorted((repo / "generated").glob("stiffness_*.py")):
        head = p.read_text(encoding="utf-8").splitlines()[:6]
        assert head[0] == "# GENERATED FILE - DO NOT EDIT."
        assert any(line.startswith("# derivation source hash: ") for line in head)
        assert f"# generator: SymPy {emit.REQUIRED_SYMPY}" in head


def test_stale_file_is_detected(tmp_path):
    emit.generate(tmp_path)
    p = tmp_path / "stiffness_paper.py"
    p.write_text(p.read_text() + "# edited by hand\n")
    res = emit.generate(tmp_path, check=True)
    assert res["stiffness_paper.py"] == "stale"


def test_cli_check_exit_codes_on_fresh_and_stale_copy(repo, tmp_path, capsys, monkeypatch):
    """The command itself (not only the emitter): rc 0 on an exact copy of generated/, rc 1 after one byte changes."""
    import shutil

    from chainid import cli

    monkeypatch.setattr(emit, "expected_files", _expected_files_once)

    gen = tmp_path / "generated"
    shutil.copytree(repo / "generated", gen, ignore=shutil.ignore_patterns("__pycache__"))
    assert cli.main(["generate", "--check", "--out", str(gen)]) == 0
    assert "is fresh" in capsys.readouterr().out
    p = gen / "stiffness_paper.py"
    data = bytearray(p.read_bytes())
    i = data.index(b"return ")  # one byte of code: 'r' -> 'R'
    data[i] = ord("R")
    p.write_bytes(bytes(data))
    before = p.read_bytes()
    assert cli.main(["generate", "--check", "--out", str(gen)]) == 1
    err = capsys.readouterr().err
    assert "stale" in err and "stiffness_paper.py" in err
    assert p.read_bytes() == before  # --check never rewrites


def test_cli_check_names_a_sympy_version_mismatch(tmp_path, monkeypatch, capsys):
    from chainid import cli

    monkeypatch.setattr(emit, "REQUIRED_SYMPY", "0.0.1")
    rc = cli.main(["generate", "--check", "--out", str(tmp_path)])
    assert rc == 2
    err = capsys.readouterr().err
    assert "SymPy version mismatch" in err and "0.0.1" in err


def test_import_and_kernel_call_do_not_import_sympy():
    code = (
        "import sys, chainid, numpy as np\n"
        "chainid.force(np.array([1.0, 2.2])); chainid.stiffness(2.2); chainid.displacement(1e4)\n"
        "import chainid.model.base, chainid.cli\n"
        "assert 'sympy' not in sys.modules, 'sympy imported'\n"
        "print('ok')\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "ok"


def test_numba_cache_dir_is_honoured(tmp_path):
    code = "import chainid; chainid.force(2.2)\n"
    env = {**__import__("os").environ, "NUMBA_CACHE_DIR": str(tmp_path)}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300, env=env)
    assert out.returncode == 0, out.stderr
    assert list(tmp_path.rglob("*.nbi")), "no numba cache index written to NUMBA_CACHE_DIR"
