"""The augmented model, its file, predict and simulate --model (issue 17)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from chainid.cli import main
from chainid.gap.benchmark.grid import grid3x3_plan
from chainid.gap.harmonic.prepare import prepare_test
from chainid.model import ChainModel, LinearModel, PolynomialLaw, parse_effect
from chainid.model.augmented import AugmentedModel
from chainid.model.modelfile import load_model, model_from_dict, model_to_dict, save_model
from chainid.model.timedamping import Damping, dominant
from chainid.records import read_records, write_records
from chainid.records.simulate import simulate, write_plan

MODEL = ChainModel()
LAW = PolynomialLaw([0.5, 1.0, 100.0, 20.0, 50.0])  # N·s/mm, ω rad/s, A mm
HOLD = "3,7,11"


def records(effect: str | None, noise: float = 20.0, model=MODEL):
    return simulate(grid3x3_plan(prefix=""), model, LAW, n_cycles=8, samples_per_cycle=128, noise_F=noise, seed=1,
                    force_fn=parse_effect(effect, model) if effect else None)


@pytest.mark.parametrize("effect,base", [("friction:F_c=150", "chain"), ("hysteresis:F_h=200,x_h=0.05", "linear")])
def test_saved_model_reproduces_the_diagnosis_held_out_nrmse(tmp_path, effect, base):
    data = tmp_path / "d.csv"
    write_records(data, records(effect))
    m, r, p = tmp_path / "m.toml", tmp_path / "r.json", tmp_path / "p.json"
    assert main(["diagnose", str(data), "--holdout", HOLD, "--max-combo", "1", "--model", base, "--json", str(r),
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


def test_simulate_model_then_predict_round_trips_to_the_noise_level(tmp_path):
    data, plan = tmp_path / "d.csv", tmp_path / "plan.csv"
    write_records(data, records("friction:F_c=150"))
    write_plan(plan, grid3x3_plan(prefix=""))
    m = tmp_path / "m.toml"
    assert main(["diagnose", str(data), "--holdout", HOLD, "--max-combo", "1", "--save-model", str(m)]) == 0
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


def test_force_closed_form_linear_viscous_mass_delay_and_non_uniform_sampling():
    k, xr, c, m, tau, w = 200.0, 0.5, 3.0, 2.0, 0.01, 5.0
    model = AugmentedModel(LinearModel(k, xr), [], Damping("viscous", {"c": c}), tau, m)
    rng = np.random.default_rng(0)
    for t in (np.linspace(0, 4, 8001), np.sort(np.r_[0.0, rng.uniform(0, 4, 8000), 4.0])):
        x = 1.0 + 0.3 * np.sin(w * t)
        F = model.force(t, x)
        ts = t - tau  # closed form at t − τ (inside the record)
        ref = m * 1e-3 * (-0.3 * w * w * np.sin(w * ts)) + k * (1.0 + 0.3 * np.sin(w * ts) - xr) + c * 0.3 * w * np.cos(w * ts)
        inner = (t > 0.05) & (t < 3.95)
        assert np.max(np.abs(F - ref)[inner]) < 2e-3 * np.max(np.abs(ref))


def test_memory_effects_run_forward_and_do_not_depend_on_the_sampling():
    model = AugmentedModel(LinearModel(100.0, 0.0), [("friction", {"F_c": 30.0, "x_s": 0.05}),
                                                      ("hysteresis", {"F_h": 20.0, "x_h": 0.1})])
    t = np.linspace(0, 3, 3001)
    x = 0.4 * np.sin(2 * math.pi * t) * np.minimum(t, 1.0)
    keep = np.unique(np.r_[np.random.default_rng(1).choice(t.size, 400, replace=False), 0, t.size - 1])
    # the non-uniform subset keeps every reversal of x (the path of a rate-independent operator)
    rev = np.flatnonzero(np.diff(np.sign(np.diff(x))) != 0) + 1
    keep = np.unique(np.r_[keep, rev])
    Fu, Fn = model.force(t, x), model.force(t[keep], x[keep])
    assert np.max(np.abs(Fn - Fu[keep])) < 1e-9 * np.max(np.abs(Fu))


def test_hysteretic_rule_keeps_the_energy_per_cycle():
    w, A, c = 2.0, 0.3, 50.0
    d = Damping("law", law="viscous", coefficients=[c], rule="hysteretic").resolve(w, A, 0.0, x0=0.0)
    t = np.linspace(0, 3 * 2 * math.pi / w, 6001)
    F, dE = d.force(A * np.sin(w * t), A * w * np.cos(w * t))
    assert np.sum(dE[-2000:]) == pytest.approx(math.pi * c * w * A * A, rel=1e-9)  # viscous c: W = πcωA²
    # the compensating spring removes the in-phase first harmonic; the quadrature one is c·ω·A
    psi = w * t[-2001:-1]
    assert 2 * np.mean(F[-2001:-1] * np.sin(psi)) == pytest.approx(0.0, abs=1e-3 * c * w * A)
    assert 2 * np.mean(F[-2001:-1] * np.cos(psi)) == pytest.approx(c * w * A, rel=2e-3)


def test_dominant_frequency_and_amplitude_of_a_ramped_record():
    from chainid.records.simulate import TestSpec, simulate_test

    r = simulate_test(TestSpec("a", 3.0, 5.0, 0.4), MODEL, 1.0, ramp_rate=0.08973, n_cycles=8)
    w, A, x0 = dominant(r.t, r.x)
    assert w == pytest.approx(3.0, rel=2e-3) and A == pytest.approx(0.4, rel=5e-3) and x0 == pytest.approx(5.0, rel=1e-3)


def test_model_file_round_trip_and_errors(tmp_path):
    m = AugmentedModel(MODEL, [("slack", {"s": 0.01}), ("friction", {"F_c": 10.0})],
                       Damping("law", law="viscous", coefficients=[2.0], per_test={"1": 2.5}), 0.002, 3.0)
    for name in ("m.toml", "m.json"):
        p = save_model(m, tmp_path / name)
        assert model_to_dict(load_model(p)) == model_to_dict(m)
        with pytest.raises(ValueError, match="exists"):
            save_model(m, p)
    d = model_to_dict(m)
    with pytest.raises(ValueError, match="format_version = 2"):
        model_from_dict(d | {"format_version": 2})
    with pytest.raises(ValueError, match="unknown key.*colour"):
        model_from_dict(d | {"colour": 1})
    with pytest.raises(ValueError, match="wobble"):
        model_from_dict(d | {"effects": [{"name": "wobble", "params": {}}]})
    with pytest.raises(ValueError, match="unknown parameter.*Q"):
        model_from_dict(d | {"effects": [{"name": "friction", "params": {"Q": 1.0}}]})
    with pytest.raises(ValueError, match="mass_kg"):
        model_from_dict(d | {"mass_kg": -1.0})
    bad = tmp_path / "bad.toml"
    bad.write_text("format_version = 1\n[base\n")
    with pytest.raises(ValueError, match="not valid TOML"):
        load_model(bad)
    with pytest.raises(ValueError, match="does not exist"):
        load_model(tmp_path / "none.toml")
    assert main(["predict", str(tmp_path / "none.toml"), str(bad)]) == 2
