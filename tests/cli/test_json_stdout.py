"""With ``--json -`` the JSON alone is on stdout (the text table goes to stderr), for every command that has
``--json``; stdout is parsed with ``json.loads``.

Two commands are cut short so the file stays fast: ``verify`` runs one of its SymPy checks (Eq. 4, not the
~4 s of all of them) and ``benchmark-gap`` one case of its small grid (serial).  The routing under test (the
command's own printing) is unchanged by that."""
from __future__ import annotations

import json

import pytest

from chainid.cli import main


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("js")
    data = d / "d.csv"
    assert main(["simulate", str(data), "--cycles", "5", "--samples-per-cycle", "48"]) == 0
    model = d / "m.toml"
    assert main(["diagnose", "--resamples", "0", str(data), "--holdout", "3,7", "--max-combo", "1", "--save-model", str(model)]) == 0
    return data, model


def _run(capsys, argv):
    capsys.readouterr()
    rc = main(argv)
    cap = capsys.readouterr()
    return rc, cap.out, cap.err


@pytest.mark.slow
@pytest.mark.parametrize("argv, key", [
    (["identify", "{data}", "--json", "-"], "tests"),
    (["diagnose", "--resamples", "0", "{data}", "--holdout", "3,7", "--max-combo", "1", "--json", "-"], "verdict"),
    (["audit", "--json", "-"], None),
    (["stiffness", "--x", "2.2", "--json", "-"], "points"),
    (["chains", "--json", "-"], "presets"),
    (["predict", "{model}", "{data}", "--json", "-"], "pooled"),
    (["dynamics", "--masses", "8", "--links", "80", "--t-end", "0.01", "--quiet", "--json", "-"], None),
])
def test_json_dash_is_the_only_stdout(files, capsys, argv, key):
    data, model = files
    rc, out, err = _run(capsys, [a.format(data=data, model=model) for a in argv])
    assert rc == 0, err
    doc = json.loads(out)  # nothing but the JSON
    assert isinstance(doc, dict) and doc
    if key:
        assert key in doc
    if argv[0] != "chains":  # (chains writes no text with --json -)
        assert err.strip()  # the human text went to stderr
    assert "wrote -" not in err  # stdout is no file: nothing claims to have written one named '-'


def test_json_dash_verify(monkeypatch, capsys):
    from chainid.derive import verify

    monkeypatch.setattr(verify, "run_checks", lambda progress=None: [verify.check_eq4()])
    rc, out, err = _run(capsys, ["verify", "--json", "-"])
    assert rc == 0
    doc = json.loads(out)
    assert doc["summary"]["agrees"] + doc["summary"]["differs"] == 1
    assert "status" in err and "agree" in err


@pytest.mark.slow
def test_json_dash_benchmark_gap(monkeypatch, capsys):
    from chainid.gap.benchmark import grid as benchmark

    small = benchmark.grid(True, 0)[:1]
    monkeypatch.setattr(benchmark, "grid", lambda small_, seed, *excitations: small)
    rc, out, err = _run(capsys, ["benchmark-gap", "--small", "--scheduler", "serial", "--no-progress",
                                 "--json", "-"])
    assert rc == 0, err
    doc = json.loads(out)
    assert isinstance(doc, dict) and doc
    assert err.strip()
