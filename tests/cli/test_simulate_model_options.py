"""``simulate --model M.toml`` takes the chain, variant, damping, effects, base and mass from the file: any of
``--chain --variant --law --params --effect --k --x-ref --mass`` given with it is refused by name (it would be
ignored), before anything is written; without them the file runs."""
from __future__ import annotations

import pytest

from chainid.chain.spec import PAPER_CHAIN
from chainid.cli import main
from chainid.model.augmented import AugmentedModel
from chainid.model.base import ChainModel
from chainid.model.modelfile import save_model
from chainid.model.timedamping import Damping


@pytest.fixture()
def model(tmp_path):
    return str(save_model(AugmentedModel(ChainModel(PAPER_CHAIN), [], Damping("viscous", {"c": 2.0})),
                          tmp_path / "m.toml"))


@pytest.mark.parametrize("extra, named", [
    (["--chain", "studless:76"], "--chain"),
    (["--variant", "paper"], "--variant"),  # given, even with the default value
    (["--law", "viscous"], "--law"),
    (["--params", "100"], "--params"),
    (["--effect", "friction:F_c=10"], "--effect"),
    (["--k", "100"], "--k"),
    (["--x-ref", "0.1"], "--x-ref"),
    (["--mass", "3"], "--mass"),
    (["--chain", "studless:76", "--mass", "3"], "--chain, --mass"),
])
def test_an_option_the_file_overrides_is_refused(model, tmp_path, capsys, extra, named):
    out = tmp_path / "o.csv"
    assert main(["simulate", str(out), "--model", model, *extra]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [f"chainid simulate: error: --model {model!r} is a model file: {named} cannot be given with it (the "
                   "file holds the chain, its kernel variant, the effects, the damping, the base and the mass)"]
    assert not out.exists()


def test_the_file_alone_runs(model, tmp_path, capsys):
    out = tmp_path / "o.csv"
    assert main(["simulate", str(out), "--model", model, "--cycles", "3", "--samples-per-cycle", "32"]) == 0
    assert out.read_text().startswith("test,t,x,F\n")
