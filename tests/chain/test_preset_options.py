"""Preset-name options: an explicit argument beats the name's option, a repeated option is refused, and
``chainid chains NAME:grade=G --grade H`` lists grade H with a note (the explicit option wins).

References are the literal numbers of the request (n = 8 asked for explicitly, n = 32 written in the name, 16 the
documented default) and the grades' proof loads typed from DNV-OS-E302 / the data file's sources
(minimum breaking load in kN, d in mm: R3 0.0223 d²(44 − 0.08 d), R5 0.0320 d²(44 − 0.08 d)).
"""
from __future__ import annotations

import json

import pytest

from chainid.chain import presets
from chainid.chain.spec import ChainSpec
from chainid.cli import main


@pytest.mark.parametrize("name, n, expected", [
    ("din22252:14x50:n=32", 8, 8),      # explicit n beats the name's :n=
    ("din22252:14x50:n=32", None, 32),  # the name's :n= beats the default
    ("din22252:14x50", None, 16),       # the default
    ("studless:76:N=40", 12, 12),       # option keys in any case
])
def test_explicit_n_beats_the_name_option(name, n, expected):
    assert presets.resolve(name, n=n).chain.n == expected
    assert ChainSpec.preset(name, n=n).n == expected
    assert presets.chain(name, n=n).n == expected


@pytest.mark.parametrize("name, key, first, second", [
    ("studless:76:n=32:n=64", "n", "32", "64"),
    ("studless:76:grade=R3:grade=R5", "grade", "R3", "R5"),
    ("din22252:14x50:E=200000:e=210000", "E", "200000", "210000"),
    ("studlink:76:nu=0.3:NU=0.29", "nu", "0.3", "0.29"),
])
def test_a_repeated_option_is_refused(name, key, first, second):
    with pytest.raises(ValueError) as e:
        presets.resolve(name)
    msg = str(e.value)
    assert f"option {key!r} is given twice" in msg and f"{key}={first}" in msg and f"{key}={second}" in msg
    with pytest.raises(ValueError, match="given twice"):
        ChainSpec.preset(name)


def test_chains_cli_refuses_a_repeated_option_in_one_line(capsys):
    assert main(["chains", "studless:76:n=32:n=64"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("chainid chains: error: preset 'studless:76:n=32:n=64'"), err


def test_chains_grade_option_beats_the_name_grade_with_a_note(capsys):
    assert main(["chains", "studless:76:grade=R3", "--grade", "R5", "--json", "-"]) == 0
    cap = capsys.readouterr()
    doc = json.loads(cap.out)
    row = doc["presets"][0]
    d = 76.0
    mbl_r5_N = 0.0320 * d * d * (44 - 0.08 * d) * 1e3  # R5 minimum breaking load [kN -> N]
    assert row["grade"] == "R5"
    assert row["breaking_load_N"] == pytest.approx(mbl_r5_N, rel=1e-9)
    assert doc["notes"] == ["--grade R5 replaces the grade R3 written in 'studless:76:grade=R3': studless:76 is "
                            "listed as grade R5"]
    assert cap.err.strip() == "chainid chains: note: " + doc["notes"][0]


def test_chains_same_grade_twice_ways_gives_no_note(capsys):
    assert main(["chains", "studless:76:grade=r4", "--grade", "R4", "--json", "-"]) == 0
    cap = capsys.readouterr()
    assert "notes" not in json.loads(cap.out) and cap.err == ""
