"""The model a time-domain diagnosis finds is runnable: saved, reloaded, and run by predict, simulate, dynamics.

Independent reference: ``predict`` evaluates a saved model through :meth:`AugmentedModel.force`, a code path
apart from the diagnosis' own time-domain evaluation (:class:`chainid.gap.timedomain.problem.AnyProblem`); on the
same records the two must give the same per-record NRMSE (the diagnosis' held-out number is a prediction,
so reloading the model must reproduce it).
"""

from __future__ import annotations

import json
import tomllib
import warnings

import pytest

from chainid.cli import main
from chainid.gap.benchmark.grid import grid
from chainid.gap.benchmark.nonharmonic import records
from chainid.gap.diagnose import diagnose
from chainid.gap.modelio import predict
from chainid.model.modelfile import load_model
from chainid.records.writer import write_canonical


@pytest.fixture(scope="module")
def sweep_set(tmp_path_factory):
    """Four sweep records of the paper's chain with Coulomb friction (the benchmark's small sweep case)."""
    case = next(k for k in grid(True, 0, ("sweep",)) if k["family"] == "single") | {"chain": "14x50"}
    recs, dev = records(case)
    path = tmp_path_factory.mktemp("sweep") / "sweep.csv"
    write_canonical(path, recs)
    return case, recs, dev, path


@pytest.mark.slow
def test_a_time_domain_diagnosis_carries_its_models(sweep_set) -> None:
    case, recs, dev, _ = sweep_set
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = diagnose(recs, [case["hold"]], dev["nominal"], uncertainty=False, quiet=True)
    assert res["route"] == "time"
    models = res["_models"]
    assert len(models) == len(res["steps"])
    last = res["steps"][-1]
    m = models[-1]
    # four records of distinct band and amplitude: the dashpot follows them, c_r = c + b_w·Δω + b_A·ΔA (the
    # paper's c_e(ω, A) on any excitation)
    assert m.damping.form == "feature"
    assert [m.damping.params[k] for k in ("c", "b_w", "b_A")] == pytest.approx(last["law_params"], rel=1e-12)
    assert [n for n, _ in m.effects] == [s["effect"] for s in res["steps"][1:]]
    assert res["model"]["damping"]["form"] == "feature"
    p = m.damping.params  # with the box of features it was identified on (the law is held there, not extrapolated)
    assert p["w_lo"] <= p["w_ref"] <= p["w_hi"] and p["A_lo"] <= p["A_ref"] <= p["A_hi"]
    assert p["w_lo"] < p["w_hi"] and p["A_lo"] < p["A_hi"]
    # passive at every record (predict refuses a negative dashpot: the next test runs it on all four)


@pytest.mark.slow
def test_predict_reproduces_the_time_diagnosis_numbers(sweep_set) -> None:
    case, recs, dev, _ = sweep_set
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = diagnose(recs, [case["hold"]], dev["nominal"], uncertainty=False, quiet=True)
        out = predict(res["_models"][-1], recs)
    pred = {r["test"]: r for r in out["tests"]}
    assert {r["mode"] for r in out["tests"]} == {"time-domain"}
    assert out["damping_used"] == "feature"
    for t in res["tests"]:
        assert pred[t["test"]]["nrmse_baseline"] == pytest.approx(t["nrmse_before"], rel=1e-9)
        assert pred[t["test"]]["nrmse_model"] == pytest.approx(t["nrmse_after"], rel=1e-9)
    held = pred[case["hold"]]
    assert held["nrmse_model"] == pytest.approx(res["steps"][-1]["nrmse_holdout"], rel=1e-9)


@pytest.mark.slow
def test_cli_saves_a_time_domain_model_that_predict_simulate_and_dynamics_run(sweep_set, tmp_path, capsys) -> None:
    case, _, _, data = sweep_set
    m, d = tmp_path / "m.toml", tmp_path / "d.json"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["diagnose", "--resamples", "0", str(data), "--holdout", case["hold"], "--quiet", "--save-model", str(m),
                     "--save-steps", "--json", str(d)]) == 0
    assert m.is_file() and (tmp_path / "m.step0.toml").is_file()
    doc = tomllib.loads(m.read_text())
    assert doc["damping"]["form"] == "feature" and doc["damping"]["params"]["c"] > 0
    diag = json.loads(d.read_text())
    assert load_model(m).damping.params["c"] == pytest.approx(diag["steps"][-1]["law_params"][0], rel=1e-12)
    p = tmp_path / "p.json"
    assert main(["predict", str(m), str(data), "--json", str(p)]) == 0
    pooled = json.loads(p.read_text())["pooled"]
    assert pooled["shrinkage"] > 0.5  # the friction the diagnosis found closes most of the gap on its own records
    assert main(["simulate", str(tmp_path / "s.csv"), "--model", str(m), "--noise-F", "1", "--seed", "1"]) == 0
    # a segment's damping law over record features runs at a stated operating point (here its reference point)
    law = doc["damping"]["params"]
    assert main(["dynamics", "--links", "40", "--masses", "4", "--pretension", "2000", "--t-end", "0.05",
                 "--segment-model", str(m), "--segment-omega", f"{law['w_ref']:.9g}",
                 "--segment-amplitude", f"{law['A_ref']:.9g}", "--quiet"]) == 0
    capsys.readouterr()
