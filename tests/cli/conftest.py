"""Fixtures shared by the CLI tests."""
from __future__ import annotations

import pytest


@pytest.fixture(scope="session")
def chain_records(tmp_path_factory):
    """The paper's plan simulated on the chain with a viscous c = 300 N·s/mm: 4 cycles of 100 samples per test, no
    ramp, written as a records CSV (s, mm, N); returns its path.  Read only by the tests."""
    from chainid.model.base import ChainModel
    from chainid.model.laws import ViscousLaw
    from chainid.records.files import write_records
    from chainid.records.simulate import paper_plan, simulate

    recs = simulate(paper_plan(), ChainModel(), ViscousLaw([300.0]), n_cycles=4, samples_per_cycle=100,
                    ramp_rate=None)
    return write_records(tmp_path_factory.mktemp("c") / "d.csv", recs)
