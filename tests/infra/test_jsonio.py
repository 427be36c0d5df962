"""JSON conversion (chainid.infra.jsonio) by hand: numpy types, non-finite numbers as null."""
from __future__ import annotations

import json

import pytest


def test_to_jsonable_by_hand():
    import math
    from pathlib import Path

    import numpy as np

    from chainid.infra.jsonio import dumps_json, json_default, to_jsonable

    doc = {1: (np.float64(1.5), np.int32(-3), np.bool_(True)), "a": [math.inf, -math.inf, math.nan, 2.0],
           "p": Path("/x/y.csv"), "arr": np.array([[1, 2], [3, 4]]), "t": True, "n": None, "s": "é", "i": 7}
    out = to_jsonable(doc)
    assert out == {"1": [1.5, -3, True], "a": [None, None, None, 2.0], "p": "/x/y.csv", "arr": [[1, 2], [3, 4]],
                   "t": True, "n": None, "s": "é", "i": 7}
    assert type(out["1"][1]) is int and type(out["1"][2]) is bool and out["t"] is True
    with pytest.raises(TypeError, match="not JSON serialisable: object"):
        to_jsonable(object())
    assert dumps_json({"a": [1, math.nan]}, indent=None) == '{"a": [1, null]}'
    assert dumps_json({"s": "é"}) == '{\n  "s": "é"\n}'  # UTF-8 kept, two-space indent
    assert json.dumps({"v": np.float32(0.5), "k": np.int64(3), "a": np.arange(2)}, default=json_default) == \
        '{"v": 0.5, "k": 3, "a": [0, 1]}'
    with pytest.raises(TypeError, match="not JSON serialisable"):
        json_default(object())
