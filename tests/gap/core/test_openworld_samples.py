"""The model-free check's sample rules (chainid.gap.core.openworld): at least 50 training and 10 held-out rows, and
a regular sub-sample beyond MAX_TRAIN = 10000 training rows."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.gap.core.openworld import MAX_TRAIN, open_world


def _table(n_train: int, n_hold: int, seed: int = 0) -> dict:
    rng = np.random.default_rng(seed)
    return {"X_train": rng.normal(size=(n_train, 2)), "r_train": rng.normal(size=n_train),
            "X_hold": rng.normal(size=(n_hold, 2)), "r_hold": rng.normal(size=n_hold),
            "unit_hold": np.arange(n_hold) % 2, "names": ["x", "xd"]}


@pytest.mark.parametrize("n_train, n_hold, too_few", [(49, 20, True), (50, 9, True), (50, 10, False)])
def test_too_few_samples_is_said_and_not_flagged(n_train, n_hold, too_few):
    ow = open_world(_table(n_train, n_hold), at_floor=False)
    assert (ow["message"] == "too few samples for the model-free check") is too_few
    assert ow["missing_effect"] is False
    if too_few:
        assert ow["predictable_share"] is None and ow["z"] is None and ow["kinds"] == []


def test_training_rows_beyond_the_maximum_are_sub_sampled_regularly():
    """10001 rows: every ceil(10001/10000) = 2nd row, 5001 of them."""
    assert MAX_TRAIN == 10000
    ow = open_world(_table(10001, 40), at_floor=False, keep_model=True)
    assert ow["_X"].shape == (math.ceil(10001 / 2), 2)
    t = _table(10001, 40)
    np.testing.assert_array_equal(ow["_X"], t["X_train"][::2])
