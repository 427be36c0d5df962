"""``predict``, ``simulate --model`` and ``dynamics --segment-model`` load a model file through the one checked
loader: the same bad key is the same one-line error in all three (rc 2, nothing written), and the same implausible
key is the same warning, on stderr and in the JSON of the commands that write one.
"""
from __future__ import annotations

import json
import os

import pytest

from chainid.chain.spec import PAPER_CHAIN
from chainid.cli import main
from chainid.model.augmented import AugmentedModel
from chainid.model.base import ChainModel
from chainid.model.modelfile import model_to_dict, save_model, to_toml
from chainid.model.timedamping import Damping


def _file(tmp_path, name, **edit):
    d = model_to_dict(AugmentedModel(ChainModel(PAPER_CHAIN), [("friction", {"F_c": 150.0})],
                                     Damping("viscous", {"c": 2.0})))
    d["delay_s"] = edit.pop("delay_s", 0.0)
    for k, v in edit.items():
        d["effects"][0]["params"][k] = v
    p = tmp_path / name
    p.write_text(to_toml(d))
    return str(p)


@pytest.fixture(scope="module")
def records(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("rec")
    good = save_model(AugmentedModel(ChainModel(PAPER_CHAIN), [("friction", {"F_c": 150.0})],
                                     Damping("viscous", {"c": 2.0})), tmp / "good.toml")
    out = tmp / "d.csv"
    assert main(["simulate", str(out), "--model", str(good), "--cycles", "4", "--samples-per-cycle", "64"]) == 0
    return str(out)


def _commands(model, records, out_dir):
    return {
        "predict": ["predict", model, records, "--json", str(out_dir / "p.json")],
        "simulate": ["simulate", str(out_dir / "s.csv"), "--model", model, "--cycles", "4",
                     "--samples-per-cycle", "64"],
        "dynamics": ["dynamics", "--segment-model", model, "--links", "100", "--masses", "10", "--t-end", "0.05",
                     "--json", str(out_dir / "d.json")],
    }


@pytest.mark.parametrize("command", ["predict", "simulate", "dynamics"])
def test_a_bad_key_is_the_same_error_in_every_command(command, tmp_path, records, capsys):
    model = _file(tmp_path, "bad.toml", F_c=-150.0)
    out = tmp_path / "out"
    out.mkdir()
    capsys.readouterr()
    assert main(_commands(model, records, out)[command]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [f"chainid {command}: error: model file {model!r}: effects[0].params.F_c = -150.0 is out of range: "
                   "valid range >= 0 and <= 1e+09 N"]
    assert os.listdir(out) == []


@pytest.mark.parametrize("command", ["predict", "simulate", "dynamics"])
def test_an_implausible_key_is_the_same_warning_in_every_command(command, tmp_path, records, capsys):
    model = _file(tmp_path, "odd.toml", delay_s=2.0)
    out = tmp_path / "out"
    out.mkdir()
    capsys.readouterr()
    assert main(_commands(model, records, out)[command]) == 0
    text = f"model file {model!r}: delay_s = 2.0 s is implausible (plausible: -1 to 1 s); it is used as given"
    err = capsys.readouterr().err.splitlines()
    assert f"chainid {command}: warning: {text}" in err
    js = list(out.glob("*.json"))
    if command != "simulate":  # (simulate writes records, no JSON)
        assert text in json.loads(js[0].read_text())["warnings"]
