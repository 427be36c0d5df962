"""``chainid benchmark-gap``: --chain and --excitations choose the sim generator's cases, so they are accepted with
``--generator sim`` (and the default) and refused with ``--generator ode``, before any case runs."""
from __future__ import annotations

import argparse

import pytest

from chainid.cli.gap import _check_generator


def _args(generator: str, chain=None, excitations=None) -> argparse.Namespace:
    return argparse.Namespace(generator="".join(generator), chain=chain, excitations=excitations, seed=0)


@pytest.mark.parametrize("chain, excitations", [("studless:76:grade=R4", None), (None, "harmonic,random")])
def test_chain_and_excitations_are_accepted_with_the_sim_generator(chain, excitations):
    _check_generator(_args("sim", chain, excitations))  # no error
    _check_generator(_args("both", chain, excitations))


@pytest.mark.parametrize("chain, excitations", [("studless:76:grade=R4", None), (None, "harmonic")])
def test_chain_and_excitations_are_refused_with_the_ode_generator(chain, excitations):
    with pytest.raises(ValueError, match=r"--chain and --excitations choose the sim generator's cases"):
        _check_generator(_args("ode", chain, excitations))
