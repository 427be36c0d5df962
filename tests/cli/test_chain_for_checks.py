"""The chain that read records are checked against (``chainid.cli.readopts.chain_for_checks``): the built-in chain
for ``--model chain`` (the default), none for any other model (a linear device, a model file), whatever its name
sorts like."""
from __future__ import annotations

import argparse

import pytest

from chainid.chain.spec import default_chain
from chainid.cli.readopts import chain_for_checks


def test_the_default_model_checks_against_the_built_in_chain():
    chain = chain_for_checks(argparse.Namespace(model="chain", chain=None))
    assert chain is not None and chain == default_chain()
    assert chain_for_checks(argparse.Namespace()) == default_chain()  # a command without --model


@pytest.mark.parametrize("model", ["linear", "A.toml", "./m.toml", "/abs/m.json", "chains"])
def test_any_other_model_has_no_chain_to_check_against(model):
    """Seed-29 survivor: ``!= "chain"`` → ``> "chain"`` passed every call (``linear`` sorts after ``chain``); a model
    file whose name sorts before it ('A.toml', './m.toml') was then checked against the default chain."""
    assert chain_for_checks(argparse.Namespace(model=model, chain=None)) is None
