"""Plausibility warnings are one line per check, not one per test (a file with a unit slip in every test).

The reference: the chain's breaking-load elongation of the paper's chain is a few mm, so x written in µm and read
as mm spans ~1000x it in every test; the check must fire once, naming the first test and the others.
"""
from __future__ import annotations

import numpy as np

from chainid.chain.spec import default_chain
from chainid.records.plausible import grouped, plausibility_warnings
from chainid.records.record import Record


def _rec(test: str, scale: float) -> Record:
    t = np.linspace(0.0, 10.0, 2001)
    x = scale * (2.0 + 0.5 * np.sin(2 * np.pi * t))
    return Record(test, t, x, 2.0e4 + 5.0e3 * np.sin(2 * np.pi * t))


def test_one_slip_in_every_test_is_one_line_naming_all_tests():
    recs = [_rec(f"t{i}", 1000.0) for i in range(5)]  # x in um read as mm
    msgs = [m for m in plausibility_warnings(recs, default_chain()) if "x spans" in m]
    assert len(msgs) == 1
    assert msgs[0].startswith("test 't0': x spans")
    assert "[the same check on 4 more test(s): 't1', 't2', 't3', 't4']" in msgs[0]


def test_different_checks_and_unslipped_tests_stay_apart():
    msgs = grouped(["test 'a': x spans 1.2e+03 mm, 3x", "test 'b': F reaches 9e+09 N", "test 'c': x spans 17 mm, 4.1x",
                    "no tag 1", "no tag 2"])
    assert msgs == ["test 'a': x spans 1.2e+03 mm, 3x [the same check on 1 more test(s): 'c']",
                    "test 'b': F reaches 9e+09 N", "no tag 1", "no tag 2"]  # untagged: never merged
