"""A friction force that follows an operating condition: F_c = F0 + F1·i over 5 records at coil currents
i = 0 … 1 A (:func:`recovery_cases.covariate_friction_records`: the linear device + (1 + 2·i)·sgn(ẋ) on the true
velocity).  The chain names ``friction`` following the covariate (the step ``friction@i``: its amplitude F_c with
a slope over i, or ``friction`` then the slope term ``friction.F_c@i``); F0 and F1 come back within
10 %, with the covariate given on the records (``Record.covariates``) and read by ``chainid diagnose`` from the
test ids (``--covariate 'i=_i([0-9.]+)$'``).
"""
from __future__ import annotations

import json

import pytest

import recovery_cases as rc

pytestmark = pytest.mark.slow


def _F0_F1(params: dict) -> tuple[float, float]:
    """F0 (at i = 0) and F1 [N, N/A] from the fitted F_c at the reference current and its slope."""
    slope = params["friction.F_c@i"]
    return params["friction.F_c"] - slope * params["covariate.i.ref"], slope


def _check(res: dict) -> None:
    assert res["verdict"] == "friction", res["chain_text"]
    steps = [s["effect"] for s in res["steps"]]
    assert "friction@i" in steps or "friction.F_c@i" in steps, res["chain_text"]
    F0, F1 = _F0_F1(rc.final_params(res))
    assert rc.rel_err(F0, rc.COV_F0) <= 0.10, (F0, F1)
    assert rc.rel_err(F1, rc.COV_F1) <= 0.10, (F0, F1)


def test_friction_following_a_covariate_on_records():
    res = rc.diagnosed("covariate", rc.covariate_set)[0]
    assert res["base"]["covariates"] == ["i"]
    _check(res)


def _write_csv(path, recs) -> None:
    """The canonical records file test,t,x,F (s, mm, N), written here by hand."""
    with open(path, "w", encoding="utf-8") as fh:
        fh.write("test,t,x,F\n")
        for r in recs:
            for row in zip(r.t, r.x, r.F):
                fh.write(f"{r.test},{float(row[0])!r},{float(row[1])!r},{float(row[2])!r}\n")


def test_friction_following_a_covariate_read_from_test_ids(tmp_path, capsys):
    from chainid.cli import main

    recs = rc.covariate_friction_records(ids=lambda k, i: f"run_i{i:g}")  # the records of the test above
    data = tmp_path / "runs.csv"
    _write_csv(data, recs)
    out = tmp_path / "dg.json"
    code = main(["diagnose", str(data), "--model", "linear", "--holdout", "run_i0.5", "--covariate",
                 "i=_i([0-9.]+)$", "--resamples", "0", "--json", str(out), "--quiet"])
    err = capsys.readouterr().err
    assert code == 0, err
    doc = json.loads(out.read_text())
    assert {t["test"]: t["covariates"] for t in doc["tests"]} == {f"run_i{i:g}": {"i": i} for i in rc.COV_I}
    _check(doc)
    # the same samples as Record objects with covariates: the same diagnosis
    api = rc.final_params(rc.diagnosed("covariate", rc.covariate_set)[0])
    got = rc.final_params(doc)
    for k in ("friction.F_c", "friction.F_c@i", "damping.c", "covariate.i.ref"):
        assert got[k] == pytest.approx(api[k], rel=1e-9, abs=1e-12), k


def test_friction_following_a_covariate_on_a_second_noise_realisation():
    res = rc.diagnosed("covariate_seed1", lambda: (rc.covariate_friction_records(seed=1), ["r2"], None))[0]
    _check(res)
