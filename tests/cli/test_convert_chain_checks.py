"""``chainid convert`` judges the records against a chain only when ``--chain`` names one.

One test written with x in metres by mistake (x = 2.0 ± 0.2 mm written as 0.0020 ± 0.0002, F = 11 ± 1 kN): read as
mm, x spans 0.0004 mm.  With ``--chain studless:76`` that is under 1/1000 of the chain's elongation at its working
load, a unit slip the chain's checks name; without ``--chain`` nothing says what x should be, and no chain check
runs.
"""
from __future__ import annotations

import math

import pytest

from chainid.cli import main


@pytest.fixture()
def metres(tmp_path):
    rows = ["test,t,x,F"]
    for i in range(400):
        t = i * 0.005
        s = math.sin(2 * math.pi * 2 * t)
        rows.append(f"A,{t:.4f},{(2.0 + 0.2 * s) / 1000:.8f},{11000 + 1000 * s:.3f}")
    p = tmp_path / "m.csv"
    p.write_text("\n".join(rows) + "\n")
    return p


def test_a_named_chain_flags_x_in_metres(metres, tmp_path, capsys):
    assert main(["convert", str(metres), "--to", str(tmp_path / "b.csv"), "--chain", "studless:76"]) == 0
    err = capsys.readouterr().err
    assert "x spans 0.0004 mm, under 1/1000 of the chain's elongation" in err
    assert "--units x=m" in err


def test_without_a_chain_no_chain_check_runs(metres, tmp_path, capsys):
    assert main(["convert", str(metres), "--to", str(tmp_path / "a.csv")]) == 0
    err = capsys.readouterr().err
    assert "chain" not in err and "warning" not in err, err
