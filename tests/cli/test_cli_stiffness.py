"""``chainid stiffness`` refuses bad chain files and reads inf and negative forces."""
from __future__ import annotations

import math

import pytest

import chainid
from chainid import cli


@pytest.mark.parametrize("toml,needle", [
    ("d = 100\npitch = 250\nwidth = 17\nn = 16\nmass_per_m = 4\n", "ChainSpec.width = 17.0"),
    ("d = 14\npitch = 50\nwidth = 17\nn = 1e20\nmass_per_m = 4\n", "ChainSpec.n = 1e+20"),
    ("d = 14\npitch = 50\nwidth = 17\nn = true\nmass_per_m = 4\n", "ChainSpec.n = True"),
    ("d = 14\npitch = 50\nwidth = 17\nn = 16\nE = 1e300\nmass_per_m = 4\n", "ChainSpec.E = 1e+300"),
])
def test_cli_stiffness_refuses_bad_chain_files(tmp_path, capsys, toml, needle):
    p = tmp_path / "c.toml"
    p.write_text(toml)
    assert cli.main(["stiffness", "--x", "1", "--chain", str(p)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("chainid stiffness: error: " + needle), err


def test_cli_stiffness_inf_and_negative_force(capsys):
    assert cli.main(["stiffness", "--F", "-1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "F = -1.0 N is invalid" in err
    assert cli.main(["stiffness", "--F", "inf"]) == 0
    row = capsys.readouterr().out.strip().splitlines()[-1].split()
    assert row[:2] == ["inf", "inf"] and float(row[2]) == pytest.approx(chainid.stiffness(math.inf), rel=1e-5)
