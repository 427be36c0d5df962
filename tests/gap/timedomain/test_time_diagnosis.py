"""The diagnosis on any excitation (time-domain route): one band-limited random case per effect family recovered
blind, a compound cause, drift, chatter, transfer, mixed sets, a lead-in at rest.

Records built here from the library's operators run causally over x(t) (tests/transient_forms.py), not through
the time-domain route of the diagnosis; chain model; force noise 5 N."""
from __future__ import annotations

import functools
import warnings

import numpy as np
import pytest

from chainid.gap import diagnose, parse_effect
from chainid.records.simulate import grid_plan, simulate

from transient_forms import chain_set


@pytest.mark.slow
def test_compound_friction_on_a_softer_chain():
    def fric(t, x, xd):
        from chainid.model.effects import stick_slip
        return 60.0 * stick_slip(x, xd, 0.0, periodic=False)

    model, recs = chain_set("stiffness_level", {"scale": 0.8}, extra=fric, seed=10)
    res = diagnose(recs, ["r2"], model, quiet=True)
    assert set(res["verdict"].split("+")) == {"stiffness_level", "friction"}, res["chain_text"]
    p = res["steps"][-1]["params"]
    assert p["stiffness_level.scale"] == pytest.approx(0.8, rel=0.10)
    assert p["friction.F_c"] == pytest.approx(60.0, rel=0.10)


@pytest.mark.slow
def test_drift_is_flagged_non_stationary():
    # a force sensor drifting by 80 N over each 20 s record (16 σ), no other effect
    model, recs = chain_set("none", {}, extra=lambda t, x, xd: 80.0 * t / t[-1], seed=20)
    res = diagnose(recs, ["r2"], model, quiet=True)
    assert res["residual"]["stationary"] is False
    assert res["where"][0]["kind"] == "nonstationary"
    assert res["verdict"] == "unexplained"


@pytest.mark.slow
def test_no_drift_is_stationary():
    model, recs = chain_set("friction", {"F_c": 60.0}, seed=30)
    res = diagnose(recs, ["r2"], model, quiet=True)
    assert res["residual"]["stationary"] is True
    assert not any(f["kind"] == "chatter" for f in res["where"])


@pytest.mark.slow
def test_stick_slip_chatter_is_reported_not_named():
    # friction plus a 30 Hz, 40 N oscillation while the contact slides (|ẋ| > 0.3 of its peak): chatter
    def chatter(t, x, xd):
        from chainid.model.effects import stick_slip
        slide = np.abs(xd) > 0.3 * np.abs(xd).max()
        return 60.0 * stick_slip(x, xd, 0.0, periodic=False) + 40.0 * np.sin(2 * np.pi * 30.0 * t) * slide

    model, recs = chain_set("none", {}, extra=chatter, seed=40)
    res = diagnose(recs, ["r2"], model, quiet=True)
    ch = [f for f in res["where"] if f["kind"] == "chatter"]
    assert ch, [f["finding"] for f in res["where"]]
    assert ch[0]["frequency_Hz"] == pytest.approx(30.0, rel=0.05)
    assert "chatter" not in res["verdict"]
    assert any("chatter" in w and "no library effect" in w for w in res["warnings"])


def _harmonic(model):
    plan = grid_plan((4.0, 8.0, 12.0), (0.05, 0.08, 0.12), 2.0)
    return simulate(plan, model, 30.0, n_cycles=6, samples_per_cycle=128, noise_F=5.0, seed=3,
                    force_fn=parse_effect("hysteresis:F_h=80,x_h=0.02", model))


@pytest.mark.slow
def test_transfer_harmonic_to_random_and_back():
    model, rand = chain_set("hysteresis", {"F_h": 80.0, "x_h": 0.02}, seed=50)
    harm = _harmonic(model)
    res = diagnose(harm, ["5"], model, uncertainty=False, quiet=True, validate=rand)
    assert res["route"] == "harmonic" and res["verdict"] == "hysteresis"
    tr = res["transfer"]
    assert tr["transfers"] is True and tr["pooled"]["shrinkage"] >= 0.7, tr["verdict_text"]
    assert {r["route"] for r in tr["tests"]} == {"time"}  # random records: scored in the time domain
    back = diagnose(rand, ["r2"], model, quiet=True, validate=harm)
    assert back["route"] == "time"
    assert back["transfer"]["transfers"] is True and back["transfer"]["pooled"]["shrinkage"] >= 0.7
    # a time-route model scores every record of the other set in the time domain, its steady harmonic tests too
    # (chainid.gap.transfer's docstring): all 9 tests, no phase bins
    assert [r["test"] for r in back["transfer"]["tests"]] == [r.test for r in harm]
    assert {r["route"] for r in back["transfer"]["tests"]} == {"time"}


@pytest.mark.slow
def test_transfer_refused_for_a_wrong_chain():
    # fitted on friction records, scored on hysteresis records with a long travel: the chain does not transfer
    model, fr = chain_set("friction", {"F_c": 60.0}, seed=60)
    _, hy = chain_set("hysteresis", {"F_h": 80.0, "x_h": 0.2}, seed=70)
    res = diagnose(fr, ["r2"], model, quiet=True, validate=hy)
    assert res["verdict"] == "friction"
    assert res["transfer"]["transfers"] is False, res["transfer"]["verdict_text"]


@pytest.mark.slow
def test_mixed_set_one_problem():
    model, rand = chain_set("hysteresis", {"F_h": 80.0, "x_h": 0.02}, seed=80)
    harm = _harmonic(model)
    res = diagnose(harm + rand, ["5", "r2"], model, quiet=True)
    # a set with a record that is not a steady harmonic test takes the time route, every record sample by sample
    # (the route rule of chainid.gap.diagnose): one problem, the harmonic tests in it
    assert res["route"] == "time"
    assert res["verdict"] == "hysteresis", res["chain_text"]
    assert res["steps"][1]["params"]["hysteresis.F_h"] == pytest.approx(80.0, rel=0.10)
    assert sorted(t["test"] for t in res["tests"]) == sorted(r.test for r in harm + rand)
    assert {t["route"] for t in res["tests"]} == {"time"}
    assert {t["test"] for t in res["tests"] if t["split"] == "holdout"} == {"5", "r2"}


def test_holdout_blocks_bad_values():
    model, recs = chain_set("none", {}, n_rec=1, n=600)
    with pytest.raises(ValueError, match="holdout-blocks"):
        diagnose(recs, [], model, holdout_blocks=1)
    with pytest.raises(ValueError, match="--holdout"):
        diagnose(recs, [], model)


@functools.lru_cache(maxsize=1)
def _rest_lead_in_case():
    """The benchmark's small random friction case with one viscous c on every record (``damping_varies`` False:
    the benchmark now varies c over a case's records), diagnosed blind with r4 held out: (records' device, result)."""
    from chainid.gap.benchmark.grid import grid
    from chainid.gap.benchmark.nonharmonic import records
    from chainid.gap.diagnose import diagnose

    case = next(k for k in grid(True, 0, ("random",)) if k["family"] == "single")
    assert case["truth"] == ["friction"] and case["hold"] == "r4"
    recs, dev = records(case | {"damping_varies": False})
    assert dev["c_records"] == [dev["c"]] * 4
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return dev, diagnose(recs, ["r4"], dev["nominal"], uncertainty=False, quiet=True)


@pytest.mark.slow
def test_coulomb_friction_behind_a_rest_lead_in_is_named_on_a_held_out_record() -> None:
    """The benchmark's small random friction case: its held-out record r4 starts with 323 samples at rest.
    Before the rest rule the noise's velocity sign put ±F_c on them (310 of 3970 samples with the wrong
    sign) and the case was `unexplained` (held-out shrinkage 49 %); the truth is F_c = 139.07 N
    (``effect_spec`` of the case: 0.15·S, S = 927.12 N) and c = 19.32 N·s/mm (0.02874·2k/ω_max), no μ."""
    dev, res = _rest_lead_in_case()
    assert np.count_nonzero(dev["motions"][3].xd == 0.0) == 323
    assert dev["c"] == pytest.approx(19.32, rel=1e-3)
    assert res["verdict"] == "friction"
    last = res["steps"][-1]
    assert last["params"]["friction.F_c"] == pytest.approx(139.07, rel=0.03)
    assert last["params"]["damping.c"] == pytest.approx(19.32, rel=0.05)


@pytest.mark.slow
def test_coulomb_friction_behind_a_rest_lead_in_closes_most_of_the_held_out_gap() -> None:
    """The same case: the friction step shrinks the held-out error by more than 80 % (the noise floor allows 90 %).
    It did with the old kinematics; with one c for every record it reached 0.795 (the estimated kinematics leave r4
    at NRMSE 0.0200 against its 0.0096 floor, 66 % of it the friction sign in the last ~54 samples of the rest
    lead-in, where the zero-phase filters ring ahead of the onset); with the base's dashpot following the records'
    features 0.802."""
    _, res = _rest_lead_in_case()
    assert res["steps"][-1]["shrinkage"] > 0.8


CASES = [
    ("friction", {"F_c": 60.0}, {"friction.F_c": 60.0}),
    ("hysteresis", {"F_h": 80.0, "x_h": 0.02}, {"hysteresis.F_h": 80.0, "hysteresis.x_h": 0.02}),
    ("backlash", {"b": 0.03}, {"backlash.b": 0.03}),
    ("stiffness_level", {"scale": 0.8}, {"stiffness_level.scale": 0.8}),
    ("slack", {"s": 0.05}, {"slack.s": 0.05}),
    ("sensor_delay", {"tau": 0.02}, {"sensor_delay.tau": 0.02}),
]


@pytest.mark.slow
@pytest.mark.parametrize("effect,p,expect", CASES, ids=[c[0] for c in CASES])
def test_random_excitation_recovers_each_family(effect, p, expect):
    model, recs = chain_set(effect, p)
    res = diagnose(recs, ["r2"], model, quiet=True)
    assert res["route"] == "time"
    # the family is named first (a family member of the same physics may stand in for contact_law/level)
    assert res["steps"][1]["effect"] == effect, res["chain_text"]
    got = res["steps"][1]["params"]
    for k, v in expect.items():
        assert got[k] == pytest.approx(v, rel=0.10), (k, got)
    assert res["steps"][-1]["shrinkage"] >= 0.5
    # the noise floor is estimated from the records themselves: σ = 5 N simulated
    assert res["baseline"]["noise_sigma_N"] == pytest.approx(5.0, rel=0.10)


def test_no_effect_is_none():
    model, recs = chain_set("none", {})
    res = diagnose(recs, ["r2"], model, quiet=True)
    assert res["verdict"] == "none", res["chain_text"]
