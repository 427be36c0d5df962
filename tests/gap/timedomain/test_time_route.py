"""The choice of route (the rule in chainid.gap.diagnose's docstring) and the time route's blocks
(chainid.gap.timedomain.route.build_problem)."""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np


def _rec(test, n=200, **cov):  # noqa: ANN001, ANN202
    from chainid.records.record import Record

    t = np.arange(n) / 100.0
    x = 1.0 + 0.5 * np.sin(2 * np.pi * t)
    return Record(test, t, x, 100.0 * x, covariates=cov)


def test_build_problem_routes_harmonic_tests_by_the_documented_rule(monkeypatch):
    """A set of steady harmonic tests at one operating condition takes the harmonic route (the tests' phase-bin
    data, the held-out ids); every other set takes the time route with ALL its usable records, the harmonic tests
    too: a record that is not a harmonic test with >= MIN_SAMPLES = 64 samples, covariates that differ between
    the tests, or --holdout-blocks K > 0.  A non-harmonic record too short for the time route stays excluded.
    The result names the route ("time" or "harmonic", never "mixed").  ``build_problem`` cuts every record in
    LOO_BLOCKS = 4 blocks (or K)."""
    import importlib

    import chainid.gap.timedomain.route as dt

    dg = importlib.import_module("chainid.gap.diagnose")  # the module (the package re-exports the function)

    calls = []

    def prepare(records, n_bins, allow, steady_tol, strict):  # noqa: ANN001, ANN202
        # stand-in for the phase-bin preparation: tests named h* are steady harmonic tests, the others are not
        data = [SimpleNamespace(test=r.test) for r in records if r.test.startswith("h")]
        return data, [{"test": r.test, "reason": "not a harmonic test"} for r in records if not r.test.startswith("h")]

    def harmonic(data, hold, model, **k):  # noqa: ANN001, ANN202
        calls.append(("harmonic", [d.test for d in data], list(hold), [e["test"] for e in k["excluded"]]))
        return {"route": "harmonic"}

    def any_(records, hold, model, holdout_blocks=0, **k):  # noqa: ANN001, ANN202
        calls.append(("time", [r.test for r in records], list(hold), holdout_blocks))
        return {"route": "time"}

    monkeypatch.setattr(dg, "_prepare", prepare)
    monkeypatch.setattr(dg, "diagnose_harmonic", harmonic)
    monkeypatch.setattr(dt, "diagnose_any", any_)
    monkeypatch.setattr(dg, "attach_models", lambda res, ev: [])
    harm = [_rec(f"h{i}") for i in range(1, 5)]

    def run(recs, hold, blocks=0):  # noqa: ANN001, ANN202
        calls.clear()
        res = dg.diagnose(recs, hold, None, quiet=True, holdout_blocks=blocks)
        (call,) = calls
        assert res["route"] == call[0]
        return call

    assert run(harm, ["h4"]) == ("harmonic", ["h1", "h2", "h3", "h4"], ["h4"], [])
    # one random record (200 >= 64 samples): every record sample by sample, the harmonic tests too
    assert run(harm + [_rec("r1")], ["h4"]) == ("time", ["h1", "h2", "h3", "h4", "r1"], ["h4"], 0)
    # a non-harmonic record of 63 < 64 samples: excluded, the harmonic tests keep their route
    assert run(harm + [_rec("s1", n=63)], ["h4"]) == ("harmonic", ["h1", "h2", "h3", "h4"], ["h4"], ["s1"])
    assert run(harm, [], blocks=3) == ("time", ["h1", "h2", "h3", "h4"], [], 3)
    # operating conditions: one value for all tests is one condition; two values go the time route
    same = [_rec(f"h{i}", p_bar=2.0) for i in range(1, 5)]
    assert run(same, ["h4"])[0] == "harmonic"
    differ = [_rec(f"h{i}", p_bar=1.0 + (i > 2)) for i in range(1, 5)]
    assert run(differ, ["h4"]) == ("time", ["h1", "h2", "h3", "h4"], ["h4"], 0)

    made = []
    monkeypatch.setattr(dt, "prepare_time", lambda r, nb, cap=None: SimpleNamespace(test=r.test, nb=nb, cap=cap))
    monkeypatch.setattr(dt, "TimeProblem", lambda tdata, model, hold, blocks, mass_kg=None, damping_law="auto":
                        made.append(([(d.test, d.nb) for d in tdata], model, hold, blocks, mass_kg, [d.cap for d in
                                                                                                     tdata]))
                        or made[-1][:5])
    assert dt.LOO_BLOCKS == 4
    assert dt.build_problem(harm + [_rec("r1")], ["h4"], 0, "M", 2.0) == (
        [("h1", 4), ("h2", 4), ("h3", 4), ("h4", 4), ("r1", 4)], "M", ["h4"], 0, 2.0)
    assert dt.build_problem(harm, [], 3, None)[0] == [("h1", 3), ("h2", 3), ("h3", 3), ("h4", 3)]
    dt.build_problem(harm, [], 3, None, sigma_caps={"h2": 4.0})  # a record's noise cap reaches its preparation only
    assert made[-1][5] == [None, 4.0, None, None]
