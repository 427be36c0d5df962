"""On a large problem the selection fits each round's effect sets on forked workers (``prefetch``); the chain, its
parameters and its scores are exactly those of the fits made one by one in this process."""
from __future__ import annotations

import warnings

import numpy as np
import pytest

import recovery_cases as rc
from chainid.gap.core import selection
from chainid.infra.forkpool import can_fork
from chainid.gap.diagnose import diagnose
from chainid.gap.timedomain import problem as tp


def _run(monkeypatch, parallel: bool) -> tuple[dict, list[int]]:
    calls: list[int] = []
    real = selection.fork_map

    def counting(fn, items, *a, **k):  # noqa: ANN001, ANN202
        calls.append(len(items))
        return real(fn, items, *a, **k)

    monkeypatch.setattr(selection, "fork_map", counting)
    monkeypatch.setattr(tp, "PARALLEL_SAMPLES", 0 if parallel else 10**12)
    recs = rc.linear_random(lambda mo, t: 0.5 * np.sign(mo(t)[1]), n=1500, seed=4)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = diagnose(recs, ["r4"], None, quiet=True, effects=["friction", "hysteresis", "stribeck"],
                       max_combo=2, resamples=0)
    return res, calls


@pytest.mark.skipif(can_fork(2) == 0, reason="no fork start method here")
def test_forked_fits_give_the_chain_and_numbers_of_the_serial_fits(monkeypatch):
    par, calls = _run(monkeypatch, True)
    ser, none = _run(monkeypatch, False)
    assert calls and calls[0] == 3 and not none  # the first round's three sets went to the workers
    assert par["verdict"] == ser["verdict"] == "friction"
    assert [s["effect"] for s in par["steps"]] == [s["effect"] for s in ser["steps"]]
    for a, b in zip(par["steps"], ser["steps"]):
        assert a["params"].keys() == b["params"].keys()
        for k in a["params"]:
            assert a["params"][k] == pytest.approx(b["params"][k], rel=1e-12, abs=1e-15), k
        assert a["nrmse_holdout"] == pytest.approx(b["nrmse_holdout"], rel=1e-12)
    assert par["stop"] == ser["stop"] and par["confounded"] == ser["confounded"]
    assert [r["effect"] for r in par["ranking"]] == [r["effect"] for r in ser["ranking"]]
    for a, b in zip(par["ranking"], ser["ranking"]):
        assert a["nrmse_loto"] == pytest.approx(b["nrmse_loto"], rel=1e-12)
