"""Every command's error is one line that names the command: ``chainid COMMAND: error: ...`` (rc 2).

Each command gets a bad input that is refused before any work (a missing input file, an existing output, an
out-of-range option), and an option it does not have (argparse's own message would name only ``chainid``).
Two outputs of one run that are one file are refused before any work, naming both options.
"""
from __future__ import annotations

import os

import pytest

from chainid.cli import main
from chainid.cli.parser import build_parser


def _commands() -> list[str]:
    import argparse

    p = build_parser()
    for a in p._actions:
        if isinstance(a, argparse._SubParsersAction):
            return sorted(a.choices)
    raise AssertionError("no subcommands")


def _bad_inputs(tmp):
    existing = tmp / "exists.json"
    existing.write_text("{}\n")
    a_file = tmp / "a_file"
    a_file.write_text("x\n")
    missing = str(tmp / "missing.csv")
    return {
        "verify": ["verify", "--json", str(existing)],
        "generate": ["generate", "--out", str(a_file)],
        "stiffness": ["stiffness", "--x", "1", "--chain", str(tmp / "missing.toml")],
        "identify": ["identify", missing],
        "simulate": ["simulate", str(existing)],
        "audit": ["audit", "--data", missing],
        "diagnose": ["diagnose", "--resamples", "0", missing, "--holdout", "1"],
        "benchmark-gap": ["benchmark-gap", "--workers", "0"],
        "report": ["report", "--out", str(tmp / "rep"), "--data", missing],
        "chains": ["chains", "din22252:1x1"],
        "dynamics": ["dynamics", "--modes", "0"],
        "predict": ["predict", str(tmp / "missing.toml"), missing],
        "convert": ["convert", missing, "--to", str(tmp / "out.csv")],
    }


def test_the_bad_inputs_cover_every_command(tmp_path):
    assert sorted(_bad_inputs(tmp_path)) == _commands()


@pytest.mark.parametrize("command", _commands())
def test_a_refused_input_is_one_line_naming_the_command(command, tmp_path, capsys):
    argv = _bad_inputs(tmp_path)[command]
    rc = main(argv)
    err = [ln for ln in capsys.readouterr().err.splitlines() if ln.strip()]
    assert rc == 2, err
    assert len(err) == 1 and err[0].startswith(f"chainid {command}: error: "), err
    assert "Traceback" not in err[0]


#: positional arguments of the commands that have them (never opened: the unknown option is refused first)
POSITIONALS = {"identify": ["D"], "simulate": ["O"], "diagnose": ["D"], "predict": ["M", "D"], "convert": ["I", "--to", "O"]}


@pytest.mark.parametrize("command", _commands())
def test_an_unknown_option_names_the_command(command, capsys):
    with pytest.raises(SystemExit) as e:
        main([command, *POSITIONALS.get(command, []), "--no-such-option-here"])
    assert e.value.code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1] == f"chainid {command}: error: unrecognized arguments: --no-such-option-here", err


@pytest.mark.parametrize("argv, one, other", [
    (["diagnose", "--resamples", "0", "D", "--holdout", "1", "--save-model", "X.json", "--json", "X.json"], "--save-model 'X.json'",
     "--json 'X.json'"),
    (["identify", "D", "--json", "S.csv", "--write-side", "S.csv"], "--write-side 'S.csv'", "--json 'S.csv'"),
    (["diagnose", "--resamples", "0", "D", "--holdout", "1", "--save-model", "M.toml", "--save-steps", "--json", "M.step1.toml"],
     "--save-steps 'M.step1.toml'", "--json 'M.step1.toml'"),
])
def test_two_outputs_that_are_one_file_are_refused(argv, one, other, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "D").write_text("test,t,x,F\n")
    rc = main(argv)
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and len(err) == 1, err
    assert err[0].startswith(f"chainid {argv[0]}: error: ")
    assert err[0].endswith("one run cannot write both there; give two different files")
    assert {one, other} <= {err[0].split(": error: ")[1].split(" is the same file as ")[0],
                            err[0].split(" is the same file as ")[1].split(": one run")[0]}
    assert sorted(os.listdir(tmp_path)) == ["D"]  # nothing written


def test_the_same_file_by_another_spelling_is_refused(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "sub").mkdir()
    (tmp_path / "D").write_text("test,t,x,F\n")
    rc = main(["diagnose", "--resamples", "0", "D", "--holdout", "1", "--save-model", "sub/../X.json", "--json", "./X.json"])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and "--save-model 'sub/../X.json' is the same file as --json './X.json'" in err[0], err
