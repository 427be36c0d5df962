"""A diagnosis' saved model reproduces it: reloaded, its held-out NRMSE to 1e-9; simulated then predicted, to the
noise level; a delay of 0.3 of the shortest period recovered and signed in `where`."""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

from chainid.cli import main
from chainid.gap.benchmark.grid import grid3x3_plan
from chainid.gap.harmonic.prepare import prepare_test
from chainid.model import ChainModel, PolynomialLaw, parse_effect
from chainid.model.modelfile import load_model
from chainid.records import read_records, write_records
from chainid.records.simulate import simulate, write_plan


MODEL = ChainModel()


LAW = PolynomialLaw([0.5, 1.0, 100.0, 20.0, 50.0])  # N·s/mm, ω rad/s, A mm


HOLD = "3,7,11"


def records(effect: str | None, noise: float = 20.0, model=MODEL):
    return simulate(grid3x3_plan(prefix=""), model, LAW, n_cycles=8, samples_per_cycle=128, noise_F=noise, seed=1,
                    force_fn=parse_effect(effect, model) if effect else None)


@pytest.mark.slow
@pytest.mark.parametrize("effect,base", [("friction:F_c=150", "chain"), ("hysteresis:F_h=200,x_h=0.05", "linear")])
def test_saved_model_reproduces_the_diagnosis_held_out_nrmse(tmp_path, effect, base):
    data = tmp_path / "d.csv"
    write_records(data, records(effect))
    m, r, p = tmp_path / "m.toml", tmp_path / "r.json", tmp_path / "p.json"
    assert main(["diagnose", "--resamples", "0", str(data), "--holdout", HOLD, "--max-combo", "1", "--model", base, "--json", str(r),
                 "--save-model", str(m), "--save-steps"]) == 0
    diag = json.loads(r.read_text())
    assert diag["verdict"] == effect.split(":")[0]
    assert main(["predict", str(m), str(data), "--tests", HOLD, "--json", str(p), "--plots", str(tmp_path / "fig")]) == 0
    assert sorted(f.name for f in (tmp_path / "fig").iterdir()) == [f"predict_{t}.png" for t in sorted(HOLD.split(","))]
    pred = json.loads(p.read_text())
    assert pred["pooled"]["nrmse_model"] == pytest.approx(diag["steps"][-1]["nrmse_holdout"], rel=1e-9)
    assert pred["pooled"]["nrmse_baseline"] == pytest.approx(diag["baseline"]["nrmse_holdout"], rel=1e-9)
    assert {t["test"] for t in pred["tests"]} == set(HOLD.split(","))
    assert set(pred["tests"][0]) >= {"test", "nrmse_baseline", "nrmse_model", "shrinkage"}
    # the step files: step 0 is the baseline, the last step is the saved model
    s0, s1 = load_model(tmp_path / "m.step0.toml"), load_model(tmp_path / "m.step1.toml")
    assert s0.effects == [] and [n for n, _ in s1.effects] == [effect.split(":")[0]]
    # the diagnosis JSON carries every fitted parameter of the base
    step = diag["steps"][-1]
    assert len(step["law_params"]) >= 1 and step["base"]["model"] == base and step["mass_kg"] >= 0
    if base == "linear":
        assert step["base"]["k"] > 0 and math.isfinite(step["base"]["x_ref"])
    assert diag["model"]["effects"][0]["name"] == effect.split(":")[0]


@pytest.mark.slow
def test_simulate_model_then_predict_round_trips_to_the_noise_level(tmp_path):
    data, plan = tmp_path / "d.csv", tmp_path / "plan.csv"
    write_records(data, records("friction:F_c=150"))
    write_plan(plan, grid3x3_plan(prefix=""))
    m = tmp_path / "m.toml"
    assert main(["diagnose", "--resamples", "0", str(data), "--holdout", HOLD, "--max-combo", "1", "--save-model", str(m)]) == 0
    sigma = 20.0
    out = {}
    for noise in (sigma, 0.0):
        sim, p = tmp_path / f"s{noise}.csv", tmp_path / f"p{noise}.json"
        assert main(["simulate", str(sim), "--model", str(m), "--plan", str(plan), "--noise-F", str(noise),
                     "--cycles", "8", "--samples-per-cycle", "128"]) == 0
        assert main(["predict", str(m), str(sim), "--json", str(p)]) == 0
        out[noise] = {t["test"]: t for t in json.loads(p.read_text())["tests"]}
    recs = {r.test: r for r in read_records(tmp_path / f"s{sigma}.csv")}
    for tid, row in out[sigma].items():
        d = prepare_test(recs[tid])
        # independent noise floor of a bin-mean NRMSE: σ²/n per bin over the bins' variance of the force
        floor = math.sqrt(np.sum(d.counts * sigma**2 / d.counts) /
                          np.sum(d.counts * (d.Fbar - np.average(d.Fbar, weights=d.counts)) ** 2))
        assert row["nrmse_model"] < 1.3 * floor, (tid, row, floor)
        assert out[0.0][tid]["nrmse_model"] < 0.01 * floor  # what the time-domain form leaves without noise (measured <= 0.002)


@pytest.mark.slow
def test_delay_of_0_3_shortest_period_is_recovered_and_signed_in_where():
    from chainid.gap.diagnose import diagnose

    plan = grid3x3_plan(prefix="")
    tau = 0.3 * 2 * math.pi / max(s.omega for s in plan)
    res = diagnose(records(f"sensor_delay:tau={tau}", noise=2.0), HOLD.split(","), MODEL, max_combo=1,
                   uncertainty=False)
    assert res["verdict"] == "sensor_delay"
    assert res["best"]["params"]["sensor_delay.tau"] == pytest.approx(tau, rel=0.05)
    sig = [f for f in res["where"] if f["kind"] == "delay"]
    assert sig and sig[0]["tau_s"] == pytest.approx(tau, rel=0.05)
    # no delay: no delay signature
    res0 = diagnose(records("friction:F_c=150", noise=2.0), HOLD.split(","), MODEL, max_combo=1, uncertainty=False)
    assert not [f for f in res0["where"] if f["kind"] == "delay"]
