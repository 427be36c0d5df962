"""Models out of a diagnosis (chainid.gap.modelio): a step as a model file with its provenance, step 0 as the bare
baseline, predict's per-test and pooled NRMSE by hand and the damping it names."""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from chainid.model.base import LinearModel


# ---------------------------------------------------------------- modelio.step_models
@pytest.mark.slow
def test_step_models_baseline_is_step_zero_and_step_zero_is_bare():
    """Every step's model is compared with step 0 (the baseline: the base spring and the fitted damping, no effect,
    no delay); step 0's own baseline is that same bare model, so both predict the same force on any record.
    The truth here is a pure 0.05 s force-channel lag: the last step carries it, step 0 does not."""
    from chainid.gap.benchmark.grid import grid3x3_plan
    from chainid.gap.diagnose import diagnose
    from chainid.model.base import ChainModel
    from chainid.model.effects import parse_effect
    from chainid.model.laws import PolynomialLaw
    from chainid.records.simulate import simulate

    model = ChainModel()
    recs = simulate(grid3x3_plan(prefix=""), model, PolynomialLaw([0.5, 1.0, 100.0, 20.0, 50.0]), n_cycles=6,
                    samples_per_cycle=96, noise_F=2.0, seed=1, force_fn=parse_effect("sensor_delay:tau=0.05", model))
    res = diagnose(recs, ["3", "7", "11"], model, max_combo=1, uncertainty=False, quiet=True)
    assert res["verdict"] == "sensor_delay"
    models = res["_models"]
    assert len(models) == len(res["steps"]) == 2
    assert models[0].effects == [] and models[0].delay_s == 0.0
    assert models[1].delay_s == pytest.approx(0.05, rel=0.05) and models[1].baseline is models[0]
    b0 = models[0].baseline
    assert b0.effects == [] and b0.delay_s == 0.0 and b0.base is models[0].base
    r = recs[0]
    t, x = np.asarray(r.t, float), np.asarray(r.x, float)
    np.testing.assert_allclose(b0.force(t, x), models[0].force(t, x), rtol=1e-12, atol=1e-9)


def test_predict_time_domain_nrmse_and_pooling_by_hand():
    """Two ramps (not harmonic tests: predicted in the time domain), F = 100·x + e measured; the model is the
    100 N/mm spring, its baseline an 80 N/mm one (no damping, no mass).  NRMSE = sqrt(SSE/Σ(F − F̄)²) per test over
    the samples the time route compares (all but ``edge_samples`` at each end, where the kinematics rest on the
    filters' padding), pooled over the tests' sums; shrinkage 1 − model/baseline."""
    from chainid.gap.core import noise as nz
    from chainid.gap.core.kinematics import estimate
    from chainid.gap.modelio import predict
    from chainid.model.augmented import AugmentedModel
    from chainid.model.timedamping import Damping
    from chainid.records.record import Record

    rng = np.random.default_rng(4)
    recs, want = [], {}
    for name, slope in (("A", 1.0), ("B", 2.0)):
        t = np.linspace(0.0, 1.0, 400)
        x = slope * t
        e = 0.5 * rng.normal(size=t.size)
        F = 100.0 * x + e
        recs.append(Record(name, t, x, F))
        k = estimate(t, x, nz.excitation_band(t, x)).edge_samples(399.0)
        assert 0 < k < 40
        m = slice(k, t.size - k)
        var = float(np.sum((F[m] - F[m].mean()) ** 2))
        want[name] = (float(np.sum((20.0 * x[m] + e[m]) ** 2)), float(np.sum(e[m] ** 2)), var)
    model = AugmentedModel(LinearModel(100.0, 0.0), [], Damping("none"), 0.0)
    model.baseline = AugmentedModel(LinearModel(80.0, 0.0), [], Damping("none"), 0.0)
    out = predict(model, recs)
    for row in out["tests"]:
        sb, sm, var = want[row["test"]]
        assert row["mode"] == "time-domain"
        assert row["nrmse_baseline"] == pytest.approx(math.sqrt(sb / var), rel=1e-9)
        assert row["nrmse_model"] == pytest.approx(math.sqrt(sm / var), rel=1e-9)
        assert row["shrinkage"] == pytest.approx(1 - math.sqrt(sm / sb), rel=1e-9)
    sb, sm, var = (sum(v[i] for v in want.values()) for i in range(3))
    p = out["pooled"]
    assert (p["nrmse_baseline"], p["nrmse_model"]) == (pytest.approx(math.sqrt(sb / var), rel=1e-9),
                                                       pytest.approx(math.sqrt(sm / var), rel=1e-9))
    assert p["shrinkage"] == pytest.approx(1 - math.sqrt(sm / sb), rel=1e-9)
    assert out["damping_used"] == "none" and "_series" not in out  # the model's damping form (no law here)
    one = predict(model, recs, tests=["B"], fitted=True, keep=True)
    assert [r["test"] for r in one["tests"]] == ["B"] and one["damping_used"] == "none"  # no law: fitted c_e do not exist
    np.testing.assert_allclose(one["_series"]["B"][3], 100.0 * recs[1].x, rtol=1e-12)  # the model's force
    np.testing.assert_allclose(one["_series"]["B"][4], 80.0 * recs[1].x, rtol=1e-12)  # the baseline's
    assert one["pooled"]["nrmse_model"] == pytest.approx(math.sqrt(want["B"][1] / want["B"][2]), rel=1e-9)
    with pytest.raises(ValueError, match=r"--tests: test id\(s\) \['C'\] not in the data; valid ids: A, B"):
        predict(model, recs, tests=["A", "C"])
    with pytest.raises(ValueError, match="no records to predict"):
        predict(model, [])
    # no baseline: the model is its own, shrinkage 0; a constant force has no variance: None, not a NaN
    own = AugmentedModel(LinearModel(100.0, 0.0), [], Damping("none"), 0.0)
    assert predict(own, recs)["pooled"]["shrinkage"] == pytest.approx(0.0, abs=1e-12)
    flat = Record("F", recs[0].t, recs[0].x, np.full(400, 7.0))
    row = predict(own, [flat])["tests"][0]
    assert row["nrmse_model"] is None and row["shrinkage"] is None


def test_predict_names_the_damping_it_used():
    """A c_e law: "law" (with fitted=True: the fitted c_e only where the law was fitted on the test — none here, so
    the law for the one test); any other form: its name."""
    from chainid.gap.modelio import predict
    from chainid.model.augmented import AugmentedModel
    from chainid.model.timedamping import Damping
    from chainid.records.record import Record

    t = np.linspace(0.0, 1.0, 400)
    recs = [Record("A", t, 1.0 + 0.1 * np.sin(2 * np.pi * 3 * t), 100.0 + 10.0 * np.sin(2 * np.pi * 3 * t))]
    for damping, fitted, want in ((Damping("law", law="viscous", coefficients=[0.0]), False, "law"),
                                  (Damping("law", law="viscous", coefficients=[0.0]), True,
                                   "per-test fitted c_e on 0 test(s) the law was fitted on; the law on the other 1"),
                                  (Damping("law", law="viscous", coefficients=[0.0], per_test={"A": 0.0}), True,
                                   "per-test fitted c_e"),
                                  (Damping("viscous", {"c": 0.0}), True, "viscous"),
                                  (Damping("none"), False, "none")):
        model = AugmentedModel(LinearModel(100.0, 0.0), [], damping, 0.0)
        assert predict(model, recs, fitted=fitted)["damping_used"] == want


def test_model_of_step_carries_effects_delay_law_and_training_ce():
    """Effects other than sensor_delay/damping_law become force terms with their own parameters; the delay is
    sensor_delay.tau; the law's per-test c_e only for training tests; k_e of a linear baseline is its k (a
    chain's: None, from the chain at x0)."""
    from chainid.gap.modelio import model_of_step, step_fields
    from chainid.model.base import ChainModel

    lin = LinearModel(100.0, 0.5)
    prob = SimpleNamespace(train=[SimpleNamespace(test="1"), SimpleNamespace(test="2")], is_chain=False, model=lin,
                           model_for=lambda p: LinearModel(p.get("spring.k", 100.0), p.get("spring.x_ref", 0.5)))
    cand = SimpleNamespace(names=["friction", "sensor_delay"], law="viscous", law_params=[0.25],
                           params={"spring.k": 90.0, "spring.x_ref": 0.4, "friction.F_c": 30.0, "sensor_delay.tau": 0.01},
                           _ev={"c_e": {"1": 0.2, "2": 0.3, "H": 9.0}})
    m = model_of_step(prob, cand, {"note": "x"})
    assert [n for n, _ in m.effects] == ["friction"] and m.effects[0][1]["F_c"] == 30.0
    assert m.delay_s == 0.01 and (m.base.k, m.base.x_ref) == (90.0, 0.4)
    assert (m.damping.law, m.damping.coefficients, m.damping.k_e) == ("viscous", [0.25], 100.0)
    assert m.damping.per_test == {"1": 0.2, "2": 0.3} and m.info == {"note": "x"}
    no_delay = SimpleNamespace(names=["friction"], law="viscous", law_params=[0.25],
                               params={"friction.F_c": 30.0, "sensor_delay.tau": 0.5})
    assert model_of_step(prob, no_delay).delay_s == 0.0  # a stale key of another step is not this step's delay
    chain = SimpleNamespace(train=[], is_chain=True, model=ChainModel(), model_for=lambda p: ChainModel())
    assert model_of_step(chain, no_delay).damping.k_e is None
    f = step_fields(prob, cand)
    assert f["law_params"] == [0.25] and f["delay_s"] == 0.01 and f["mass_kg"] == 0.0


def test_provenance_of_a_model_file(tmp_path):
    import datetime as dt
    import hashlib

    from chainid import __version__
    from chainid.gap.modelio import provenance

    data = tmp_path / "d.csv"
    blob = bytes(range(256)) * 5000  # 1.28 MB: more than one 1 MiB chunk
    data.write_bytes(blob)
    p = provenance(data, "chainid diagnose d.csv")
    assert p["data_sha256"] == hashlib.sha256(blob).hexdigest() and p["data_file"] == str(data)
    assert p["command"] == "chainid diagnose d.csv" and p["chainid_version"] == __version__
    when = dt.datetime.fromisoformat(p["date"])
    assert when.utcoffset() == dt.timedelta(0) and abs(dt.datetime.now(dt.timezone.utc) - when).total_seconds() < 60
    assert provenance(None, "c")["data_file"] is None and provenance(None, "c")["data_sha256"] is None
    assert provenance(tmp_path / "gone.csv", "c")["data_sha256"] is None
