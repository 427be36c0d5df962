"""The ODE world's case generation by hand: effect strengths not covered by the scaling test, the scales a case draws
on, the frequency response of the resonant base, the test plans' counts and amplitudes, the case list per family
and its labels, the drift, hold-out, covariate and damping-law helpers of the world, and the logger's drift and
offset.  Units mm, N, s, kg, Hz."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.gap.benchmark import odecases as oc
from chainid.gap.benchmark import odeworld as ow
from chainid.gap.benchmark.odefamilies import world_cases

SC = {"S": 800.0, "A": 0.4, "v": 25.0, "k": 2000.0, "x_mean": 1.5, "f_hi": 4.0}


def _eff(name: str, level: float, sign: float = 1.0) -> dict:
    return oc.effect_params(name, level, SC, np.random.default_rng(0), sign)


def test_end_stop_cubic_and_contact_strengths_by_hand():
    """deadband: g = 1.5·0.4 = 0.6 mm, k_d = 0.5·2·2000/0.4 = 5000 N/mm², p 2, centred at x_mean 1.5;
    hardening: k3 = 0.1·2·800/0.4³ = 2500 N/mm³; contact_law: scale 1 + 0.3·level, β 2/3 below level 1.5."""
    assert _eff("deadband", 2.0) == pytest.approx({"k_d": 5000.0, "g": 0.6, "p": 2.0, "x_c": 1.5}, rel=1e-12)
    assert _eff("hardening", 2.0) == pytest.approx({"k3": 2500.0, "k2": 0.0, "x_m": 1.5}, rel=1e-12)
    assert _eff("contact_law", 1.0) == pytest.approx({"scale": 1.3, "beta": 2.0 / 3.0}, rel=1e-12)
    assert _eff("contact_law", 1.5) == pytest.approx({"scale": 1.45, "beta": 0.8}, rel=1e-12)


@pytest.mark.parametrize("level, scale", [(0.5, 0.94), (2.0, 0.76), (2.5, 1.3)])
def test_stiffness_level_softens_by_twelve_per_cent_per_level_up_to_two(level, scale):
    """scale = 1 − 0.12·level up to level 2 (0.94 at 0.5, 0.76 at 2); above level 2 the case is a stiffer base,
    scale 1.3 (odecases: the level-2.5 strength)."""
    assert _eff("stiffness_level", level)["scale"] == pytest.approx(scale, rel=1e-12)


def test_sensor_delay_is_a_signed_fifteen_centiradian_lag_at_the_band_edge_and_damping_law_spread_saturates():
    """τ = ±0.15·level / (2π·4 Hz): 0.15 rad at f_hi; damping_law spread 0.2·min(level, 1.5)."""
    assert _eff("sensor_delay", 2.0)["tau"] == pytest.approx(0.3 / (8 * math.pi), rel=1e-12)
    assert _eff("sensor_delay", 1.0, -1.0)["tau"] == pytest.approx(-0.15 / (8 * math.pi), rel=1e-12)
    assert [_eff("damping_law", lv)["spread"] for lv in (1.0, 1.5, 2.0)] == pytest.approx([0.2, 0.3, 0.3])
    assert _eff("slack", 2.0) == pytest.approx({"s": 0.08})
    with pytest.raises(ValueError, match="effect 'creep' has no strength rule in the ODE world"):
        _eff("creep", 1.0)


def test_friction_slips_harder_one_way_in_a_third_of_draws_by_thirty_per_cent():
    """2000 draws: the share with dF ≠ 0 is 1/3 ± 0.035 (3.3 binomial sd), dF = ±0.3·F_c both ways,
    F_c = 0.1·level·S = 80 N, x_s = 0.02·A = 0.008 mm; stribeck F_c = 0.05·level·S = 40 N, F_s = 2·F_c, v_s = 0.2·v, v_e = 0.02·v_s."""
    rng = np.random.default_rng(12)
    draws = [oc.effect_params("friction", 1.0, SC, rng) for _ in range(2000)]
    asym = [d["dF"] for d in draws if d["dF"] != 0.0]
    assert abs(len(asym) / 2000 - 1 / 3) < 0.035
    assert set(np.round(asym, 9)) == {-24.0, 24.0}
    assert {d["F_c"] for d in draws} == {80.0} and np.allclose([d["x_s"] for d in draws], 0.008, rtol=1e-12)
    st = _eff("stribeck", 1.0)
    assert st == pytest.approx({"F_c": 40.0, "F_s": 80.0, "dF": 0.0, "v_s": 5.0, "v_e": 0.1}, rel=1e-12)
    bw = [oc.effect_params("bouc_wen", 1.0, SC, rng) for _ in range(200)]
    assert {d["n"] for d in bw} == {2.0, 4.0} and all(0.5 <= d["r"] <= 1.0 for d in bw)
    assert {d["F_y"] for d in bw} == {80.0} and np.allclose([d["x_y"] for d in bw], 0.08, rtol=1e-12)


def test_scales_of_a_resonant_a_damper_and_a_stiff_base():
    """v = 2π·(f_lo + f_hi)/2·A; S = k·A with a mass, else the larger of k·A and c·v; the mean elongation is x0,
    or x_ref + F0/k for a force-driven base (resonant: 0.3 + 150/300 = 0.8 mm)."""
    res = {"kind": "linear", "m": 2.0, "k": 300.0, "c": 50.0, "x_ref": 0.3, "F0": 150.0, "A": 0.5, "f_lo": 10.0,
           "f_hi": 30.0, "fs": 2000.0}
    s = oc.scales(res)
    assert s["v"] == pytest.approx(2 * math.pi * 20.0 * 0.5) and s["S"] == pytest.approx(150.0)  # not c·v
    assert s["x_mean"] == pytest.approx(0.8) and (s["k"], s["A"], s["fs"]) == (300.0, 0.5, 2000.0)
    assert (s["f_lo"], s["f_hi"]) == (10.0, 30.0)
    dam = {"kind": "linear", "m": 0.0, "k": 5.0, "c": 0.5, "x_ref": 0.0, "x0": -1.2, "A": 2.0, "f_lo": 4.0,
           "f_hi": 20.0, "fs": 1000.0}
    s = oc.scales(dam)
    assert s["S"] == pytest.approx(0.5 * 2 * math.pi * 12.0 * 2.0) and s["x_mean"] == -1.2  # c·v = 75.4 > k·A = 10
    stiff = {**dam, "k": 100.0, "c": 0.01, "x0": 5.0}
    assert oc.scales(stiff)["S"] == pytest.approx(200.0)  # k·A = 200 > c·v = 1.5


def test_frf_gain_of_the_resonant_base_by_hand():
    """At f_n the mass and spring cancel: |H| = 1/(c·ω_n); at 0 Hz 1/k; above, 1/|k − m ω² 1e-3| with c·ω small."""
    m, fn, c = 2.0, 30.0, 0.1
    k = m * (2 * math.pi * fn) ** 2 * 1e-3
    b = {"k": k, "m": m, "c": c}
    g = oc._frf_gain(b, np.array([fn, 0.0, 60.0]))
    assert g[0] == pytest.approx(1 / (c * 2 * math.pi * fn), rel=1e-9)
    assert g[1] == pytest.approx(1 / k, rel=1e-12)
    w = 2 * math.pi * 60.0
    assert g[2] == pytest.approx(1 / math.hypot(k - m * w * w * 1e-3, c * w), rel=1e-12)


def test_chain_harmonic_plan_is_table_one_scaled_by_the_chain_length():
    """Nine records, f = column/20 Hz, ≥ 3 cycles and ≥ 2000 samples (0.05 Hz at 250 Hz: 15000), x0 and A × 1.5."""
    b = {"kind": "chain", "x_scale": 1.5, "x0": 3.0, "A": 0.1, "f_lo": 0.2, "f_hi": 2.0, "fs": 250.0}
    plan = oc.draw_plan("chain18", b, "harmonic", np.random.default_rng(0))
    assert [r["f"] for r in plan] == pytest.approx([0.05, 0.2, 0.3, 0.4, 0.5, 0.3, 0.3, 0.3, 0.3])
    assert [r["n"] for r in plan] == [15000, 3750, 2500, 2000, 2000, 2500, 2500, 2500, 2500]
    assert [r["mean"] for r in plan] == pytest.approx([3.3] * 5 + [3.225, 3.375, 3.45, 3.525])
    assert [r["amp"] for r in plan] == pytest.approx([0.375] * 5 + [0.3, 0.45, 0.525, 0.6])
    assert {r["fs"] for r in plan} == {250.0} and {r["kind"] for r in plan} == {"harmonic"}


def test_force_driven_sine_plan_sets_the_displacement_amplitude_and_rings_in():
    """Resonant base, 30 plans: 6–8 sines between 1.2·0.97·f_lo and 1.03·f_hi/1.2; the force amplitude times the
    FRF gain at f is √2·A·(0.6–1.4); the pre-roll is max(3, ⌈1.5·f/(ζ f_n)⌉) cycles (the free decay's time)."""
    rng = np.random.default_rng(8)
    ratios = []
    for _ in range(30):
        b = oc.draw_base("resonant", rng)
        plan = oc.draw_plan("resonant", b, "harmonic", rng)
        assert 6 <= len(plan) <= 8
        for r in plan:
            assert b["f_lo"] * 1.2 * 0.97 <= r["f"] <= b["f_hi"] / 1.2 * 1.03
            assert r["pre"] == max(3, math.ceil(1.5 * r["f"] / (b["zeta"] * b["f_n"])))
            assert r["n"] == max(2000, math.ceil(8 * r["fs"] / r["f"])) and r["mean"] == b["F0"]
            ratios.append(r["amp"] * float(oc._frf_gain(b, np.array([r["f"]]))[0]) / (math.sqrt(2) * b["A"]))
    assert 0.6 <= min(ratios) < 0.65 and 1.35 < max(ratios) <= 1.4


def test_force_driven_multisine_plan_counts_periods_and_rings_in():
    """4–8 records of 4000–20000 samples; n_periods p (+0.5 sometimes) with T/p·(f_hi − f_lo) ≥ 8 lines unless
    the record holds a single period; pre-roll ⌈1.5/(ζ ω_n) / (T/p)⌉ periods; force RMS × the band's RMS gain =
    A·(0.7–1.3); f_lo within the base's × 0.9–1.1, f_hi at most the base's × 1.1 and fs/10."""
    rng = np.random.default_rng(3)
    ratios, halves = [], 0
    for _ in range(25):
        b = oc.draw_base("resonant", rng)
        gain = math.sqrt(np.mean(oc._frf_gain(b, np.linspace(b["f_lo"], b["f_hi"], 200)) ** 2))
        plan = oc.draw_plan("resonant", b, "multisine", rng)
        assert 4 <= len(plan) <= 8
        for r in plan:
            T = r["n"] / r["fs"]
            assert 4000 <= r["n"] <= 20000 and r["f_hi"] <= r["fs"] / 10
            assert 0.9 * b["f_lo"] <= r["f_lo"] <= 1.1 * b["f_lo"] and r["f_hi"] <= 1.1 * b["f_hi"]
            p = math.floor(r["n_periods"])
            halves += r["n_periods"] != p
            assert p in (1, 2, 3, 4) and (T / p * (r["f_hi"] - r["f_lo"]) >= 8 or p == 1)
            assert r["pre"] == max(1, math.ceil(1.5 / (b["zeta"] * 2 * math.pi * b["f_n"]) / (T / r["n_periods"])))
            ratios.append(r["amp"] * gain / b["A"])
    assert 0.7 <= min(ratios) < 0.75 and 1.25 < max(ratios) <= 1.3 and halves > 0


def test_displacement_driven_noise_plan_tapers_and_rests_as_stated():
    """Damper: 2000–8000 samples, taper 5–15 % and a rest of 0–5 % of n/fs, the mean x0, RMS A·(0.7–1.3)."""
    rng = np.random.default_rng(4)
    taper, rest = [], []
    for _ in range(20):
        b = oc.draw_base("damper", rng)
        for r in oc.draw_plan("damper", b, "noise", rng):
            assert 2000 <= r["n"] <= 8000 and r["mean"] == b["x0"] and 0.7 <= r["amp"] / b["A"] <= 1.3
            taper.append(r["taper"] * r["fs"] / r["n"])
            rest.append(r["rest"] * r["fs"] / r["n"])
    assert 0.05 <= min(taper) < 0.06 and 0.14 < max(taper) <= 0.15
    assert 0.0 <= min(rest) < 0.005 and 0.045 < max(rest) <= 0.05
    with pytest.raises(ValueError, match="excitation = 'step' is unknown"):
        oc.draw_plan("damper", b, "step", rng)


def test_a_down_chirp_plan_sweeps_from_its_top_frequency():
    r = {"kind": "chirp", "fs": 500.0, "n": 5000, "f_lo": 2.0, "f_hi": 20.0, "n_sweeps": 1, "rest": 1.0,
         "down": True, "log": False}
    s = oc.make_shape(r, np.random.default_rng(0))
    tt = s.t[(s.t > 1.5) & (s.t < 9.0)]
    y = s.y[(s.t > 1.5) & (s.t < 9.0)]
    zc = tt[np.flatnonzero(np.diff(np.sign(y)) != 0)]
    gaps = np.diff(zc)
    assert gaps[:5].mean() < gaps[-5:].mean()  # fast first: from 20 Hz down
    up = oc.make_shape({**r, "down": False}, np.random.default_rng(0))
    assert np.max(np.abs(up.y[::-1][: s.y.size] - s.y)) > 0.1


def test_case_counts_per_family_of_the_full_world():
    """control 4+3+4+3+4 excitations + 2 offsets = 20; single 3 levels × (11+5+9+5+6) + 7 Table 1 = 115; pair
    2 × 8 + 1 = 17; outside 2 × 8 = 16; covariate 4."""
    fam = [c["family"] for c in world_cases(False, 0)]
    assert {f: fam.count(f) for f in set(fam)} == {"control": 20, "single": 115, "pair": 17, "outside": 16,
                                                   "covariate": 4}


def test_labels_name_family_base_excitation_effects_levels_and_forms():
    """By hand from the tables: the excitation cycles per base (chain18: noise, harmonic, multisine; pair j at
    level index k: excitation j + k), damping_law off level 1 runs harmonic where the base has it."""
    cases = {c["label"]: c for c in world_cases(False, 0)}
    for lab in ("control/resonant/multisine/none+offsets", "control/stiff/harmonic/none",
                "single/chain18/noise/friction@0.5", "single/chain18/harmonic/friction@1",
                "single/chain18/multisine/contact_law@2", "single/damper/multisine/damping_law@0.5",
                "single/damper/chirp/damping_law@1", "single/damper/noise/damping_law@2",
                "single/stiff/harmonic/damping_law@0.5", "single/stiff/noise/damping_law@1",
                "single/stiff/harmonic/damping_law@2", "single/stiff/noise/damping_law@1~table1",
                "pair/chain14/multisine/friction+sensor_delay@1/1", "pair/chain14/noise/friction+sensor_delay@2/2",
                "pair/resonant/noise/hysteresis+sensor_delay-@1/1", "pair/resonant/chirp/hysteresis+sensor_delay-@2/2",
                "pair/chain14/chirp/backlash+damping_law@1/1~table1", "outside/stiff/noise/chatter@2",
                "covariate/resonant/multisine/stribeck@1"):
        assert lab in cases, lab
    c = cases["pair/resonant/noise/hysteresis+sensor_delay-@1/1"]
    assert c["effects"] == {"hysteresis": 1.0, "sensor_delay": 1.0} and c["sign"] == -1.0
    assert cases["single/chain14/noise/sensor_delay@1"]["sign"] == 1.0  # i = 25 of 4 excitations: noise
    assert cases["single/chain14/multisine/sensor_delay-@1"]["sign"] == -1.0  # i = 28
    assert cases["control/resonant/multisine/none+offsets"]["offsets"] is True
    assert cases["outside/stiff/noise/chatter@2"]["outside"] == {"chatter": 2.0}
    cov = cases["covariate/damper/multisine/friction@1"]["covariate"]
    assert (cov["param"], cov["lo"], cov["hi"], cov["levels"], cov["slope_rel"]) == ("F_c", 0.0, 2.0, 5, 1.0)


def test_drift_starts_where_the_previous_records_left_it():
    """total 6 N over a mean record of 3 s: 2 N/s; a record starting at 11 s starts at 22 N."""
    assert ow._drift({"drift": {"total": 6.0}}, 11.0, 3.0) == pytest.approx((22.0, 2.0))
    assert ow._drift({"relaxation": {}}, 11.0, 3.0) == (0.0, 0.0)


@pytest.mark.parametrize("n, k", [(5, 1), (6, 1), (7, 2), (8, 2), (9, 3)])
def test_holdout_takes_one_two_or_three_distinct_records(n, k):
    hold = ow._holdout({}, n, None, np.random.default_rng(n))
    assert len(set(hold)) == k and all(1 <= int(h[1:]) <= n for h in hold) and hold == sorted(hold)


def test_holdout_of_a_covariate_case_is_the_middle_condition():
    """Seven records at conditions 0, 1, 2, 0, 1, 2, 0: median 1, two held out → r2 and r5; five: one."""
    cov = np.array([0.0, 1.0, 2.0, 0.0, 1.0, 2.0, 0.0])
    assert ow._holdout({}, 7, cov, np.random.default_rng(0)) == ["r2", "r5"]
    # skewed conditions 0, 0, 1, 2, 100: the median 1 (r3), not the one nearest the mean 20.6 (r4)
    assert ow._holdout({}, 5, np.array([0.0, 0.0, 1.0, 2.0, 100.0]), np.random.default_rng(0)) == ["r3"]


def test_covariate_cycles_its_levels_and_states_its_linear_law():
    """Levels linspace(20, 60, 3) = 20, 40, 60 over 5 records: 20, 40, 60, 20, 40; p1 = 1.0·p0/hi = 12/60."""
    case = {"covariate": {"name": "T", "unit": "degC", "effect": "hysteresis", "param": "F_h", "lo": 20.0,
                          "hi": 60.0, "levels": 3, "slope_rel": 1.0}}
    values, truth = ow._covariate(case, 5, {"hysteresis": {"F_h": 12.0, "x_h": 0.1}}, np.random.default_rng(0))
    np.testing.assert_array_equal(values, [20.0, 40.0, 60.0, 20.0, 40.0])
    assert truth["p0"] == 12.0 and truth["p1"] == pytest.approx(0.2, rel=1e-12)
    assert truth["label"] == "hysteresis.F_h@T" and truth["values"] == [20.0, 40.0, 60.0, 20.0, 40.0]
    assert ow._covariate({}, 5, {}, np.random.default_rng(0)) == (None, None)


def test_linear_damping_law_spends_its_spread_on_the_features_that_vary():
    """ω alone varies: |c_r − c| peaks at exactly spread·c on the ω extremes; both vary: the ω and A parts peak at
    share·spread·c and (1 − share)·spread·c with share 0.3–0.7, and c_r averages to c."""
    rng = np.random.default_rng(2)
    w = np.array([2.0, 5.0, 9.0, 20.0])
    c_r, law = ow._damping_per_record(10.0, 0.2, w, np.full(4, 0.3), rng)
    assert float(np.max(np.abs(c_r - 10.0))) == pytest.approx(2.0, rel=1e-12) and law["b_A"] == 0.0
    assert law["omega_mean"] == pytest.approx(9.0) and law["c"] == 10.0
    c_r, law = ow._damping_per_record(10.0, 0.2, np.full(4, 5.0), np.array([0.1, 0.2, 0.3, 0.6]), rng)
    assert float(np.max(np.abs(c_r - 10.0))) == pytest.approx(2.0, rel=1e-12) and law["b_w"] == 0.0
    A = np.array([0.1, 0.2, 0.3, 0.6])
    for _ in range(10):
        c_r, law = ow._damping_per_record(10.0, 0.2, w, A, rng)
        pw = abs(law["b_w"]) * float(np.max(np.abs(w - w.mean())))
        pA = abs(law["b_A"]) * float(np.max(np.abs(A - A.mean())))
        assert pw + pA == pytest.approx(2.0, rel=1e-12) and 0.6 <= pw <= 1.4
        assert float(np.mean(c_r)) == pytest.approx(10.0, rel=1e-12)


def test_logger_adds_drift_and_offset_on_the_record_times():
    """F_meas = F + d0 + d1·t + offset with t the record's own times (no noise, no lag); x untouched."""
    from chainid.gap.benchmark import odeshapes as sh
    from chainid.gap.benchmark.odedevice import Trace
    from chainid.gap.benchmark.odemeasure import Logger, measure

    s = sh.harmonic(500.0, 2000, 5.0)
    F = 3.0 * s.y
    tr = Trace(s.t, 0.1 * s.y, 0.1 * s.yd, 0.1 * s.ydd, F, np.zeros((s.t.size, 0)))
    rec = measure("r1", s, tr, Logger(offset_F=0.5, drift=(2.0, -0.25)), np.random.default_rng(0))
    idx = s.record_index
    t = s.t[idx]
    np.testing.assert_allclose(rec.F, F[idx] + 2.0 - 0.25 * t + 0.5, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(rec.x, 0.1 * s.y[idx])


@pytest.mark.parametrize("small", [True, False])
def test_every_effect_of_a_single_or_pair_case_has_a_strength(small):
    """An effect at strength 0 is no effect: the case would be a control under an effect's name, and a right
    `none` would be scored as a miss.  Every single and pair case of both worlds names its effects with strengths
    above 0, and both worlds hold every family (single, pair, control, outside, covariate)."""
    from chainid.gap.benchmark.odefamilies import world_cases

    cases = world_cases(small)
    named = [c for c in cases if c["family"] in ("single", "pair")]
    assert named and all(c["effects"] and all(lv > 0 for lv in c["effects"].values()) for c in named)
    assert {c["family"] for c in cases} == {"single", "pair", "control", "outside", "covariate"}
