"""Issue 20 §5: behaviours of the gap package that the mutation runs found unpinned (seed 22 and own seeds).

Each test checks a documented behaviour against a hand computation or the documented contract; the expensive
parts (simulation, diagnosis) are replaced by recorders where the test is about what the benchmark hands them.
Units: mm, N, s.
"""
from __future__ import annotations

import math
import sys
from types import SimpleNamespace

import numpy as np
import pytest

from chainid.model.base import LinearModel


class _Stop(Exception):
    """Raised by a recorder to end a benchmark case once its call was seen."""


def _motion(n: int, fs: float, f: float) -> SimpleNamespace:
    t = np.arange(n) / fs
    w = 2 * np.pi * f
    return SimpleNamespace(t=t, x=2.0 + 0.1 * np.sin(w * t), xd=0.1 * w * np.cos(w * t),
                           xdd=-0.1 * w * w * np.sin(w * t))


def test_effect_snr_is_the_rms_added_force_over_the_pooled_noise_by_hand():
    from chainid.gap.benchmark_time import effect_snr

    # two records of whole periods (Σ ẋ = 0): a constant force C has no part along ẋ, so it counts in full;
    # a force proportional to ẋ is all along ẋ (the fitted viscous c absorbs it): 0
    m1, m2 = _motion(400, 100.0, 1.0), _motion(600, 200.0, 2.0)
    C, s1, s2 = 3.0, 2.0, 5.0

    def offset(t, x, xd, xdd, F):  # noqa: ANN001
        return F + C

    def viscous(t, x, xd, xdd, F):  # noqa: ANN001
        return F + 7.0 * xd

    snr = effect_snr([m1, m2], LinearModel(k=100.0, x_ref=0.0), [offset, viscous], 0.5, [s1, s2])
    want = math.sqrt((400 * C ** 2 + 600 * C ** 2) / (400 * s1 ** 2 + 600 * s2 ** 2))
    assert snr[0] == pytest.approx(want, rel=1e-9)
    assert snr[1] == pytest.approx(0.0, abs=1e-9)
    # no noise at all: 0, not a division by zero
    assert effect_snr([m1], LinearModel(k=100.0, x_ref=0.0), [offset], 0.5, [0.0]) == [0.0]


@pytest.mark.parametrize("direction", ["harmonic>random", "random>harmonic"])
def test_transfer_case_fits_on_one_set_and_scores_the_other(monkeypatch, direction):
    """The module docstring: ``harmonic>random`` fits on the 11 harmonic tests (3 held out) and scores on the
    random records; ``random>harmonic`` fits on the random records (one held out) and scores the harmonic set."""
    from chainid.gap.benchmark_time import run_case_transfer, time_grid

    seen = {}

    def recorder(records, holdout, model, **kw):  # noqa: ANN001
        seen.update(train=[r.test for r in records], holdout=list(holdout), validate=[r.test for r in kw["validate"]])
        raise _Stop

    monkeypatch.setattr(sys.modules["chainid.gap.diagnose"], "diagnose", recorder)
    case = next(c for c in time_grid(small=True) if c["excitation"] == "transfer") | {"direction": direction}
    row = run_case_transfer(case)
    assert row["verdict"].startswith("error: _Stop")
    harm, rand = [f"h{i}" for i in range(1, 12)], ["r1", "r2", "r3", "r4"]
    if direction == "harmonic>random":
        assert seen == {"train": harm, "holdout": ["h3", "h6", "h11"], "validate": rand}
    else:
        assert seen == {"train": rand, "holdout": [case["hold"]], "validate": harm}


def _harmonic_case(**kw):
    case = {"excitation": "harmonic", "family": "single", "truth": ["friction"], "effects": ["friction"],
            "levels": [2.0], "noise": 0.02, "chain": "14x50", "plan": "grid3x3", "seed": 5}
    return case | kw


def test_harmonic_case_noise_damping_and_holdout_by_hand(monkeypatch):
    """``run_case`` (harmonic): noise σ = noise × S with S the plan's median dynamic force k(x0)·A, the viscous
    loss ~2 % of k at the top frequency (Eq. 21's α5 = 0.02·k/ω_max), the friction level 0.1·level·S
    (``effect_spec``), three held-out tests (the 3rd, the middle one and the last)."""
    from chainid.chain.spec import default_chain
    from chainid.gap.benchmark import run_case
    from chainid.model.base import ChainModel
    from chainid.records import simulate as simulate_module

    nominal = ChainModel(default_chain())
    # grid3x3: ω ∈ {1, 2, 4} × A ∈ {0.1, 0.2, 0.3} at x0 = 2, plus (3, 2.2, 0.15) and (1.5, 1.8, 0.25)
    kx = {x0: float(nominal.stiffness(np.array([x0]))[0]) for x0 in (1.8, 2.0, 2.2)}
    dyn = sorted([kx[2.0] * A for A in (0.1, 0.2, 0.3) for _ in range(3)] + [kx[2.2] * 0.15, kx[1.8] * 0.25])
    S = dyn[5]  # the median of 11
    k = kx[2.0]  # median stiffness: 9 of the 11 tests are at x0 = 2
    seen = {}

    def sim(plan, model, law, **kw):  # noqa: ANN001
        seen.update(kw, law=law, plan=[p.test for p in plan])
        x = np.linspace(1.9, 2.1, 5)
        seen["added"] = kw["force_fn"](x, x, np.ones(5), 0 * x, np.zeros(5))  # sliding forward: + F_c
        raise _Stop

    monkeypatch.setattr(simulate_module, "simulate", sim)
    with pytest.raises(_Stop):
        run_case(_harmonic_case())
    assert seen["noise_F"] == pytest.approx(0.02 * S, rel=1e-12)
    assert seen["seed"] == 5 and seen["n_cycles"] == 8 and seen["samples_per_cycle"] == 256
    assert list(seen["law"].params) == pytest.approx([0, 0, 0, 0, 0.02 * k / 4.0], rel=1e-12)
    assert seen["added"] == pytest.approx(np.full(5, 0.1 * 2.0 * S), rel=1e-5)  # F_c = 0.1·level·S (6 digits)

    held = {}

    def sim2(plan, model, law, **kw):  # noqa: ANN001
        return [SimpleNamespace(test=p.test) for p in plan]

    def diag(records, holdout, model, **kw):  # noqa: ANN001
        held["ids"] = list(holdout)
        raise ValueError("boom")

    monkeypatch.setattr(simulate_module, "simulate", sim2)
    monkeypatch.setattr(sys.modules["chainid.gap.diagnose"], "diagnose", diag)
    row = run_case(_harmonic_case())
    assert held["ids"] == ["a3", "a6", "a11"]
    assert row["verdict"] == "error: ValueError: boom" and row["snr"] == math.inf and row["steps"] == []


# ---------------------------------------------------------------- stationarity: the pooling rule by hand

def _cycles(slope: float, n: int = 10) -> dict[str, np.ndarray]:
    t = np.arange(n, dtype=float)  # one cycle a second
    return {"t": t, "mean": slope * t, "a": np.zeros(n), "b": np.zeros(n), "xm": np.full(n, 2.0),
            "xa": np.full(n, 0.1)}


def _tests(slopes):
    return [SimpleNamespace(test=f"T{i}", sigma=1.0, cycles=_cycles(s)) for i, s in enumerate(slopes)]


def test_stationarity_a_trend_in_a_quarter_of_the_tests_by_hand():
    """Noise-free lines: the scatter is 0, so the standard error is the floor σ·sqrt(1/n) = 1 N (no cycle counts
    given: n = 1) over sqrt(Σ(t − t̄)²) = sqrt(82.5) for t = 0 … 9 s; slope 5 N/s: z = 5·sqrt(82.5) = 45.4,
    change 5·9 = 45 N.  One trending test in 4 is a quarter (non-stationary), one in 5 is not."""
    from chainid.gap import stationarity

    z = 5.0 * math.sqrt(82.5)
    res = stationarity.check(_tests([5.0, 0.0, 0.0, 0.0]))
    assert res["stationary"] is False
    assert res["z"] == pytest.approx(z, rel=1e-9)
    q = res["by_quantity"]["mean"]
    assert q["n_tests"] == 1 and q["max_z"] == pytest.approx(z, rel=1e-9)
    assert q["change_N"] == pytest.approx(math.sqrt(45.0 ** 2 / 4), rel=1e-9)  # RMS over the 4 tests: 22.5 N
    assert res["trend_change_N"] == pytest.approx(22.5, rel=1e-9)  # a and b flat: only the mean counts
    assert res["by_quantity"]["a"] == {"max_z": 0.0, "change_N": 0.0, "n_tests": 0}
    assert res["finding"].startswith(
        "non-stationary: the mean force trends over the cycles in 1 of 4 tests (change over the window 22.5 N "
        "RMS over tests, up to 45.4 standard errors)")
    assert [r["n_cycles"] for r in res["tests"]] == [10] * 4
    res5 = stationarity.check(_tests([5.0, 0.0, 0.0, 0.0, 0.0]))
    assert res5["stationary"] is True and res5["finding"].startswith("the force is stationary")
    assert res5["by_quantity"]["mean"]["change_N"] == pytest.approx(45.0 / math.sqrt(5), rel=1e-9)
    # two in 5 (ceil(0.25 · 5) = 2) is enough again
    assert stationarity.check(_tests([5.0, -5.0, 0.0, 0.0, 0.0]))["stationary"] is False


@pytest.mark.parametrize("z,stationary", [(3.9, True), (4.1, False)])
def test_stationarity_threshold_is_four_standard_errors(z, stationary):
    from chainid.gap import stationarity

    res = stationarity.check(_tests([z / math.sqrt(82.5)]))
    assert res["z"] == pytest.approx(z, rel=1e-9)
    assert res["stationary"] is stationary
    assert res["trend_change_N"] == pytest.approx(0.0 if stationary else 9 * z / math.sqrt(82.5), rel=1e-9)


def test_stationarity_floor_of_a_harmonic_amplitude_uses_the_cycle_counts():
    """A harmonic amplitude's floor is σ·sqrt(2/n) with n the mean samples per cycle: σ = 2 N, n = 50 →
    0.4 N; a slope 0.1 N/s of b over t = 0 … 9: z = 0.1·sqrt(82.5)/0.4."""
    from chainid.gap import stationarity

    cy = _cycles(0.0) | {"b": 0.1 * np.arange(10.0), "n": np.full(10, 50.0)}
    res = stationarity.check([SimpleNamespace(test="T", sigma=2.0, cycles=cy)])
    assert res["tests"][0]["b"]["z"] == pytest.approx(0.1 * math.sqrt(82.5) / 0.4, rel=1e-9)
    assert res["tests"][0]["b"]["change_N"] == pytest.approx(0.9, rel=1e-9)


def test_trend_uses_the_covariate_from_six_cycles_on():
    """y = 3·t + 10·cov exactly: with ≥ 6 cycles the covariate is fitted and the slope is 3 N/s exactly; with 5
    it is not (too few cycles for three coefficients and a scatter), and the slope is the plain line's."""
    from chainid.gap import stationarity

    cov = np.array([0.3, -0.1, 0.7, 0.2, -0.4, 0.5])
    for n in (5, 6):
        t, c = np.arange(n, dtype=float), cov[:n]
        y = 3.0 * t + 10.0 * c
        sl, se, chg = stationarity.trend(t, y, c)
        plain = float(np.polyfit(t, y, 1)[0])
        assert sl == pytest.approx(3.0 if n == 6 else plain, rel=1e-9, abs=1e-12)
        assert chg == pytest.approx(abs(sl) * (n - 1), rel=1e-12)
        if n == 5:
            assert plain != pytest.approx(3.0, rel=1e-3)  # the two readings differ
    assert stationarity.trend(np.arange(2.0), np.arange(2.0)) == (0.0, math.inf, 0.0)  # fewer than 3 cycles
    assert stationarity.trend(np.zeros(4), np.arange(4.0)) == (0.0, math.inf, 0.0)  # no time span
    none = stationarity.check(_tests([]) + [SimpleNamespace(test="S", sigma=1.0, cycles=_cycles(1.0, n=3))])
    assert none["stationary"] is None
    assert none["finding"] == "stationarity not checked: no test has >= 4 whole steady cycles"


# ---------------------------------------------------------------- damping law choice

def test_law_choice_leave_one_out_errors_and_ties_by_hand():
    """c_e = 0.5 + noise-free scatter d_i: the viscous law's LOO prediction of test i is the mean of the others,
    so its error is n/(n − 1)·(c_i − c̄) and its LOO RMS n/(n − 1)·std(c).  A Coulomb-exact set
    c = 4·F_f/(π·ω·A) is fitted with zero error by coulomb and by viscous+coulomb: the tie goes to the law with
    fewer coefficients."""
    from chainid.gap.law_choice import choose

    w = np.array([1.0, 2.0, 4.0, 1.0, 2.0, 4.0, 3.0])
    A = np.array([0.1, 0.1, 0.1, 0.3, 0.3, 0.3, 0.2])
    ke = np.full(7, 5000.0)
    c = 0.5 + np.array([0.01, -0.02, 0.03, 0.0, -0.01, 0.02, -0.03])
    best, errs = choose(w, A, ke, c, ["viscous"])
    assert best == "viscous" and errs["viscous"] == pytest.approx(7 / 6 * np.std(c), rel=1e-9)
    cc = 4 * 20.0 / (np.pi * w * A)
    best, errs = choose(w, A, ke, cc, ["viscous+coulomb", "viscous", "coulomb", "hysteretic"])
    assert best == "coulomb" and errs["coulomb"] < 1e-9 and errs["viscous+coulomb"] < 1e-9
    assert errs["viscous"] > 10 and errs["hysteretic"] > 1  # c spans 21 … 255 N·s/mm
    ch = 0.02 * ke / w  # structural, eta = 0.02
    assert choose(w, A, ke, ch, ["viscous", "coulomb", "hysteretic", "viscous+hysteretic"])[0] == "hysteretic"
    with pytest.raises(ValueError, match="no damping law has fewer coefficients than the training tests"):
        choose(w, A, ke, c, [])


# ---------------------------------------------------------------- verdict: drift and bounds (module docstring)

def _nonstat(change):
    return {"stationary": False, "trend_change_N": change, "finding": "non-stationary: X"}


def test_verdict_a_drift_of_a_quarter_of_the_residual_is_unexplained():
    """`unexplained` when what is left drifts by at least NONSTAT_FRACTION = 1/4 of the baseline's systematic
    residual (8 N here: 2 N is the limit); a smaller drift keeps the named chain with a warning; the finding goes
    first in `where`."""
    from chainid.gap import verdict as vd

    final = SimpleNamespace(names=("friction",), shrinkage=0.8, at_bound=())
    for change, want in ((2.0, "unexplained"), (1.99, "friction")):
        where, warn = [{"finding": "old"}], []
        v = vd.decide(False, final, _nonstat(change), 8.0, [None, final], {"stop": "S"}, where, warn)
        assert v == want
        assert where[0] == {"finding": "non-stationary: X", "kind": "nonstationary", "trend_change_N": change,
                            "score": change} and where[1] == {"finding": "old"}
        msg = ("non-stationary: X; the static effects friction absorb part of it, but what is left drifts with "
               "time")
        if want == "unexplained":
            msg += " (trend change 2 N over the window vs systematic residual 8 N: no confident name)"
        assert warn == [msg]
    # no chain: the drift is all there is
    warn = []
    assert vd.decide(False, None, _nonstat(0.1), 8.0, [None], {"stop": "S"}, [], warn) == "unexplained"
    assert warn == ["non-stationary: X; no static effect can explain it"]
    # the baseline at the noise floor: `none`, no drift warning (the finding is still listed)
    warn, where = [], []
    assert vd.decide(True, final, _nonstat(5.0), 8.0, [None, final], {"stop": "S"}, where, warn) == "none"
    assert warn == [] and where[0]["kind"] == "nonstationary"


def test_verdict_warns_of_each_step_with_a_parameter_at_its_bound():
    from chainid.gap import verdict as vd

    s1 = SimpleNamespace(name="friction", at_bound=("friction.x_s",))
    s2 = SimpleNamespace(name="slack", at_bound=())
    s3 = SimpleNamespace(name="backlash", at_bound=("backlash.b", "backlash.k"), names=("friction", "slack",
                         "backlash"), shrinkage=0.9)
    warn = []
    stat = {"stationary": True, "trend_change_N": 0.0, "finding": ""}
    assert vd.decide(False, s3, stat, 1.0, [s1, s1, s2, s3], {"stop": "S"}, [], warn) == "friction+slack+backlash"
    tail = ("at the bound of their physical range; the effect's form may not match the data there (read the value "
            "as a limit, not an estimate)")
    # path[0] is the baseline: not warned about even if it had a bound
    assert warn == [f"friction: parameter(s) friction.x_s {tail}", f"backlash: parameter(s) backlash.b, backlash.k {tail}"]


# ---------------------------------------------------------------- interpret: the engineer's words

def test_step_texts_by_hand():
    from chainid.gap.interpret import step_text

    assert step_text({"effect": "baseline", "params": {}, "nrmse_holdout": 0.12345}) == \
        "baseline [held-out NRMSE 0.123]"
    assert step_text({"effect": "baseline", "params": {}, "nrmse_holdout": None}) == "baseline"
    # scale 0.79: −21 %; its sd 0.0123 → 2 significant digits
    assert step_text({"effect": "stiffness_level", "params": {"stiffness_level.scale": 0.79},
                      "params_sd": {"stiffness_level.scale": 0.0123}}) == "stiffness level -21 % (EA × 0.79 ± 0.012)"
    assert step_text({"effect": "contact_law", "params": {"contact_law.scale": 1.5, "contact_law.beta": 0.5}}) == \
        "contact law: Hertz compliance × 1.5, exponent 0.5 (Hertz 0.667)"
    # units per parameter; a zero, infinite or missing sd is not shown; other effects' parameters left out
    txt = step_text({"effect": "friction", "params": {"friction.F_c": 150.04, "friction.mu": 0.012,
                                                       "slack.s": 0.3},
                     "params_sd": {"friction.F_c": 0.0, "friction.mu": float("inf")}, "nrmse_holdout": 0.05})
    assert txt == "friction F_c = 150 N, mu = 0.012 [held-out NRMSE 0.05]"
    assert step_text({"effect": "sensor_delay", "params": {"sensor_delay.tau": 0.0021},
                      "params_sd": {"sensor_delay.tau": 0.0001}}) == "sensor_delay tau = 0.0021 ± 0.0001 s"
    assert step_text({"effect": "slack", "params": {"slack.s": None}}) == "slack s = ? mm"


def test_mechanism_joins_families_once_and_separating_test_of_stiffness_pairs():
    from chainid.gap.interpret import mechanism, separating_test

    assert mechanism("stiffness_level+machine_compliance+sensor_delay", "") == "stiffness+instrumentation"
    assert mechanism("friction+hysteresis", "Dahl friction (x_h << A)") == "friction"
    assert mechanism("damping_law+backlash", "") == "damping form+play"
    assert separating_test("slack", "contact_law").startswith("tests over a wider mean-load range x0")
    assert separating_test("damping_law", "backlash").startswith("tests over a wider amplitude range at fixed ω")
    assert separating_test("friction", "backlash").startswith("tests over a wider amplitude range at fixed ω")


def test_interpretation_dahl_and_stiffness_level_by_hand():
    """Dahl friction when x_h < A_min/2; a stiffness level s on a model with a linear coefficient c_lin [mm/N] is
    a series compliance c_lin·(1/s − 1)."""
    from chainid.gap.interpret import interpretation

    prob = SimpleNamespace(data=[SimpleNamespace(A=0.3), SimpleNamespace(A=0.1)],
                           model=SimpleNamespace(coefficients=[2e-5, 1.0]))
    base = SimpleNamespace(names=(), params={})
    fin = SimpleNamespace(names=("hysteresis",), params={"hysteresis.x_h": 0.0499})
    assert interpretation([base, fin], prob, "hysteresis") == (
        "Dahl-type hysteresis with transition travel x_h = 0.0499 mm << A (>= 0.1 mm): rate-independent "
        "frictional sliding with smooth pre-sliding (Dahl friction)")
    assert interpretation([base, SimpleNamespace(names=("hysteresis",), params={"hysteresis.x_h": 0.05})],
                          prob, "hysteresis") == ""  # x_h = A_min/2 is not << A
    assert interpretation([base], prob, "none") == ""
    lvl = SimpleNamespace(names=("stiffness_level",), params={"stiffness_level.scale": 0.8})
    # 2e-5 · (1/0.8 − 1) = +5e-6 mm/N; 20 % softer
    assert interpretation([base, lvl], prob, "stiffness_level") == (
        "the chain is 20 % softer in its linear (bar) term than the derivation; equivalently a series compliance "
        "of +5e-06 mm/N (test machine, fixtures, a larger contact flattening)")
    up = SimpleNamespace(names=("stiffness_level",), params={"stiffness_level.scale": 1.25})
    assert "25 % stiffer" in interpretation([base, up], prob, "x") and "-4e-06 mm/N" in interpretation(
        [base, up], prob, "x")
    lin = SimpleNamespace(data=prob.data, model=SimpleNamespace())  # no coefficients: a linear spring
    assert interpretation([base, lvl], lin, "stiffness_level") == ""


def test_step_dict_is_the_json_contract_of_a_step():
    from chainid.gap.interpret import step_dict

    c = SimpleNamespace(names=("friction", "slack"), params={"spring.k": 1.0, "friction.F_c": 3.0, "slack.s": 0.1},
                        param_sd={"friction.F_c": float("nan"), "slack.s": 0.01, "spring.k": 0.5}, law="viscous",
                        nrmse_loto=0.1, nrmse_holdout=float("inf"), shrinkage=0.7, db_holdout=3.0,
                        step_test={"z": 4.5, "relative_gain": 0.3}, at_bound=("slack.s",))
    assert step_dict(c, 2) == {
        "effect": "slack", "effects": ("friction", "slack"), "params": {"friction.F_c": 3.0, "slack.s": 0.1},
        "params_sd": {"friction.F_c": None, "slack.s": 0.01}, "damping_law": "viscous", "nrmse_loto": 0.1,
        "nrmse_holdout": None, "shrinkage": 0.7, "db_over_noise": 3.0, "z_loto": 4.5, "relative_gain_loto": 0.3,
        "at_bound": ["slack.s"]}
    c.step_test = {}
    d = step_dict(c, 0)
    assert d["effect"] == "baseline" and d["z_loto"] is None and d["relative_gain_loto"] is None


# ---------------------------------------------------------------- summary: the terminal text and the JSON contract

def _summary_result(**kw):
    step0 = {"effect": "baseline", "nrmse_loto": 0.2, "nrmse_holdout": 0.25, "shrinkage": None,
             "db_over_noise": 12.34, "params": {}, "params_sd": {}}
    step1 = {"effect": "friction", "nrmse_loto": 0.05, "nrmse_holdout": 0.04, "shrinkage": 0.84,
             "db_over_noise": 1.0, "params": {"friction.F_c": 150.04, "spring.k": 3.0, "law.a": 1.0,
                                              "friction.x_s": None, "friction.mu": 0.0123},
             "params_sd": {"friction.F_c": 3.21}, "at_bound": ["friction.mu"]}
    res = {"baseline": {"model": "chain", "damping_law": "polynomial", "nrmse_train": 0.1, "nrmse_holdout": 0.25,
                        "db_over_noise": 12.34, "excess_rms_N": 50.0, "noise_sigma_N": 4.0},
           "where": [{"finding": f"w{i}"} for i in range(10)],
           "ranking": [{"effect": f"e{i}", "nrmse_loto": 0.1 * i, "nrmse_holdout": 0.2, "shrinkage": 0.5,
                        "params": {f"e{i}.p": 1.5}} for i in range(8)],
           "confounded": [{"pair": ["friction", "hysteresis"], "separate_by": "a small test"}],
           "excluded": [{"test": "7", "reason": "not steady"}],
           "steps": [step0, step1], "stop": "no further effect shrinks it", "verdict": "friction",
           "chain_text": "baseline → friction", "residual": {"db_over_noise": 1.04, "stationary": True},
           "interpretation": "dry sliding", "mechanism": "friction", "warnings": ["w!"]}
    return res | kw


def test_summary_text_by_hand():
    from chainid.gap.summary import summary

    lines = summary(_summary_result(), n_rank=3).splitlines()
    assert lines[0] == ("Baseline (chain, damping law: polynomial): NRMSE train 0.1, held-out 0.25 (12.3 dB over the "
                        "noise floor; systematic 50 N vs noise σ 4 N)")
    assert lines[1] == "  excluded test 7: not steady"
    assert lines[3:5] == ["WHERE the model misses (largest first):", "  - w0"]
    assert "  - w7" in lines and "  - w8" not in lines  # the first 8 findings
    assert "WHICH effects, in order (each fitted on top of the previous ones; scored leave-one-test-out):" in lines
    i = lines.index("WHICH effects, in order (each fitted on top of the previous ones; scored leave-one-test-out):")
    assert lines[i + 2] == f"  {0:<5} {'baseline':<20} {0.2:>8.4g} {0.25:>9.4g} {0.0:>6.1f}% {12.34:>8.1f}  "
    # spring.*, law.* and None parameters are not shown; sd with 2 digits; a bound marked
    assert lines[i + 3].endswith("  friction.F_c=150±3.2, friction.mu=0.0123 (at bound)")
    assert f"{84.0:>6.1f}%" in lines[i + 3]
    assert lines[i + 4] == "  left: 1.0 dB over the noise floor; stationary"
    assert lines[i + 5] == "  the chain stops: no further effect shrinks it"
    assert sum(".p=1.5" in ln for ln in lines) == 3  # n_rank
    assert "  confounded: friction ~ hysteresis; to separate them: a small test" in lines
    assert "VERDICT: friction — baseline → friction" in lines
    assert "  held-out NRMSE 0.25 → 0.04 (shrinkage 84 %)" in lines
    assert lines[-3:] == ["  meaning: dry sliding", "  mechanism: friction", "WARNING: w!"]


def test_summary_route_residual_and_unexplained_texts():
    from chainid.gap.summary import summary, waterfall

    txt = summary(_summary_result(route="time", verdict="unexplained", left_nrmse_holdout=0.123456,
                                  mechanism="unexplained", interpretation="", warnings=[]))
    assert "scored leave-one-block/test-out):" in txt
    assert txt.splitlines()[-1] == ("VERDICT: unexplained — no library effect passed the step rule or shrinks the "
                                    "held-out gap by half; held-out NRMSE left 0.1235.")
    assert "mechanism:" not in txt and "meaning:" not in txt
    assert "scored leave-one-block/test-out" in summary(_summary_result(route="mixed"))
    assert "scored leave-one-test-out" in summary(_summary_result(route="phase"))
    drift = summary(_summary_result(verdict="unexplained", left_nrmse_holdout=0.2,
                                    residual={"db_over_noise": 0.0, "stationary": False, "at_noise_floor": True}))
    assert ("VERDICT: unexplained — what is left changes with time within the tests (no static effect explains "
            "that); held-out NRMSE left 0.2.") in drift
    assert waterfall({"steps": [], "residual": {"db_over_noise": 0.04, "stationary": False,
                                                "at_noise_floor": True}})[1] == \
        "  left: 0.0 dB over the noise floor (at the floor); NOT stationary"
    assert waterfall({"steps": [], "residual": {"db_over_noise": 2.0, "stationary": None}})[1] == \
        "  left: 2.0 dB over the noise floor; stationarity not checked"
    assert len(waterfall({"steps": []})) == 1  # no residual: the header only
    # a named verdict without steps falls back on the best candidate
    best = {"nrmse_holdout": 0.1, "shrinkage": 0.6}
    assert "  held-out NRMSE 0.25 → 0.1 (shrinkage 60 %)" in summary(_summary_result(steps=[], best=best))


def test_to_json_drops_private_keys_and_non_finite_numbers():
    from chainid.gap.summary import to_json

    res = {"a": np.float64(1.5), "_problem": object(), "b": [np.int64(3), float("nan"), (float("inf"), 2.0)],
           "c": {"_x": 1, "y": np.float32(0.5)}, 4: "four"}
    assert to_json(res) == {"a": 1.5, "b": [3, None, [None, 2.0]], "c": {"y": 0.5}, 4: "four"}
    assert type(to_json(res)["b"][0]) is int and type(to_json(res)["c"]["y"]) is float  # numpy → Python


# ---------------------------------------------------------------- transfer: pooling and the transfer rule by hand

def _fake_scores(monkeypatch, model_r2):
    """Per (candidate, record) SSEs: baseline b, model m, after the linear refit br/mr, variance v; the model's
    squared residual r2 against the noise floor f2 over n samples of σ = 1 N."""
    from chainid.gap import transfer as tr

    table = {("r1", "base"): (100.0, 64.0), ("r1", "final"): (16.0, 25.0),
             ("r2", "base"): (300.0, 100.0), ("r2", "final"): (20.0, 20.0)}
    var = {"r1": 400.0, "r2": 600.0}

    def score(prob, cand, rec, n_bins, steady_tol):  # noqa: ANN001
        sse, sse_r = table[(rec.test, cand.tag)]
        return {"route": "time" if rec.test == "r1" else "harmonic", "sse": sse, "sse_refit": sse_r,
                "var": var[rec.test], "r2": model_r2[rec.test], "f2": 100.0, "n": 100, "sigma": 1.0}

    monkeypatch.setattr(tr, "_score", score)
    base = SimpleNamespace(names=(), tag="base")
    final = SimpleNamespace(names=("friction", "slack"), tag="final")
    recs = [SimpleNamespace(test="r1"), SimpleNamespace(test="r2")]
    return tr, base, final, recs


def test_transfer_pooled_numbers_and_rule_by_hand(monkeypatch):
    """Per record NRMSE = sqrt(SSE/var); pooled over records sqrt(ΣSSE/Σvar): baseline sqrt(400/1000), model
    sqrt(36/1000) (shrinkage 1 − sqrt(36/400) = 0.7); refit sqrt(164/1000) → sqrt(45/1000) (shrinkage
    1 − sqrt(45/164) = 0.476 < 0.5).  The model leaves r2/f2 = (4000/200)/(200/200) = 20 (13.0 dB, not at the
    floor): it does NOT transfer.  At its noise floor (r2 = f2) the same numbers transfer."""
    tr, base, final, recs = _fake_scores(monkeypatch, {"r1": 1000.0, "r2": 3000.0})
    out = tr.transfer({"_problem": None, "_path": [base, final]}, recs)
    r1 = out["tests"][0]
    assert r1["test"] == "r1" and r1["route"] == "time"
    assert (r1["nrmse_baseline"], r1["nrmse_model"]) == (pytest.approx(0.5), pytest.approx(0.2))
    assert (r1["nrmse_baseline_refit"], r1["nrmse_model_refit"]) == (pytest.approx(0.4), pytest.approx(0.25))
    assert (r1["shrinkage"], r1["shrinkage_refit"]) == (pytest.approx(0.6), pytest.approx(0.375))
    p = out["pooled"]
    assert p["nrmse_baseline"] == pytest.approx(math.sqrt(0.4)) and p["nrmse_model"] == pytest.approx(math.sqrt(0.036))
    assert p["shrinkage"] == pytest.approx(0.7)
    assert p["shrinkage_refit"] == pytest.approx(1 - math.sqrt(45 / 164))
    assert p["model_db_over_noise"] == pytest.approx(10 * math.log10(20.0))
    assert p["model_at_noise_floor"] is False and out["transfers"] is False and out["chain"] == "friction+slack"
    assert out["verdict_text"] == (
        "the chain friction+slack does NOT transfer to the other set (2 harmonic/time record(s)): pooled NRMSE "
        "baseline 0.632 → model 0.19 (shrinkage 70 %); with offset, stiffness and viscous term refitted per record "
        "0.405 → 0.212 (shrinkage 48 %); the model leaves 13.0 dB over the other set's noise; it transfers when the "
        "first reaches 50 % and the second does too or the model is at the noise floor")
    tr, base, final, recs = _fake_scores(monkeypatch, {"r1": 100.0, "r2": 100.0})
    out = tr.transfer({"_problem": None, "_path": [base, final]}, recs)
    assert out["pooled"]["model_at_noise_floor"] is True and out["transfers"] is True
    assert "TRANSFERS" in out["verdict_text"] and "noise (at its noise floor)" in out["verdict_text"]


def test_transfer_without_a_named_effect_and_without_records(monkeypatch):
    tr, base, final, recs = _fake_scores(monkeypatch, {"r1": 100.0, "r2": 100.0})
    out = tr.transfer({"_problem": None, "_path": [base]}, recs)
    assert out["transfers"] is False and out["chain"] == "baseline"
    assert out["pooled"]["shrinkage"] == 0.0  # the model is the baseline
    assert out["verdict_text"] == ("no effect was named on the fitting set; on the other set the baseline leaves "
                                   "NRMSE 0.632 (0.405 after the linear refit)")
    with pytest.raises(ValueError, match="--validate: the other set has no records"):
        tr.transfer({"_problem": None, "_path": [base, final]}, [])


def test_transfer_refit_removes_offset_stiffness_and_viscous_terms():
    """F − F_model = 3 + 2·x − 0.5·ẋ + e with e orthogonal to 1, x, ẋ: the refit leaves e (weights 1)."""
    from chainid.gap import transfer as tr

    n = 64
    psi = 2 * np.pi * np.arange(n) / n
    x, v = np.sin(psi), np.cos(psi)
    e = np.sin(3 * psi)  # orthogonal to 1, sin ψ, cos ψ over whole periods
    Fm = np.linspace(0, 1, n)
    np.testing.assert_allclose(tr._refit(Fm + 3 + 2 * x - 0.5 * v + e, Fm, x, v), e, atol=1e-12)
    np.testing.assert_allclose(tr._refit(Fm + 3 + 2 * x - 0.5 * v + e, Fm, x, v, np.ones(n)), e, atol=1e-12)


# ---------------------------------------------------------------- problem: parameter keys and bounds

def test_problem_keys_spring_bounds_and_no_damping_law_parameters_by_hand():
    """A linear baseline re-fits its spring: k in [0, max(10·k0, 10·F_scale/x_scale)], x_ref within ± 2·x_scale;
    ``damping_law`` has no fitted effect parameters (its law coefficients are the damping fit's), also when its
    name is a string built at run time (read from a command line), not the interned literal."""
    from chainid.gap.problem import Problem
    from chainid.model.effects import EFFECT_NAMES, make_effect

    effects = {n: make_effect(n, 100.0, 0.5, 10.0) for n in EFFECT_NAMES}
    fake = SimpleNamespace(_spring_start=lambda: {"spring.k": 30.0, "spring.x_ref": 1.0}, x_scale=0.5,
                           F_scale=100.0, effects=effects)
    law = "".join(["damping", "_law"])
    keys, lo, hi, x0 = Problem._keys(fake, [law, "friction"])
    fr = effects["friction"]
    assert keys == ["spring.k", "spring.x_ref"] + [f"friction.{k}" for k in fr.param_names]
    # 10·k0 = 300 < 10·F/x = 2000
    assert lo[:2] == [0.0, 1.0 - 2 * 0.5] and hi[:2] == [2000.0, 1.0 + 2 * 0.5] and x0[:2] == [30.0, 1.0]
    assert lo[2:] == [b[0] for b in fr.bounds] and hi[2:] == [b[1] for b in fr.bounds]
    assert x0[2:] == list(fr.x0_guess)
    fake.effects, fake.F_scale = effects, 1.0  # 10·k0 = 300 > 10·1/0.5 = 20
    assert Problem._keys(fake, [])[2] == [300.0, 2.0]
    fake._spring_start = lambda: {}  # a chain baseline: no spring parameters
    assert Problem._keys(fake, [law]) == ([], [], [], [])


# ---------------------------------------------------------------- benchmark report: transfer and non-harmonic texts

def _trow(direction, verdict, sh, shr, ok, truth=("friction",)):
    return {"excitation": "transfer", "family": "transfer", "direction": direction, "truth": list(truth),
            "verdict": verdict, "transfer_shrinkage": sh, "transfer_shrinkage_refit": shr, "transfers": ok,
            "transfer_chain": verdict, "seed": 1, "snr": 9.0, "shrinkage": 0.9, "seconds": 1.0}


def test_transfer_rates_by_hand():
    from chainid.gap.benchmark_report import transfer_rates

    rows = [_trow("harmonic>random", "friction", 0.8, 0.6, True), _trow("harmonic>random", "hysteresis", 0.2, None, False),
            _trow("random>harmonic", "friction", None, None, False),
            _trow("random>harmonic", "machine_compliance", 0.9, 0.7, True, truth=("stiffness_level",))]
    t = transfer_rates(rows)
    assert t["n"] == 4
    assert t["median_shrinkage"] == pytest.approx(0.8)  # of 0.8, 0.2, 0.9 (None left out)
    assert t["median_shrinkage_refit"] == pytest.approx(0.65)  # of 0.6, 0.7
    assert t["transfers_rate"] == 0.5
    assert t["fit_right_rate"] == 0.75  # machine_compliance reads as stiffness_level
    h, r = t["by_direction"]["harmonic>random"], t["by_direction"]["random>harmonic"]
    assert (h["n"], h["median_shrinkage"], h["median_shrinkage_refit"], h["transfers_rate"]) == (2, 0.5, 0.6, 0.5)
    assert (r["n"], r["median_shrinkage"], r["fit_right_rate"]) == (2, 0.9, 1.0)
    assert list(t["by_direction"]) == ["harmonic>random", "random>harmonic"]
    assert t["rows"][2] == {"direction": "random>harmonic", "truth": ["friction"], "verdict": "friction",
                            "transfer_chain": "friction", "transfer_shrinkage": None,
                            "transfer_shrinkage_refit": None, "transfers": False, "seed": 1}
    empty = transfer_rates([])
    assert empty["n"] == 0 and empty["median_shrinkage"] is None and empty["transfers_rate"] is None


def _row(exc, family, truth, verdict, snr=9.0, **kw):
    return {"excitation": exc, "family": family, "truth": truth, "verdict": verdict, "snr": snr, "shrinkage": 0.8,
            "seconds": 2.0, "chain": "c", "plan": exc, "noise": 0.01, "levels": [1.0], "seed": 7} | kw


def test_summarise_splits_excitations_and_formats_the_non_harmonic_lines():
    """Harmonic rows at the top level; each non-harmonic excitation apart and pooled; transfer apart; the
    terminal lines say each rate with its n, PASS/MISS against issue 18's targets and the misses."""
    from chainid.gap.benchmark_report import format_summary, summarise

    rows = [_row("harmonic", "single", ["friction"], "friction"),
            _row("random", "single", ["friction"], "friction"), _row("random", "single", ["slack"], "backlash"),
            _row("sweep", "single", ["friction"], "friction"), _row("sweep", "control", [], "none", snr=0.5),
            _row("sweep", "outside", ["chatter"], "friction", truth_named=["friction"], chatter=True),
            _trow("harmonic>random", "friction", 0.8, 0.6, True)]
    s = summarise(rows)
    assert (s["n_cases"], s["harmonic_n"]) == (7, 1)
    assert s["single_right_rate"] == 1.0 and s["single_n"] == 1  # the harmonic one only
    assert sorted(s["by_excitation"]) == ["random", "sweep"]
    assert s["by_excitation"]["random"]["single_right_rate"] == 0.5
    nh = s["nonharmonic"]
    assert (nh["single_right_rate"], nh["single_n"], nh["control_none_rate"]) == (2 / 3, 3, 1.0)
    assert s["transfer"]["n"] == 1 and s["rows"] is rows
    txt = format_summary(s | {"wall_seconds": 12.4})
    lines = txt.splitlines()
    assert "non-harmonic excitations (residual >= 3x noise; n in brackets):" in lines
    i = lines.index("non-harmonic excitations (residual >= 3x noise; n in brackets):")
    assert lines[i + 2] == (f"{'random':<12}{'50.0 % (2)':>14}{'n/a (0)':>14}{'n/a (0)':>14}{'n/a (0)':>14}"
                            f"{'n/a (0)':>14}{'n/a':>10}")
    assert lines[i + 3].startswith("sweep") and lines[i + 3].endswith(f"{'100.0 %':>10}")
    assert lines[i + 4].startswith(f"{'pooled':<12}{'66.7 % (3)':>14}")
    assert ("  MISS: non-harmonic single_right_rate = 66.7 % (target >= 90 %)") in lines
    assert ("  PASS: non-harmonic control_none_rate = 100.0 % (target >= 95 %)") in lines
    assert "  MISS: non-harmonic compound_both_named_rate = n/a (target >= 80 %)" in lines
    assert "  1 non-harmonic miss(es), e.g.:" in lines
    assert "    random single: truth slack -> backlash (snr 9.0, seed 7)" in lines
    assert ("transfer (1 cases): median pooled shrinkage on the other set 80.0 % (target >= 70 %: PASS); after a "
            "per-record refit of offset, spring and dashpot 60.0 %; verdict 'transfers' 100.0 %; true effect named "
            "on the fitting set 100.0 %") in lines
    assert "  harmonic>random: 1 cases, median shrinkage 80.0 %, after refit 60.0 %, transfers 100.0 %" in lines
    assert "median diagnosis time 2.00 s over 7 cases; wall 12 s" in lines
    assert "  PASS: single_right_rate = 100.0 % (target >= 92 %)" in lines
    assert "  MISS: compound_both_named_rate = n/a (target >= 85 %)" in lines


def test_format_summary_without_harmonic_rows_and_with_errors():
    from chainid.gap.benchmark_report import format_summary, summarise

    rows = [_row("quake", "single", ["friction"], "error: ValueError: boom"),
            _row("quake", "single", ["friction"], "friction")]
    txt = format_summary(summarise(rows) | {"wall_seconds": 3.0})
    lines = txt.splitlines()
    assert lines[0] == "2 cases; wall 3 s"
    assert "harmonic families:" not in txt
    assert lines[-1] == "1 case(s) raised an error (counted as misses), e.g. error: ValueError: boom"
    assert format_summary(summarise(rows)).splitlines()[0] == "2 cases"


def test_format_summary_confusion_matrix_and_misses():
    from chainid.gap.benchmark_report import format_summary, summarise

    rows = [_row("harmonic", "single", ["friction"], "friction"),
            _row("harmonic", "single", ["machine_compliance"], "hysteresis+slack"),
            _row("harmonic", "control", [], "none", snr=0.1),
            _row("harmonic", "single", ["backlash"], "error: RuntimeError: x")]
    lines = format_summary(summarise(rows)).splitlines()
    i = lines.index("confusion (rows: truth of single / mismatch / control cases; columns: verdict)")
    cols = ["(combination)", "error: RuntimeError: x", "friction", "none"]
    w = len("error: RuntimeError: x") + 1  # the widest column label + 1 (>= 8)
    assert lines[i + 1] == " " * 22 + "".join(f"{c[:w - 1]:>{w}}" for c in cols)
    assert lines[i + 2] == f"{'backlash':<22}" + "".join(f"{n:>{w}}" for n in (0, 1, 0, 0))
    assert lines[i + 4] == f"{'machine_compliance':<22}" + "".join(f"{n:>{w}}" for n in (1, 0, 0, 0))
    assert "1 case(s) raised an error (counted as misses), e.g. error: RuntimeError: x" in "\n".join(lines)
    assert "2 miss(es), e.g.:" in lines
    assert "  single: truth machine_compliance -> hysteresis+slack (snr 9.0, c, harmonic, noise 0.01)" in lines


# ---------------------------------------------------------------- the benchmark grid against its documentation

def test_benchmark_grid_is_the_documented_one():
    """README (Sim-to-real gap; the gap on any excitation): 480 cases, 328 harmonic, 140 non-harmonic, 12 transfer;
    every library effect alone at 3 strengths × 2 noise levels × 2 chains × 2 plans; 24 controls; mismatch
    EA × 0.7–1.4, Hertz compliance × 0.5–2; non-harmonic strengths log-uniform 0.5–3×, noise 0.5–3 %; transfer
    both directions, six effects; case seeds seed + 100000 + 1000·k + i (module docstring of time_grid)."""
    from chainid.gap.benchmark import ALL_EXCITATIONS, grid
    from chainid.gap.benchmark_time import EXCITATIONS
    from chainid.model.effects import EFFECT_NAMES

    g = grid(seed=3)
    ex = [c["excitation"] for c in g]
    assert (len(g), ex.count("harmonic"), ex.count("transfer")) == (480, 328, 12)
    harm = [c for c in g if c["excitation"] == "harmonic"]
    singles = [c for c in harm if c["family"] == "single"]
    for e in EFFECT_NAMES:
        mine = [c for c in singles if c["effects"] == [e]]
        assert len(mine) == 3 * 2 * 2 * 2
        assert len({(c["levels"][0], c["noise"], c["chain"], c["plan"]) for c in mine}) == 24
    assert sum(c["family"] == "control" for c in harm) == 24
    mism = [c for c in harm if c["family"] == "mismatch"]
    ea = sorted({c["ea_scale"] for c in mism if "ea_scale" in c})
    hz = sorted({c["hertz_scale"] for c in mism if "hertz_scale" in c})
    assert (ea[0], ea[-1], hz[0], hz[-1]) == (0.7, 1.4, 0.5, 2.0)
    assert [c["seed"] for c in harm] == list(range(4, 4 + 328))  # seed + 1, + 2, …: one per case
    order = EXCITATIONS + ("transfer",)
    for e in order:
        mine = [c for c in g if c["excitation"] == e]
        assert [c["seed"] for c in mine] == [3 + 100000 + 1000 * order.index(e) + i for i in range(len(mine))]
    timed = [c for c in g if c["excitation"] in EXCITATIONS]
    assert all(0.5 <= lv <= 3.0 for c in timed for lv in c["levels"])
    assert all(0.005 <= c["noise"] <= 0.03 for c in timed)
    assert all(c["hold"] in ("r1", "r2", "r3", "r4") for c in timed)
    tr = [c for c in g if c["excitation"] == "transfer"]
    assert sorted((c["effects"][0], c["direction"]) for c in tr) == sorted(
        (e, d) for e in ("friction", "hysteresis", "backlash", "stiffness_level", "slack", "sensor_delay")
        for d in ("harmonic>random", "random>harmonic"))
    # a case is the same whichever excitations run
    assert grid(seed=3, excitations=("sweep",)) == [c for c in g if c["excitation"] == "sweep"]
    assert grid(seed=3, excitations=("harmonic",)) == harm
    assert tuple(ALL_EXCITATIONS) == ("harmonic",) + order
    with pytest.raises(ValueError, match=r"--excitations 'harmonic,wind': unknown \['wind'\]; valid: "
                                         "harmonic,random,sweep,startup,quake,transfer"):
        grid(excitations=("harmonic", "wind"))
    with pytest.raises(ValueError, match=r"--excitations '': unknown empty"):
        grid(excitations=())


def test_small_grids_one_case_per_family():
    """The small subset (tests): harmonic — friction and stiffness_level alone, a control, a mismatch, a mismatch
    plus friction and one pair; non-harmonic — one single-effect case per family, one control, one transfer."""
    from chainid.gap.benchmark import grid

    g = grid(small=True)
    fam = [(c["excitation"], c["family"], tuple(c["effects"])) for c in g]
    assert fam[:6] == [("harmonic", "single", ("friction",)), ("harmonic", "single", ("stiffness_level",)),
                       ("harmonic", "control", ()), ("harmonic", "mismatch", ()),
                       ("harmonic", "mismatch+", ("friction",)),
                       ("harmonic", "pair", ("friction", "sensor_delay"))]
    assert fam[6:] == [("random", "single", ("friction",)), ("sweep", "single", ("hysteresis",)),
                       ("startup", "single", ("backlash",)), ("quake", "single", ("stiffness_level",)),
                       ("random", "control", ()), ("transfer", "transfer", ("hysteresis",))]


# ---------------------------------------------------------------- modelio.predict by hand (time-domain records)

def test_predict_time_domain_nrmse_and_pooling_by_hand():
    """Two ramps (not harmonic tests: predicted in the time domain), F = 100·x + e measured; the model is the
    100 N/mm spring, its baseline an 80 N/mm one (no damping, no mass).  NRMSE = sqrt(SSE/Σ(F − F̄)²) per test,
    pooled over the tests' sums; shrinkage 1 − model/baseline."""
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
        var = float(np.sum((F - F.mean()) ** 2))
        want[name] = (float(np.sum((20.0 * x + e) ** 2)), float(np.sum(e * e)), var)
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
    assert out["damping_used"] == "law" and "_series" not in out
    one = predict(model, recs, tests=["B"], fitted=True, keep=True)
    assert [r["test"] for r in one["tests"]] == ["B"] and one["damping_used"] == "per-test fitted c_e"
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


# ---------------------------------------------------------------- diagnose: input checks, linear baseline, jack-knife

def _recs(n=5):
    from chainid.records.record import Record

    t = np.linspace(0, 1, 50)
    return [Record(str(i), t, 2.0 + 0.1 * np.sin(2 * np.pi * t), 100.0 * np.sin(2 * np.pi * t) + i)
            for i in range(1, n + 1)]


def test_check_magnitudes_limits_and_dead_channel():
    """|F| <= 1e12 N and |x| <= 1e9 mm (the documented limits, inclusive); a constant F is refused; a record with
    a non-finite value is left to the later checks."""
    from chainid.gap.diagnose import check_magnitudes
    from chainid.records.record import Record

    t = np.linspace(0, 1, 5)
    ok = Record("a", t, np.array([0, 1e9, 0, -1e9, 0.0]), np.array([1e12, -1e12, 0, 1, 2.0]))
    check_magnitudes([ok])
    with pytest.raises(ValueError, match=r"test 'b': \|F\| = 1\.5e\+12 N is out of range; valid range \|F\| <= "
                                         r"1e\+12 N \(check the column's unit\)"):
        check_magnitudes([ok, Record("b", t, ok.x, np.array([0, 1.5e12, 0, 1, 2.0]))])
    with pytest.raises(ValueError, match=r"test 'c': \|x\| = 2e\+09 mm is out of range; valid range \|x\| <= "
                                         r"1e\+09 mm"):
        check_magnitudes([Record("c", t, np.array([0, -2e9, 0, 1, 2.0]), ok.F)])
    with pytest.raises(ValueError, match=r"test 'd': the force F is constant \(7 N in all 5 samples\): a dead "
                                         "channel"):
        check_magnitudes([Record("d", t, ok.x, np.full(5, 7.0))])
    check_magnitudes([Record("e", t, ok.x, np.array([np.nan, 3e12, 7, 7, 7.0]))])  # NaN: not judged here


def test_diagnose_refuses_bad_holdout_options_before_any_work():
    from chainid.gap.diagnose import diagnose

    recs = _recs()
    with pytest.raises(ValueError, match=r"max_combo = 0 is out of range; valid range 1 to 3"):
        diagnose(recs, ["1"], max_combo=0)
    for k in (1, -1):
        with pytest.raises(ValueError, match=rf"--holdout-blocks = {k} is out of range; valid: 0 \(off\) or >= 2"):
            diagnose(recs, ["1"], holdout_blocks=k)
    with pytest.raises(ValueError, match=r"--holdout: no test held out; give test ids or --holdout-blocks K"):
        diagnose(recs, [" ", ""])
    with pytest.raises(ValueError, match=r"--holdout: all 5 tests are held out; leave at least 3 for training"):
        diagnose(recs, [" 1", "2 ", "3", "4", "5"])  # ids are stripped
    with pytest.raises(ValueError, match=r"--holdout: test id\(s\) \['9'\] not in the data; valid ids: 1, 2, 3, 4, 5"):
        diagnose(recs, ["9"])
    bad = _recs(2)
    bad[1] = type(bad[1])("2", bad[1].t, bad[1].x, np.full(50, 3.0))
    with pytest.raises(ValueError, match="the force F is constant"):  # the --validate set is checked too
        diagnose(recs, ["1"], validate=bad)


def test_fit_linear_model_uses_the_training_records_only():
    from chainid.gap.diagnose import fit_linear_model
    from chainid.records.record import Record

    t = np.linspace(0, 1, 30)
    x = 1.0 + 0.5 * np.sin(2 * np.pi * t)
    recs = [Record("a", t, x, 50.0 * (x - 0.2)), Record("b", t, x + 0.3, 50.0 * (x + 0.1)),
            Record("h", t, x, 999.0 * x)]
    m = fit_linear_model(recs, ["h"])
    assert (m.k, m.x_ref) == (pytest.approx(50.0, rel=1e-9), pytest.approx(0.2, rel=1e-9))


def test_jackknife_sd_by_hand():
    """Leave-one-test-out refits give 1, 2, 4: sd = sqrt((n − 1)/n · Σ(v − v̄)²) = sqrt(2/3 · 42/9); a law
    coefficient (``law.*``) is not jack-knifed."""
    from chainid.gap.diagnose import _jackknife

    vals = iter([1.0, 2.0, 4.0])
    seen = []

    def fit(names, train_only, start, polish_only):  # noqa: ANN001
        seen.append(([d.test for d in train_only], polish_only, dict(start)))
        return SimpleNamespace(params={"friction.F_c": next(vals)})

    prob = SimpleNamespace(train=[SimpleNamespace(test=s) for s in "ABC"], fit=fit)
    cand = SimpleNamespace(names=["friction"], params={"friction.F_c": 2.5, "law.0": 9.0})
    sd = _jackknife(prob, cand)
    assert sd == {"friction.F_c": pytest.approx(math.sqrt(2 / 3 * 42 / 9), rel=1e-12)}
    assert [s[0] for s in seen] == [["B", "C"], ["A", "C"], ["A", "B"]] and all(s[1] for s in seen)


# ---------------------------------------------------------------- selection: the step rule on a table of fits

def _world(monkeypatch, table, floor=()):
    """Fits looked up in ``table`` (sorted effect names → (LOTO NRMSE, LOTO SSE per test A, B, C, at_bound,
    n_params)); ``floor``: effect sets whose training residual is at the noise floor."""
    from chainid.gap import selection as sel
    from chainid.gap.problem import Candidate

    calls = []

    def fit_score(prob, names, start, base_hold):  # noqa: ANN001
        key = tuple(sorted(names))
        calls.append(key)
        loto, sse, bound, k = table[key]
        c = Candidate("+".join(names), {f"{n}.p": 1.0 for n in names}, k, at_bound=list(bound))
        c.nrmse_loto, c.loto_num, c.bic = loto, dict(zip("ABC", sse)), 10.0 * k
        return c

    monkeypatch.setattr(sel, "_fit_score", fit_score)
    monkeypatch.setattr(sel, "train_floor", lambda prob, c: tuple(sorted(c.names)) in floor)
    base = Candidate("baseline", {}, 0)
    base.nrmse_loto, base.loto_num = 1.0, {"A": 100.0, "B": 100.0, "C": 100.0}
    return sel, base, calls


TABLE = {("friction",): (0.5, (25.0, 25.0, 16.0), (), 1),
         ("slack",): (0.95, (90.0, 90.0, 90.0), (), 1),
         ("friction", "slack"): (0.48, (24.0, 24.0, 15.0), (), 2)}


def test_forward_selection_stops_on_an_immaterial_step_by_hand(monkeypatch):
    """Step 1: friction lowers the LOTO NRMSE by 50 % with g_i = ½ln(100/25), ½ln(100/25), ½ln(100/16) (all > 0,
    mean far above 2 SE): kept; slack (5 %) is not material.  Step 2: slack on top lowers it by 4 %: the chain
    stops, and the stop text gives the numbers of the rule."""
    sel, base, calls = _world(monkeypatch, TABLE)
    out = sel.forward_select(None, ["friction", "slack"], base, 1.0)
    assert [c.names for c in out["path"]] == [[], ["friction"]]
    assert sorted(c.name for c in out["singles"]) == ["friction", "slack"]
    g = 0.5 * np.log(np.array([25.0, 25.0, 16.0]) / [24.0, 24.0, 15.0])
    se = float(np.std(g, ddof=1)) / math.sqrt(3)
    assert out["stop"] == (f"no significant improvement: best next effect slack lowers the LOTO NRMSE by 4.0 % (mean "
                           f"log error ratio over tests {g.mean():.3g}, jack-knife SE {se:.2g}; needs > 2 SE and >= "
                           "10 %)")
    st = out["path"][1].step_test
    g1 = 0.5 * np.log(100.0 / np.array([25.0, 25.0, 16.0]))
    assert st["delta_loto"] == pytest.approx(g1.mean(), rel=1e-12)
    assert st["se_jackknife"] == pytest.approx(np.std(g1, ddof=1) / math.sqrt(3), rel=1e-12)
    assert st["relative_gain"] == pytest.approx(0.5, rel=1e-12)
    assert out["confounded"] == [] and out["dropped"] == [] and out["swapped"] == []


def test_forward_selection_stop_reasons(monkeypatch):
    sel, base, _ = _world(monkeypatch, TABLE)
    out = sel.forward_select(None, ["friction", "slack"], base, 1.0, max_effects=1)
    assert out["stop"] == "the chain has the maximum of 1 effects" and len(out["path"]) == 2
    out = sel.forward_select(None, ["friction"], base, 1.0)
    assert out["stop"] == "no library effect left" and len(out["path"]) == 2
    sel, base, _ = _world(monkeypatch, TABLE, floor={("friction",)})
    out = sel.forward_select(None, ["friction", "slack"], base, 1.0)
    assert out["stop"] == "the training residual is at the noise floor" and len(out["path"]) == 2
    pinned = dict(TABLE) | {("friction",): (0.5, (25.0, 25.0, 16.0), ("friction.p",), 1),
                            ("slack",): (0.95, (90.0, 90.0, 90.0), ("slack.p",), 1)}
    sel, base, _ = _world(monkeypatch, pinned)
    out = sel.forward_select(None, ["friction", "slack"], base, 1.0)
    assert out["stop"] == ("the best next effect friction needs parameters at the bounds of their physical range: "
                           "its form does not fit what is left")
    assert len(out["path"]) == 1 and len(out["singles"]) == 2


def test_forward_selection_near_tie_is_confounded_and_look_ahead_takes_the_runner_up(monkeypatch):
    """Hysteresis (2 parameters) within TIE = 5 % of friction (1): friction is chosen, the pair is reported as
    confounded.  The runner-up is within LOOKAHEAD = 30 %; its best extension (hysteresis+slack) must beat the
    choice's best (friction+slack, 0.48) by more than TIE to be taken: 0.47 is not (> 0.95·0.48 = 0.456), 0.40 is."""
    base_table = dict(TABLE) | {("hysteresis",): (0.51, (26.0, 26.0, 17.0), (), 2),
                                ("friction", "hysteresis"): (0.49, (24.5, 24.5, 15.5), (), 3)}
    sel, base, _ = _world(monkeypatch, base_table | {("hysteresis", "slack"): (0.47, (24.0, 24.0, 15.0), (), 3)})
    out = sel.forward_select(None, ["friction", "slack", "hysteresis"], base, 1.0)
    assert out["path"][1].names == ["friction"]
    assert out["confounded"][0] == {"step": 1, "pair": ["friction", "hysteresis"], "loto": [0.5, 0.51]}
    sel, base, _ = _world(monkeypatch, base_table | {("hysteresis", "slack"): (0.40, (10.0, 10.0, 6.0), (), 3)})
    out = sel.forward_select(None, ["friction", "slack", "hysteresis"], base, 1.0, max_effects=2)
    assert [c.names for c in out["path"]][1:] == [["hysteresis"], ["hysteresis", "slack"]]


def test_step_rule_boundaries():
    """Rule 2: mean log ratio > Z = 2 jack-knife SE (strict); rule 3: relative gain >= MIN_GAIN = 10 %."""
    from chainid.gap.problem import Candidate
    from chainid.gap.selection import loto_jackknife, passes, step_test

    assert passes({"delta_loto": 2.0, "se_jackknife": 1.0, "relative_gain": 0.5}) is False
    assert passes({"delta_loto": 2.001, "se_jackknife": 1.0, "relative_gain": 0.5}) is True
    assert passes({"delta_loto": 3.0, "se_jackknife": 1.0, "relative_gain": 0.1}) is True
    assert passes({"delta_loto": 3.0, "se_jackknife": 1.0, "relative_gain": 0.0999}) is False

    def cand(loto, sse):
        c = Candidate("x", {}, 1)
        c.nrmse_loto, c.loto_num = loto, sse
        return c

    one = loto_jackknife(cand(1.0, {"A": 4.0}), cand(0.5, {"A": 1.0}))
    assert one == (pytest.approx(0.5 * math.log(4.0)), math.inf)  # one test: no spread to judge by
    assert loto_jackknife(cand(1.0, {}), cand(1.0, {})) == (0.0, math.inf)
    st = step_test(cand(0.0, {"A": 1.0, "B": 1.0}), cand(0.0, {"A": 1.0, "B": 1.0}))
    assert st["relative_gain"] == 0.0 and st["z"] == math.inf  # no error before: no gain; se 0: z infinite
    st = step_test(cand(2.0, {"A": 4.0, "B": 9.0}), cand(1.5, {"A": 1.0, "B": 1.0}))
    g = [0.5 * math.log(4.0), 0.5 * math.log(9.0)]
    se = abs(g[1] - g[0]) / math.sqrt(2) / math.sqrt(2)  # sd (ddof 1) of two values = |a − b|/√2
    assert st["z"] == pytest.approx(sum(g) / 2 / se, rel=1e-12) and st["relative_gain"] == pytest.approx(0.25)


def test_no_look_ahead_beyond_the_maximum_chain(monkeypatch):
    """At the last allowed step (two effects chosen, at most three) the look-ahead would fit four effects: it
    is not run (only effect sets of up to ``max_effects`` are ever fitted), and the near-tie is reported."""
    table = dict(TABLE) | {
        ("friction", "slack"): (0.3, (9.0, 9.0, 6.0), (), 2),
        ("hysteresis",): (0.9, (80.0, 80.0, 81.0), (), 2), ("backlash",): (0.92, (85.0, 85.0, 84.0), (), 1),
        ("friction", "hysteresis"): (0.45, (20.0, 20.0, 14.0), (), 3),
        ("backlash", "friction"): (0.46, (21.0, 21.0, 14.0), (), 2),
        ("friction", "hysteresis", "slack"): (0.2, (4.0, 4.0, 3.0), (), 3),
        ("backlash", "friction", "slack"): (0.21, (4.2, 4.2, 3.1), (), 4),
        ("hysteresis", "slack"): (0.6, (30.0, 30.0, 20.0), (), 3)}
    sel, base, calls = _world(monkeypatch, table)
    out = sel.forward_select(None, ["friction", "slack", "hysteresis", "backlash"], base, 1.0, max_effects=3)
    assert [c.names for c in out["path"]][1:] == [["friction"], ["friction", "slack"],
                                                  ["friction", "slack", "hysteresis"]]
    assert max(len(k) for k in calls) == 3
    assert out["stop"] == "the chain has the maximum of 3 effects"
    assert {"step": 3, "pair": ["hysteresis", "backlash"], "loto": [0.2, 0.21]} in out["confounded"]
    assert out["dropped"] == []


def test_quake_records_half_with_a_near_fault_pulse(monkeypatch):
    """README (non-harmonic families): quake records are Kanai–Tajimi noise under an envelope, half of them with
    a near-fault pulse (0.5–1.5), some with a permanent offset (|offset| <= 0.3 mm)."""
    from chainid.gap.benchmark_time import motion
    from chainid.records import excitation as ex

    seen = []

    def quake(n, fs, A, x0, rng, **kw):  # noqa: ANN001
        seen.append(kw)
        raise _Stop

    monkeypatch.setattr(ex, "earthquake", quake)
    rng = np.random.default_rng(11)
    for _ in range(400):
        with pytest.raises(_Stop):
            motion("quake", rng)
    pulses = np.array([k["pulse"] for k in seen])
    # binomial(400, 1/2): 200 ± 10 (1σ); ± 50 is 5σ
    assert 150 <= np.count_nonzero(pulses) <= 250
    assert pulses[pulses > 0].min() >= 0.5 and pulses.max() <= 1.5
    offs = np.array([k["offset"] for k in seen])
    assert 0 < np.count_nonzero(offs) < 400 and np.abs(offs).max() <= 0.3


# ---------------------------------------------------------------- the time-domain route is free of the force unit

def _time_diag(scale):
    from chainid.gap import diagnose
    from chainid.records.record import Record
    from transient_forms import chain_set

    _, recs = chain_set("friction", {"F_c": 60.0}, n=1500)
    rr = [Record(r.test, r.t, r.x, r.F * scale) for r in recs]
    return diagnose(rr, ["r2"], None, quiet=True, uncertainty=False, max_combo=1, effects=["friction"])


@pytest.fixture(scope="module")
def time_friction():
    """A time-domain diagnosis of 3 random records with friction F_c = 60 N (tests/transient_forms.py)."""
    return _time_diag(1.0)


def test_time_domain_diagnosis_is_invariant_to_the_force_unit(time_friction):
    """NRMSE is dimensionless and every fitted force scales with F: the same records with F × 1e-7 (a force
    channel in other units; each record's Σ(F − F̄)² then far below 1 N²) give the same per-test NRMSE, the same
    verdict and F_c × 1e-7 (the records: tests/transient_forms.py, friction F_c = 60 N on a random x)."""
    a, b = time_friction, _time_diag(1e-7)
    assert a["route"] == b["route"] == "time" and a["verdict"] == b["verdict"] == "friction"
    for ta, tb in zip(a["tests"], b["tests"]):
        assert tb["nrmse_before"] == pytest.approx(ta["nrmse_before"], rel=1e-9)
        assert tb["nrmse_after"] == pytest.approx(ta["nrmse_after"], rel=1e-4)
    assert b["steps"][-1]["params"]["friction.F_c"] == pytest.approx(1e-7 * a["steps"][-1]["params"]["friction.F_c"],
                                                                      rel=1e-4)
    assert b["steps"][-1]["shrinkage"] == pytest.approx(a["steps"][-1]["shrinkage"], rel=1e-4)


def test_harmonic_diagnosis_baseline_is_invariant_to_the_force_unit():
    """The phase-bin route on 11 steady tests (friction F_c = 150 N, 20 N noise) with F × 1e-7: the baseline
    (linear spring, Eq. 21, per-test NRMSE, dB over noise) is the same to round-off, the noise σ scales by 1e-7,
    the verdict is the same.  (The friction fit itself lands within 2 % of the unscaled one: the optimiser's
    path is not exactly scale-free, so it is held to a looser tolerance.)"""
    from chainid.gap import diagnose
    from chainid.gap.benchmark import grid3x3_plan
    from chainid.model.base import ChainModel
    from chainid.model.effects import parse_effect
    from chainid.model.laws import PolynomialLaw
    from chainid.records.record import Record
    from chainid.records.simulate import simulate

    m = ChainModel()
    recs = simulate(grid3x3_plan(prefix=""), m, PolynomialLaw([0.5, 1.0, 100.0, 20.0, 50.0]), n_cycles=6,
                    samples_per_cycle=64, noise_F=20.0, seed=2, force_fn=parse_effect("friction:F_c=150", m))
    a, b = (diagnose([Record(r.test, r.t, r.x, r.F * s) for r in recs], ["3", "7"], None, quiet=True,
                     uncertainty=False, max_combo=1, effects=["friction", "slack"]) for s in (1.0, 1e-7))
    assert a["verdict"] == b["verdict"] == "friction"
    assert b["baseline"]["damping_law"] == a["baseline"]["damping_law"]
    for k in ("nrmse_train", "nrmse_holdout", "db_over_noise", "nrmse_loto"):
        assert b["baseline"][k] == pytest.approx(a["baseline"][k], rel=1e-9), k
    for k in ("noise_sigma_N", "excess_rms_N"):
        assert b["baseline"][k] == pytest.approx(1e-7 * a["baseline"][k], rel=1e-9), k
    for ta, tb in zip(a["tests"], b["tests"]):
        assert tb["nrmse_before"] == pytest.approx(ta["nrmse_before"], rel=1e-9)
        assert tb["sigma_N"] == pytest.approx(1e-7 * ta["sigma_N"], rel=1e-9)
        assert tb["nrmse_after"] == pytest.approx(ta["nrmse_after"], rel=0.02)
    assert b["steps"][-1]["params"]["friction.F_c"] == pytest.approx(1e-7 * a["steps"][-1]["params"]["friction.F_c"],
                                                                      rel=0.03)


# ---------------------------------------------------------------- the phase-route figures show the result's numbers

def test_phase_route_figures_show_the_results_numbers(tmp_path, monkeypatch):
    """heatmap: each square's colour and label are the test's NRMSE before/after of the JSON ``tests`` (2
    digits), colour scale 0 … the largest baseline NRMSE, held-out squares edged red; residual surface: every
    test's bins on a circle of radius A/A_max; residual vs phase: held-out lines thick (1.5), the others thin;
    loops: model loops closed (last point = first)."""
    import chainid.infra.fileio
    from chainid.gap import diagnose
    from chainid.gap.benchmark import grid3x3_plan
    from chainid.gap.plots import make_plots
    from chainid.model.base import ChainModel
    from chainid.model.effects import parse_effect
    from chainid.model.laws import PolynomialLaw
    from chainid.records.simulate import simulate

    figs = {}
    orig = chainid.infra.fileio.save_figure

    def spy(fig, path, *a, **k):  # noqa: ANN001
        figs[path.name] = fig
        return orig(fig, path, *a, **k)

    monkeypatch.setattr(chainid.infra.fileio, "save_figure", spy)
    m = ChainModel()
    recs = simulate(grid3x3_plan(prefix=""), m, PolynomialLaw([0.5, 1.0, 100.0, 20.0, 50.0]), n_cycles=6,
                    samples_per_cycle=64, noise_F=20.0, seed=2, force_fn=parse_effect("friction:F_c=150", m))
    res = diagnose(recs, ["3", "7"], m, quiet=True, uncertainty=False, max_combo=1, effects=["friction"])
    make_plots(res, tmp_path / "p")
    tests = {t["test"]: t for t in res["tests"]}
    vmax = max(t["nrmse_before"] for t in tests.values())
    ax0, ax1 = figs["heatmap.png"].axes[:2]
    for ax, key in ((ax0, "nrmse_before"), (ax1, "nrmse_after")):
        sc = ax.collections[0]
        want = [tests[t][key] for t in tests]  # the problem's data order is the records' order
        np.testing.assert_allclose(sc.get_array(), want, rtol=1e-12)
        assert sc.norm.vmin == 0 and sc.norm.vmax == pytest.approx(vmax, rel=1e-12)
        assert [a.get_text() for a in ax.texts] == [f"{v:.2g}" for v in want]
        red = [tuple(c) for c in sc.get_edgecolors()]
        assert sum(c[:3] == (1.0, 0.0, 0.0) for c in red) == 2  # the two held-out tests
    assert ax1.get_title() == "with friction (red edge: held-out)"
    Amax = max(t["A"] for t in tests.values())
    surf = figs["residual_surface.png"].axes[0]
    for coll, t in zip(surf.collections, tests.values()):
        xy = coll.get_offsets()
        np.testing.assert_allclose(np.hypot(xy[:, 0], xy[:, 1]), t["A"] / Amax, rtol=1e-12)
    ph = figs["residual_phase.png"].axes[0]
    widths = {ln.get_label(): ln.get_linewidth() for ln in ph.lines[:-1]}
    assert widths["3"] == widths["7"] == 1.5 and sorted(widths.values()).count(0.7) == len(tests) - 2
    for ax in figs["loops.png"].axes:
        for ln in ax.lines[1:]:
            y = ln.get_ydata()
            assert y[0] == y[-1] and ln.get_xdata()[0] == ln.get_xdata()[-1]


# ---------------------------------------------------------------- diagnose_time.build_problem: which route a test takes

def test_build_problem_routes_harmonic_tests_by_the_documented_rule(monkeypatch):
    """Harmonic tests keep the phase-bin route when at least MIN_TRAIN = 3 of them are for training and no
    --holdout-blocks is given; otherwise they join the time-domain records, with a warning saying why; every
    time-domain record is cut in LOO_BLOCKS = 4 blocks (or the --holdout-blocks K)."""
    from chainid.gap import diagnose_time as dt

    made = {}
    monkeypatch.setattr(dt, "prepare_time", lambda r, nb: SimpleNamespace(test=r.test, nb=nb))
    monkeypatch.setattr(dt, "Problem", lambda data, model, hold, law, require_hold: SimpleNamespace(
        tests=[d.test for d in data], hold=hold, law=law, require_hold=require_hold))

    def anyp(tdata, model, holdout, blocks, hprob):  # noqa: ANN001
        made.update(tdata=[(d.test, d.nb) for d in tdata], hprob=hprob, blocks=blocks)
        return made

    monkeypatch.setattr(dt, "AnyProblem", anyp)
    recs = [SimpleNamespace(test=s) for s in ("h1", "h2", "h3", "h4", "r1")]
    hdata = [SimpleNamespace(test=s) for s in ("h1", "h2", "h3", "h4")]
    warn = []
    dt.build_problem(recs, hdata, [recs[4]], ["h4"], 0, "M", "viscous", warn)
    assert made["tdata"] == [("r1", 4)] and warn == []
    assert (made["hprob"].tests, made["hprob"].hold, made["hprob"].law) == (["h1", "h2", "h3", "h4"], ["h4"], "viscous")
    assert made["hprob"].require_hold is False
    dt.build_problem(recs, hdata, [recs[4]], ["h3", "h4"], 0, "M", "auto", warn)  # 2 harmonic training tests
    assert made["hprob"] is None and made["tdata"] == [("r1", 4), ("h1", 4), ("h2", 4), ("h3", 4), ("h4", 4)]
    assert warn == ["4 harmonic test(s) analysed in the time domain with the other records (fewer than 3 harmonic "
                    "training tests for the phase-bin route)"]
    warn.clear()
    dt.build_problem(recs, hdata, [recs[4]], [], 3, "M", "auto", warn)
    assert made["hprob"] is None and made["blocks"] == 3 and {nb for _, nb in made["tdata"]} == {3}
    assert warn == ["4 harmonic test(s) analysed in the time domain with the other records (--holdout-blocks "
                    "splits every record in time)"]
    warn.clear()
    dt.build_problem(recs[4:], [], [recs[4]], ["r1"], 0, "M", "auto", warn)
    assert made["hprob"] is None and warn == [] and made["tdata"] == [("r1", 4)]


# ---------------------------------------------------------------- where_time.drift: block-mean trend by hand

def _trec(name, slope, n=640, sigma=32.0 ** 0.5):
    t = np.arange(n) / 64.0
    return SimpleNamespace(test=name, t=t, x=np.full(n, 2.0), sigma=sigma), slope * t


def test_time_drift_rule_by_hand():
    """640 samples (10 s) in N_DRIFT = 20 blocks of 32: block mid-times 0.5 s apart, Σ(t − t̄)² = 0.25·665; the
    floor σ/sqrt(32) = 1 N (σ = sqrt 32); a noise-free residual slope of 2 N/s: z = 2·sqrt(166.25), change
    2·9.5 = 19 N.  Non-stationary when at least a quarter of the records drift (1 of 4, not 1 of 5)."""
    from chainid.gap.where_time import drift

    def run(slopes):
        recs = [_trec(f"r{i}", s) for i, s in enumerate(slopes)]
        return drift([d for d, _ in recs], {d.test: r for d, r in recs})

    out = run([2.0, 0.0, 0.0, 0.0])
    z = 2.0 * math.sqrt(166.25)
    assert out["stationary"] is False and out["z"] == pytest.approx(z, rel=1e-9)
    assert out["tests"][0]["change_N"] == pytest.approx(19.0, rel=1e-9)
    assert out["trend_change_N"] == pytest.approx(math.sqrt(19.0 ** 2 / 4), rel=1e-9)
    assert out["finding"].startswith(f"non-stationary: the residual drifts with time in 1 of 4 records (change 9.5 N "
                                      f"RMS over records, up to {z:.1f} standard errors)")
    five = run([2.0, 0.0, 0.0, 0.0, 0.0])
    assert five["stationary"] is True and five["finding"].startswith("the residual is stationary over each record")
    # the z threshold (Z_TREND = 4): slope 3.9/sqrt(166.25) is not a drift, 4.1/… is
    assert run([3.9 / math.sqrt(166.25)])["stationary"] is True
    assert run([4.1 / math.sqrt(166.25)])["stationary"] is False
    # fewer than 6 blocks of 32 samples: not checked
    short = [_trec("s", 1.0, n=191)]
    res = drift([short[0][0]], {"s": short[0][1]})
    assert res == {"stationary": None, "trend_change_N": 0.0, "z": 0.0, "tests": [],
                   "finding": "stationarity not checked: records too short for the drift test"}
    ok = _trec("s", 1.0, n=192)
    assert len(drift([ok[0]], {"s": ok[1]})["tests"]) == 1  # 6 blocks of 32


def test_state_map_threshold_by_hand():
    """A residual ±a split at the median of x: 16 quantile bins of x with means ±a, between-bin variance a²;
    pure noise of σ would give σ²·16/N; z = (a² − σ²·16/N)/(σ²·16/N · sqrt(2/15)); reported from z = 5 on, with
    the bin means' range and the share of the residual's variance (100 %)."""
    from chainid.gap.where_time import state_maps

    n, sig = 1600, 1.0
    x = np.linspace(1.0, 3.0, n)
    noise = sig ** 2 * 16 / n

    def maps(z):
        a = math.sqrt(noise * (1 + z * math.sqrt(2 / 15)))
        d = SimpleNamespace(test="r", t=np.arange(n) / 100.0, x=x, xd=np.zeros(n), sigma=sig)
        out = state_maps([d], {"r": np.where(x < 2.0, a, -a)}, {"r": np.zeros(n)})
        return a, {f["variable"]: f for f in out}

    a, got = maps(5.1)
    f = got["x"]
    assert f["share"] == pytest.approx(1.0, rel=1e-9) and len(f["bin_means_N"]) == 16
    assert f["finding"] == (f"residual follows the displacement x: bin means from {-a:+.3g} to {a:+.3g} N carry "
                            "100 % of its variance (→ stiffness side (level, contact law, offset))")
    assert f["score"] == pytest.approx(a, rel=1e-9)
    assert "load" not in got  # a constant model force has no bins
    assert "x" not in maps(4.9)[1]


def test_spectrum_outside_the_band_by_hand():
    """A 40 Hz sine of amplitude a in the residual, band 2 Hz (cut 4× = 8 Hz), fs = 100 Hz, σ = 1 N: the high
    pass keeps the sine, RMS² a²/2 against white noise over 8 … 50 Hz, σ²·(1 − 8/50): ratio sqrt(a²/2/0.84);
    above 1.5 it is called content outside the band, else noise.  A band whose cut reaches 0.45·fs is skipped."""
    from chainid.gap.where_time import spectrum_outside

    n, fs = 4000, 100.0
    t = np.arange(n) / fs
    d = SimpleNamespace(test="r", t=t, fs=fs, f_band=2.0, sigma=1.0)
    for a, tail in ((1.0, " (noise)"), (3.0, " (content outside the excitation's band: ringing, impacts, chatter or "
                                           "a sensor resonance)")):
        out = spectrum_outside([d], {"r": a * np.sin(2 * np.pi * 40.0 * t)})
        want = math.sqrt(a * a / 2 / 0.84)
        assert out["ratio_to_noise"] == pytest.approx(want, rel=2e-3)
        assert out["finding"] == (f"residual above 4× the excitation band: RMS {out['ratio_to_noise']:.2f}× white "
                                  "noise of the records' σ over that bandwidth" + tail)
    wide = SimpleNamespace(test="r", t=t, fs=fs, f_band=11.25, sigma=1.0)  # 4 · 11.25 = 45 Hz = 0.45 fs
    assert spectrum_outside([wide], {"r": np.sin(2 * np.pi * 40.0 * t)}) == {}


def test_time_route_figures_show_the_results_numbers(time_friction, tmp_path, monkeypatch):
    """heatmap.png: one pair of bars per record at x ∓ 0.2 (width 0.4), heights the JSON ``tests`` NRMSE before
    and after; loops.png: the held-out record's held-out samples only (measured F over x); residual_phase.png:
    the held-out time span shaded; residual_surface.png: the baseline residual over (x, ẋ), colour scale ± its
    99th percentile of |r|."""
    import chainid.infra.fileio
    from chainid.gap.plots import make_plots

    figs = {}
    orig = chainid.infra.fileio.save_figure

    def spy(fig, path, *a, **k):  # noqa: ANN001
        figs[path.name] = fig
        return orig(fig, path, *a, **k)

    monkeypatch.setattr(chainid.infra.fileio, "save_figure", spy)
    res = time_friction
    make_plots(res, tmp_path / "p")
    tests = res["tests"]
    ax = figs["heatmap.png"].axes[0]
    bars = ax.patches
    assert len(bars) == 2 * len(tests)
    for i, t in enumerate(tests):
        b, a = bars[i], bars[len(tests) + i]
        assert (b.get_x(), b.get_width(), a.get_x()) == (pytest.approx(i - 0.4), pytest.approx(0.4), pytest.approx(i))
        assert b.get_height() == pytest.approx(t["nrmse_before"], rel=1e-12)
        assert a.get_height() == pytest.approx(t["nrmse_after"], rel=1e-12)
    assert [tl.get_text() for tl in ax.get_xticklabels()] == [t["test"] for t in tests]
    prob = res["_problem"]
    data = {d.test: d for d in prob.tdata}
    loops = {a.get_title().split(" ")[0]: a for a in figs["loops.png"].axes}
    d = data["r2"]
    held = ~prob.train_mask("r2")
    assert loops["r2"].get_title() == "r2 (held-out samples)" and loops["r0"].get_title() == "r0 (training)"
    np.testing.assert_array_equal(loops["r2"].lines[0].get_ydata(), d.F[held])
    np.testing.assert_array_equal(loops["r0"].lines[0].get_ydata(), data["r0"].F)
    spans = figs["residual_phase.png"].axes[2].patches
    assert len(spans) == 1 and not figs["residual_phase.png"].axes[0].patches
    sp = spans[0]  # a Rectangle (matplotlib >= 3.9) or a Polygon (older)
    xs = [sp.get_x(), sp.get_x() + sp.get_width()] if hasattr(sp, "get_width") else np.asarray(sp.get_xy())[:, 0]
    assert (min(xs), max(xs)) == (pytest.approx(d.t[held].min()), pytest.approx(d.t[held].max()))
    sc = figs["residual_surface.png"].axes[0].collections[0]
    r = np.concatenate([res["_path"][0]._ev["time"]["res"][dd.test] for dd in prob.tdata])
    np.testing.assert_allclose(sc.get_array(), r, rtol=1e-12)
    assert sc.norm.vmax == pytest.approx(np.quantile(np.abs(r), 0.99), rel=1e-12) and sc.norm.vmin == -sc.norm.vmax


# ---------------------------------------------------------------- modelio: a step as a model file, provenance

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


# ---------------------------------------------------------------- benchmark rows from a hand-made diagnosis

def _fake_result(steps=("baseline", "friction", "slack"), **kw):
    res = {"verdict": "friction+slack", "baseline": {"excess_rms_N": 30.0, "noise_sigma_N": 4.0},
           "steps": [{"effect": e, "shrinkage": 0.1 * i, "params": {"p": i}} for i, e in enumerate(steps)],
           "best": {"shrinkage": 0.77}, "confounded": [{"pair": ["slack", "contact_law"]}],
           "residual": {"stationary": True, "where": [{"kind": "chatter"}]}, "where": [{"kind": "level"}],
           "ranking": [{"effect": "hysteresis"}, {"effect": "friction"}],
           "transfer": {"pooled": {"shrinkage": 0.8, "shrinkage_refit": 0.6}, "transfers": True, "chain": "friction"}}
    return res | kw


def test_time_and_transfer_rows_by_hand(monkeypatch):
    """The row of a non-harmonic case: snr = excess/noise (30/4), the last step's shrinkage when the chain has an
    effect (else the best's), the steps after the baseline, the first of the ranking, chatter found in `where`
    or in the residual's `where`; a transfer case adds the pooled shrinkages and the transfer verdict."""
    from chainid.gap.benchmark_time import run_case_time, run_case_transfer, time_grid

    monkeypatch.setattr(sys.modules["chainid.gap.diagnose"], "diagnose", lambda *a, **k: _fake_result())
    cases = time_grid(small=True)
    row = run_case_time(cases[0])
    assert row["snr"] == 7.5 and row["verdict"] == "friction+slack"
    assert row["shrinkage"] == pytest.approx(0.2) and row["steps"] == ["friction", "slack"] and row["params"] == {"p": 2}
    assert row["confounded"] == [["slack", "contact_law"]] and row["stationary"] is True
    assert row["ranked_first"] == "hysteresis" and row["chatter"] is True
    assert len(row["effect_snr"]) == 1 and row["effect_snr"][0] > 0 and row["seconds"] >= 0
    assert {k: row[k] for k in cases[0]} == cases[0]
    monkeypatch.setattr(sys.modules["chainid.gap.diagnose"], "diagnose", lambda *a, **k: _fake_result(
        steps=("baseline",), residual={"stationary": False}, where=[], ranking=[]))
    row = run_case_time(cases[0])
    assert row["shrinkage"] == 0.77 and row["steps"] == [] and row["params"] == {"p": 0}
    assert row["chatter"] is False and row["ranked_first"] is None and row["stationary"] is False
    monkeypatch.setattr(sys.modules["chainid.gap.diagnose"], "diagnose", lambda *a, **k: _fake_result())
    tr = run_case_transfer(cases[-1])
    assert (tr["transfer_shrinkage"], tr["transfer_shrinkage_refit"], tr["transfers"], tr["transfer_chain"]) == \
        (0.8, 0.6, True, "friction")

    def boom(*a, **k):  # noqa: ANN001
        raise RuntimeError("no")

    monkeypatch.setattr(sys.modules["chainid.gap.diagnose"], "diagnose", boom)
    err = run_case_time(cases[0])
    assert err["verdict"] == "error: RuntimeError: no" and err["snr"] == math.inf and err["chatter"] is False
    assert err["transfer_shrinkage"] is None and err["confounded"] == [] and err["stationary"] is None


def test_run_case_dispatches_by_excitation(monkeypatch):
    from chainid.gap import benchmark_time as bt
    from chainid.gap.benchmark import run_case

    monkeypatch.setattr(bt, "run_case_time", lambda c: ("time", c["excitation"]))
    monkeypatch.setattr(bt, "run_case_transfer", lambda c: ("transfer", c["excitation"]))
    assert run_case({"excitation": "quake"}) == ("time", "quake")
    assert run_case({"excitation": "transfer"}) == ("transfer", "transfer")


def test_outside_library_hooks_by_hand(monkeypatch):
    """Harmonic cases: a drift adds 0.05·level·S·t/t_end; a relaxation takes off 0.1·level·S·(1 − exp(−3 t/t_end)).
    Non-harmonic records: the same from the record's first sample, (t − t0)/(t_end − t0)."""
    from chainid.gap.benchmark import run_case
    from chainid.gap.benchmark_time import _outside
    from chainid.records import simulate as simulate_module

    t = np.linspace(0.0, 4.0, 9)
    z = np.zeros(9)
    # S of the plan (see test_harmonic_case_noise_damping_and_holdout_by_hand), via the noise σ = noise·S
    seen = {}

    def sim_s(plan, model, law, **kw):  # noqa: ANN001
        seen.update(kw)
        raise _Stop

    monkeypatch.setattr(simulate_module, "simulate", sim_s)
    with pytest.raises(_Stop):
        run_case(_harmonic_case(effects=["drift"], truth=["drift"], levels=[2.0], noise=1.0))
    S = seen["noise_F"]
    np.testing.assert_allclose(seen["force_fn"](t, z, z, z, z), 0.05 * 2.0 * S * t / 4.0, rtol=1e-12)
    with pytest.raises(_Stop):
        run_case(_harmonic_case(effects=["relaxation"], truth=["relaxation"], levels=[0.5], noise=1.0))
    np.testing.assert_allclose(seen["force_fn"](t, z, z, z, 10 + z), 10 - 0.1 * 0.5 * S * (1 - np.exp(-3 * t / 4.0)),
                               rtol=1e-12)
    rng = np.random.default_rng(0)
    t2 = 3.0 + t  # a record that starts at 3 s
    np.testing.assert_allclose(_outside("drift", 2.0, 100.0, 0.0, rng)(t2, z, z, z, z), 0.05 * 2 * 100 * t / 4.0,
                               rtol=1e-12)
    np.testing.assert_allclose(_outside("relaxation", 1.0, 100.0, 0.0, rng)(t2, z, z, z, z),
                               -0.1 * 100 * (1 - np.exp(-3 * t / 4.0)), rtol=1e-12)


def test_exchange_swaps_within_a_family_and_backward_pass_drops_a_redundant_effect(monkeypatch):
    """Exchange: after friction then slack, hysteresis (friction's family) refitted with slack is better by more
    than TIE (0.2 < 0.95·0.3): swapped, the chain rebuilt greedily (hysteresis first: 0.9 < 0.95 alone) — unless a
    hysteresis parameter sits at a bound (rule 4).  Backward: slack alone (pinned at step 1, so friction came
    first) is within 3 % of friction+slack: dropping friction is not significantly worse, so it is dropped."""
    table = dict(TABLE) | {("friction", "slack"): (0.3, (9.0, 9.0, 6.0), (), 2),
                           ("hysteresis",): (0.9, (80.0, 80.0, 81.0), (), 2),
                           ("friction", "hysteresis"): (0.45, (20.0, 20.0, 14.0), (), 3),
                           ("hysteresis", "slack"): (0.2, (4.0, 4.0, 3.0), (), 3)}
    sel, base, _ = _world(monkeypatch, table)
    out = sel.forward_select(None, ["friction", "slack", "hysteresis"], base, 1.0, max_effects=2)
    assert out["swapped"] == ["friction -> hysteresis"]
    assert [c.names for c in out["path"]][1:] == [["hysteresis"], ["hysteresis", "slack"]]
    assert out["dropped"] == []
    pinned = table | {("hysteresis", "slack"): (0.2, (4.0, 4.0, 3.0), ("hysteresis.p",), 3)}
    sel, base, _ = _world(monkeypatch, pinned)
    out = sel.forward_select(None, ["friction", "slack", "hysteresis"], base, 1.0, max_effects=2)
    assert out["swapped"] == [] and out["path"][-1].names == ["friction", "slack"]
    redundant = dict(TABLE) | {("slack",): (0.31, (9.5, 9.5, 6.2), ("slack.p",), 1),
                               ("friction", "slack"): (0.3, (9.0, 9.0, 6.0), (), 2)}
    sel, base, _ = _world(monkeypatch, redundant)
    out = sel.forward_select(None, ["friction", "slack"], base, 1.0)
    assert out["dropped"] == ["friction"] and [c.names for c in out["path"]] == [[], ["slack"]]


# ---------------------------------------------------------------- edge cases with a documented answer

def test_noise_edge_cases():
    """Fewer than 8 spectral lines or a displacement with no variation: the band is the Nyquist frequency and
    the record is not called broadband."""
    from chainid.gap import noise

    t = np.arange(12) / 100.0
    assert noise.excitation_band(t, np.sin(t)) == pytest.approx(50.0, rel=1e-9)  # 7 lines
    assert noise.is_broadband(t, np.sin(t)) is False
    t = np.arange(200) / 100.0
    assert noise.excitation_band(t, np.zeros(200)) == pytest.approx(50.0, rel=1e-9)  # no variation at all
    assert noise.force_quantum(np.array([1.0, 1.0, 2.0, 2.0, 3.0, 3.0])) == 1.0
    assert noise.force_quantum(np.array([1.0, 2.0, 3.0, 4.0])) == 0.0  # as many values as samples: not quantised


def test_problem_holdout_errors():
    from chainid.gap.problem import Problem

    data = [SimpleNamespace(test=s) for s in ("a", "b", "c", "d")]
    with pytest.raises(ValueError, match=r"--holdout: test id\(s\) \['z'\] not in the usable data; usable ids: a, b, "
                                         "c, d"):
        Problem(data, None, ["a", "z"])
    with pytest.raises(ValueError, match="--holdout: no test held out; give at least one test id"):
        Problem(data, None, [])
    with pytest.raises(ValueError, match=r"--holdout leaves 2 usable training test\(s\); at least 3 are needed"):
        Problem(data, None, ["a", "b"])


def test_every_held_out_test_excluded_is_an_error_with_the_reasons(capsys):
    from chainid.gap import diagnose
    from chainid.gap.benchmark import grid3x3_plan
    from chainid.model.base import ChainModel
    from chainid.records.record import Record
    from chainid.records.simulate import simulate

    recs = simulate(grid3x3_plan(prefix=""), ChainModel(), 50.0, n_cycles=6, samples_per_cycle=64, noise_F=5.0,
                    seed=1)
    t = np.arange(20) / 100.0  # 20 samples: no steady cycle, too short for the time-domain route
    recs[2] = Record("3", t, 2.0 + 0.1 * np.sin(8 * t), 1000.0 + 10 * np.sin(8 * t))
    with pytest.raises(ValueError, match=r"--holdout: every held-out test was excluded \(3\); reasons: "):
        diagnose(recs, ["3"], ChainModel(), quiet=False, uncertainty=False, max_combo=1)
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1 and err[0].startswith("chainid diagnose: test 3 excluded: ")
    with pytest.raises(ValueError, match=r"test '3' cannot be used \(--strict\): "):
        diagnose(recs, ["7"], ChainModel(), quiet=True, uncertainty=False, max_combo=1, strict=True)


def test_validate_record_too_short_for_the_time_domain(monkeypatch):
    from chainid.gap.timedomain import MIN_SAMPLES
    from chainid.records.record import Record

    tr, base, final, _ = _fake_scores(monkeypatch, {"r1": 1.0, "r2": 1.0})
    monkeypatch.undo()
    t = np.arange(20) / 100.0
    short = Record("v", t, 2.0 + 0.1 * np.sin(8 * t), 1000.0 + 10 * np.sin(8 * t))
    with pytest.raises(ValueError, match=rf"--validate: test 'v' has 20 samples; need >= {MIN_SAMPLES}"):
        tr.transfer({"_problem": None, "_path": [base, final]}, [short])


# ---------------------------------------------------------------- fitgrid: the documented start points

def test_fit_start_points_follow_their_documentation():
    """``starts``: the default start first; a delay gets a grid over its whole range (± half the shortest period)
    at 1/40 of a period, i.e. the 40 midpoints (i + ½)/40; a scale or delay also starts around its neutral value
    (below and above it); a parameter whose range straddles 0 starts close to 0 on both sides; the linear spring
    of a --model linear baseline may soften a lot: every start again with k × 0.1 and × 0.01; parameters of
    effects already fitted (fixed) keep their value in every start; everything inside the unit box."""
    from chainid.gap.fitgrid import DELAY_GRID, starts

    ug = np.array([0.5])
    out = starts(["sensor_delay.tau"], ["sensor_delay"], ug, np.zeros(1, bool), np.array([-0.1]), np.array([0.1]))
    u = sorted({round(float(v[0]), 12) for v in out})
    assert np.allclose(out[0], ug)
    mids = [(i + 0.5) / DELAY_GRID for i in range(DELAY_GRID)]
    assert DELAY_GRID == 40 and all(any(abs(m - v) < 1e-12 for v in u) for m in mids)
    assert any(0.5 < v < 0.5 + 1e-2 for v in u) and any(0.5 - 1e-2 < v < 0.5 for v in u)  # close to τ = 0, both sides
    sc = starts(["stiffness_level.scale"], ["stiffness_level"], np.array([0.4]), np.zeros(1, bool), np.array([0.5]),
                np.array([1.75]))
    vals = [float(v[0]) for v in sc]
    assert any(0.2 <= v < 0.4 for v in vals) and any(0.4 < v <= 1.0 for v in vals)  # around the neutral 0.4
    assert min(vals) == 0.0 and all(0.0 <= v <= 1.0 for v in vals)
    # a linear spring and one fixed parameter of an earlier effect (slack.s = 0.3 of its range)
    keys = ["spring.k", "spring.x_ref", "slack.s", "friction.F_c", "friction.mu", "friction.x_s"]
    ug = np.array([0.4, 0.5, 0.3, 0.01, 0.0, 0.0])
    fixed = np.array([False, False, True, False, False, False])
    lo, hi = np.zeros(6), np.ones(6)
    out = starts(keys, ["slack", "friction"], ug, fixed, lo, hi)
    assert all(v[2] == 0.3 and v[1] == 0.5 for v in out)
    assert all(np.all((v >= 0) & (v <= 1)) for v in out)
    n = len(out) // 3  # the starts, then each with k × 0.1, then with k × 0.01
    assert len(out) == 3 * n
    for i in range(n):
        base = out[i]
        for j, f in ((1, 0.1), (2, 0.01)):
            np.testing.assert_allclose(out[j * n + i], np.concatenate([[base[0] * f], base[1:]]), rtol=1e-12)
    assert len({tuple(np.round(v[3:], 9)) for v in out}) > 10  # a grid over the new effect's parameters


def test_time_domain_record_checks_and_split_errors():
    """The time-domain route's input checks name the test and the valid range: >= 64 samples, finite values,
    t strictly increasing, blocks 1 … n // 16; a split needs something held out and >= 3 training units."""
    from chainid.gap.timedomain import MIN_SAMPLES, prepare_time
    from chainid.gap.timeproblem import AnyProblem
    from chainid.records.record import Record

    n = 160
    t = np.arange(n) / 100.0
    x = 2.0 + 0.1 * np.sin(2 * np.pi * 1.3 * t) + 0.05 * np.sin(2 * np.pi * 3.1 * t)
    F = 1000.0 * x

    def rec(name="r", tt=t, xx=x, FF=F):
        return Record(name, tt, xx, FF)

    with pytest.raises(ValueError, match=rf"test 'r': 63 samples; the time-domain route needs >= {MIN_SAMPLES}"):
        prepare_time(rec(tt=t[:63], xx=x[:63], FF=F[:63]), 1)
    bad = F.copy()
    bad[5] = np.nan
    with pytest.raises(ValueError, match="test 'r': non-finite t, x or F"):
        prepare_time(SimpleNamespace(test="r", t=t, x=x, F=bad), 1)  # (a Record refuses NaN itself)
    tt = t.copy()
    tt[10] = tt[9]
    with pytest.raises(ValueError, match="test 'r': t must be strictly increasing"):
        prepare_time(SimpleNamespace(test="r", t=tt, x=x, F=F), 1)
    for nb in (0, 11):
        with pytest.raises(ValueError, match=rf"blocks per record = {nb} is out of range for test 'r'; valid range "
                                             r"1 to 10"):
            prepare_time(rec(), nb)
    assert prepare_time(rec(), 10).n_blocks == 10
    data = [prepare_time(rec(f"r{i}"), 1) for i in range(3)]
    with pytest.raises(ValueError, match="nothing is held out: give --holdout IDS"):
        AnyProblem(data, LinearModel(1000.0, 0.0), [], 0)
    with pytest.raises(ValueError, match=r"the split leaves 2 training unit\(s\) \(time blocks \+ harmonic tests\); "
                                         "at least 3 are needed"):
        AnyProblem(data, LinearModel(1000.0, 0.0), ["r0"], 0)


def test_library_drops_aliases_and_restricts_to_the_given_effects():
    """machine_compliance is the same physics as stiffness_level for the diagnosis (ALIASES): considered only
    when stiffness_level is not; ``effects`` restricts the library."""
    from chainid.gap.selection import library

    prob = SimpleNamespace(applicable=lambda: ["friction", "machine_compliance", "stiffness_level", "slack"])
    assert library(prob, None) == ["friction", "stiffness_level", "slack"]
    assert library(prob, ["machine_compliance", "slack"]) == ["machine_compliance", "slack"]
    assert library(prob, ["backlash"]) == []


def test_baseline_candidate_of_a_chain_and_of_a_linear_spring():
    """The chain model as given (no parameters) or the linear spring re-fitted; scored with shrinkage 0."""
    from chainid.gap.problem import Candidate
    from chainid.gap.selection import baseline_candidate

    scored = []

    def score(c, names, base_hold):  # noqa: ANN001
        scored.append((c.name, list(names), base_hold))
        c.shrinkage = 0.3
        return c

    chain = SimpleNamespace(is_chain=True, score=score, fit=lambda names: pytest.fail("a chain is not re-fitted"))
    c = baseline_candidate(chain)
    assert (c.name, c.params, c.shrinkage) == ("baseline", {}, 0.0) and scored == [("baseline", [], 1.0)]
    lin = SimpleNamespace(is_chain=False, score=score,
                          fit=lambda names: Candidate("", {"spring.k": 5.0, "spring.x_ref": 0.1}, 2))
    c = baseline_candidate(lin)
    assert (c.name, c.params["spring.k"], c.shrinkage) == ("baseline", 5.0, 0.0)


def test_bin_noise_is_the_pooled_scatter_after_a_per_bin_linear_fit():
    """σ = sqrt(Σ RSS_b / Σ(n_b − 3)) with RSS_b of a least-squares fit of F on (1, ψ, t) within each bin
    (computed here by numpy.linalg.lstsq per bin; the code uses running moments); bins with fewer than 5
    samples do not count; with none left, σ is the plain standard deviation of F."""
    from chainid.gap.prepare import _bin_noise

    rng = np.random.default_rng(5)
    B, n = 4, 200
    t = np.sort(rng.uniform(0, 10, n))
    psi = rng.uniform(0, 2 * np.pi, n)
    bins = np.minimum((psi / (2 * np.pi) * B).astype(int), B - 1)
    F = 3.0 * psi - 0.5 * t + rng.normal(0, 2.0, n)
    keep = np.ones(n, bool)
    keep[np.flatnonzero(bins == 3)[4:]] = False  # bin 3 keeps 4 samples: left out of the pool
    t, psi, bins, F = t[keep], psi[keep], bins[keep], F[keep]
    rss = dof = 0.0
    for b in range(B):
        m = bins == b
        if m.sum() < 5:
            continue
        X = np.column_stack([np.ones(m.sum()), psi[m], t[m]])
        r = F[m] - X @ np.linalg.lstsq(X, F[m], rcond=None)[0]
        rss += float(r @ r)
        dof += m.sum() - 3
    assert _bin_noise(t, F, psi, bins, B) == pytest.approx(math.sqrt(rss / dof), rel=1e-9)
    few = np.arange(8) % 4  # 2 samples per bin
    y = np.arange(8.0) ** 2
    assert _bin_noise(np.arange(8.0), y, np.linspace(0, 6, 8), few, 4) == pytest.approx(float(np.std(y)), rel=1e-12)


def test_ce_projection_and_candidate_contract():
    """c_e of a test = the count-weighted projection of F̄ − F_n on v (Eq. 27 on the cycle-mean loop): with
    F̄ − F_n = 2.5·v exactly it is 2.5; Candidate names split on '+', the baseline has none; its JSON turns
    non-finite numbers into null."""
    from chainid.gap.problem import Candidate, _ce

    v = np.array([1.0, -2.0, 0.5, 3.0])
    d = SimpleNamespace(counts=np.array([4.0, 1.0, 2.0, 3.0]), Fbar=10.0 + 2.5 * v)
    assert _ce(d, np.full(4, 10.0), v) == pytest.approx(2.5, rel=1e-12)
    w = d.counts
    Fn = np.array([9.0, 11.0, 10.0, 10.5])
    assert _ce(d, Fn, v) == pytest.approx(float(np.sum(w * (d.Fbar - Fn) * v) / np.sum(w * v * v)), rel=1e-12)
    assert Candidate("baseline", {}, 0).names == [] and Candidate("", {}, 0).names == []
    c = Candidate("friction+slack", {"friction.F_c": np.float64(3.0)}, 2, nrmse_holdout=float("nan"),
                  param_sd={"friction.F_c": float("inf")}, at_bound=("slack.s",))
    assert c.names == ["friction", "slack"]
    dct = c.to_dict()
    assert dct["effect"] == "friction+slack" and dct["params"] == {"friction.F_c": 3.0}
    assert dct["params_sd"] == {"friction.F_c": None} and dct["nrmse_holdout"] is None
    assert dct["at_bound"] == ["slack.s"] and dct["n_params"] == 2 and dct["damping_law"] == "polynomial"


def test_laws_for_and_a_given_baseline_law():
    """A candidate is scored with the baseline's law, and viscous too once it has an effect; the damping_law
    effect tries the other forms that n_train − 1 coefficients allow.  A given law is refused when unknown or
    when it has more coefficients than n_train − 1 (the messages name the value and the valid choices)."""
    from chainid.gap.law_choice import ALT_LAWS
    from chainid.gap.problem import Problem

    p = SimpleNamespace(train=[0] * 4, law="coulomb")
    assert Problem.laws_for(p, []) == ["coulomb"] and Problem.laws_for(p, ["friction"]) == ["coulomb", "viscous"]
    assert Problem.laws_for(SimpleNamespace(train=[0] * 4, law="viscous"), ["friction"]) == ["viscous"]
    assert Problem.laws_for(p, ["damping_law"]) == [k for k in ALT_LAWS if k != "coulomb"]  # <= 3 coefficients
    p2 = SimpleNamespace(train=[0] * 2, law="viscous")
    assert Problem.laws_for(p2, ["damping_law"]) == ["coulomb", "hysteretic"]  # 1 coefficient <= 2 − 1
    assert Problem.laws_for(SimpleNamespace(train=[0], law="viscous"), ["damping_law"]) == ["viscous"]
    fake = SimpleNamespace(train=[0] * 4)
    assert Problem._baseline_law(fake, "viscous+coulomb") == ("viscous+coulomb", "given")
    with pytest.raises(ValueError, match=r"--damping-law = 'cubic' is unknown; valid: auto, polynomial, viscous, "
                                         r"coulomb, viscous\+coulomb, hysteretic"):
        Problem._baseline_law(fake, "cubic")
    with pytest.raises(ValueError, match=r"--damping-law polynomial has 5 coefficients; with 4 training tests at most "
                                         "3 can be scored leave-one-out"):
        Problem._baseline_law(fake, "polynomial")
    assert Problem._baseline_law(SimpleNamespace(train=[0] * 6), "polynomial") == ("polynomial", "given")


def test_run_benchmark_checks_its_output_before_the_work_and_writes_the_summary(tmp_path, monkeypatch, capsys):
    """An existing --json target is refused before any case runs (files are sacred); with overwrite the summary
    is written (strict JSON) and printed; the rows are the run's, one per case of the grid."""
    import json

    import chainid.infra.parallel
    from chainid.gap import benchmark as bm

    ran = []

    def run_cases(fn, cases, **kw):  # noqa: ANN001
        ran.append(len(cases))
        return [c | {"verdict": "none", "snr": 0.0, "shrinkage": None, "seconds": 1.0} for c in cases]

    monkeypatch.setattr(chainid.infra.parallel, "run_cases", run_cases)
    out = tmp_path / "b.json"
    out.write_text("mine")
    with pytest.raises(Exception, match="--json"):
        bm.run_benchmark(small=True, json_path=str(out), excitations=("harmonic",), progress=False)
    assert ran == [] and out.read_text() == "mine"
    s = bm.run_benchmark(small=True, json_path=str(out), overwrite=True, excitations=("harmonic",), progress=False)
    n = len(bm.grid(small=True, excitations=("harmonic",)))
    assert ran == [n] and s["n_cases"] == n and s["control_none_rate"] == 1.0
    doc = json.loads(out.read_text())
    assert doc["n_cases"] == n and len(doc["rows"]) == n and doc["wall_seconds"] >= 0
    assert "control gives none: 100.0 % of 1 (target >= 95 %)" in capsys.readouterr().out


# ---------------------------------------------------------------- timedomain helpers by hand

def test_reversals_travel_and_blocks_by_hand():
    from chainid.gap.timedomain import reversals, split_blocks, travel_since_reversal

    xd = np.array([1.0, 2.0, 0.0, -1.0, -2.0, 0.0, 0.0, 3.0, 1.0])
    assert list(reversals(xd)) == [3, 7]  # the sample after each sign change (zeros skipped)
    assert reversals(np.array([0.0, 1.0, 0.0])).size == 0
    x = np.array([0.0, 1.0, 2.0, 1.5, 1.0, 0.5, 0.5, 1.0, 3.0])
    np.testing.assert_allclose(travel_since_reversal(x, xd), [0, 1, 2, 0, 0.5, 1.0, 1.0, 0, 2.0])
    a = SimpleNamespace(test="a", n_blocks=3)
    b = SimpleNamespace(test="b", n_blocks=2)
    tr, ho = split_blocks([a, b], ["b"], 0)
    assert [(d.test, k) for d, k in tr] == [("a", 0), ("a", 1), ("a", 2)]
    assert [(d.test, k) for d, k in ho] == [("b", 0), ("b", 1)]
    tr, ho = split_blocks([a, b], [], 2)
    assert [(d.test, k) for d, k in tr] == [("a", 0), ("a", 1), ("b", 0)]
    assert [(d.test, k) for d, k in ho] == [("a", 2), ("b", 1)]


def test_undamped_force_of_each_effect_on_a_linear_spring_by_hand():
    """F_n = m·ẍ·1e-3 + k(x − x_ref) plus: friction (F_c + μ|F_k|)·sgn-with-stick; hysteresis the Dahl operator;
    backlash k(play(x, b/2) − x_ref) instead of k(x − x_ref); sensor_delay everything at t − τ (linear
    interpolation); damping_law nothing; slack needs a chain model (a chain-only effect)."""
    from chainid.gap.timedomain import undamped
    from chainid.model.effects import dahl_operator, play_operator, stick_slip

    t = np.linspace(0.0, 2.0, 401)
    x = 1.0 + 0.3 * np.sin(2 * np.pi * t)
    xd = 0.6 * np.pi * np.cos(2 * np.pi * t)
    xdd = -1.2 * np.pi ** 2 * np.sin(2 * np.pi * t)
    d = SimpleNamespace(t=t, x=x, xd=xd, xdd=xdd)
    k, xr, m = 100.0, 0.2, 50.0
    spring = LinearModel(k, xr, mass=m)
    Fk = k * (x - xr)
    base = m * xdd * 1e-3 + Fk
    F, v = undamped([], {}, spring, d)
    np.testing.assert_allclose(F, base, rtol=1e-12)
    np.testing.assert_array_equal(v, xd)
    F, _ = undamped(["friction"], {"friction.F_c": 5.0, "friction.mu": 0.01}, spring, d)
    np.testing.assert_allclose(F, base + (5.0 + 0.01 * np.abs(Fk)) * stick_slip(x, xd, 0.0, periodic=False),
                               rtol=1e-12)
    F, _ = undamped(["hysteresis"], {"hysteresis.F_h": 7.0, "hysteresis.x_h": 0.05}, spring, d)
    np.testing.assert_allclose(F, base + dahl_operator(x, 7.0, 0.05, periodic=False), rtol=1e-12)
    F, _ = undamped(["backlash"], {"backlash.b": 0.1}, spring, d)
    np.testing.assert_allclose(F, m * xdd * 1e-3 + k * (play_operator(x, 0.05, periodic=False) - xr), rtol=1e-12)
    with pytest.raises(ValueError, match="effect 'slack' needs a chain model"):  # slack is chain-only
        undamped(["slack"], {"slack.s": 0.04}, spring, d)
    F, v = undamped(["sensor_delay", "damping_law"], {"sensor_delay.tau": 0.01}, spring, d)
    xl, xdl, xddl = (np.interp(t - 0.01, t, y) for y in (x, xd, xdd))
    np.testing.assert_allclose(F, m * xddl * 1e-3 + k * (xl - xr), rtol=1e-12)
    np.testing.assert_allclose(v, xdl, rtol=1e-12)
    idx = np.array([3, 50, 200])
    F, v = undamped(["hysteresis"], {"hysteresis.F_h": 7.0, "hysteresis.x_h": 0.05}, spring, d, idx)
    np.testing.assert_allclose(F, (base + dahl_operator(x, 7.0, 0.05, periodic=False))[idx], rtol=1e-12)


def test_time_data_blocks_and_properties():
    """Blocks contiguous in time, sample i in block floor(i·K/n); A half the range, x0 the mean, ω the spectral
    peak of x; the fit subset every q-th sample with q = min(fs/(40·band), ceil(n/4000)) (at least 1)."""
    from chainid.gap.timedomain import prepare_time
    from chainid.records.record import Record

    n, fs = 1000, 200.0
    t = np.arange(n) / fs
    x = 2.0 + 0.5 * np.sin(2 * np.pi * 2.0 * t)
    d = prepare_time(Record("r", t, x, 100.0 * x), 3)
    assert list(d.block) == [min(i * 3 // n, 2) for i in range(n)]
    assert d.A == pytest.approx(0.5 * np.ptp(d.x)) and d.x0 == pytest.approx(float(np.mean(d.x)))
    assert d.omega == pytest.approx(2 * np.pi * 2.0, rel=0.03)
    q = max(1, min(int(fs / (40 * d.f_band)), int(math.ceil(n / 4000))))
    assert list(d.fit_idx) == list(range(0, n, q))
    assert d.window == f"time domain, {n} samples, band {d.f_band:.3g} Hz, 3 blocks"


# ---------------------------------------------------------------- where.localise: the findings by hand

def _localise(C=30.0, tau=0.0):
    from chainid.gap.where import localise

    B = 64
    psi = (np.arange(B) + 0.5) * 2 * math.pi / B
    data = [SimpleNamespace(test=f"T{i}", sigma=1.0, counts=np.full(B, 10.0), omega=w, A=A, x0=2.0,
                            Fbar=1000.0 + 500.0 * np.sin(psi - w * tau) + C * np.cos(psi))
            for i, (w, A) in enumerate([(10.0, 0.2), (20.0, 0.3), (30.0, 0.4)])]
    base = {"res": {d.test: C * np.cos(psi) for d in data}, "per_test": {d.test: 0.1 * (i + 1) for i, d in
                                                                          enumerate(data)},
            "c_e": {d.test: 1.0 for d in data}}
    prob = SimpleNamespace(data=data, hold=data[:1], train=data[1:], sigma_raw=1.0, ke={d.test: 5000.0 for d in data})
    return {f["kind"]: f for f in localise(prob, base)}, localise(prob, base)


def test_localise_level_branch_and_energy_by_hand():
    """Residual C·cos ψ (C = 30 N) in every test: RMS C/√2 = 21.21 N against a cycle-mean floor σ/√10 = 0.316 N
    (36.5 dB); the loading branch (cos ψ > 0) averages +2C/π, the unloading −2C/π: a difference of 4C/π =
    +38.2 N; c_e = 1 everywhere makes W = π·c_e·ω·A², slopes (2, 1): viscous; no delay (the phase of F is the
    same at every ω)."""
    kinds, found = _localise()
    lv = kinds["level"]
    assert lv["rms_N"] == pytest.approx(30 / math.sqrt(2), rel=1e-9)
    assert lv["noise_floor_N"] == pytest.approx(1 / math.sqrt(10), rel=1e-12)
    assert lv["finding"] == ("baseline residual RMS 21.21 N, 36.5 dB over the cycle-averaged noise floor 0.316 N "
                             "(noise σ = 1 N from cycle-to-cycle scatter)")
    br = kinds["branch"]
    assert br["difference_N"] == pytest.approx(4 * 30 / math.pi, rel=1e-3)
    assert br["finding"].startswith("loading vs unloading branch: mean residual differs by +38.2 N")
    en = kinds["energy"]
    assert (en["slope_A"], en["slope_omega"]) == (pytest.approx(2.0, abs=1e-9), pytest.approx(1.0, abs=1e-9))
    assert "(closest form: viscous;" in en["finding"]
    assert "delay" not in kinds
    tests = [f for f in found if f["kind"] == "test"]
    assert [f["test"] for f in tests] == ["T0", "T1", "T2"]  # all equal RMS: the data's order
    assert tests[0]["finding"].startswith("test T0 (held-out; ω=10 rad/s, A=0.2 mm, x0=2 mm): NRMSE 0.1, residual "
                                          "RMS 21.2 N, signed energy error")
    assert tests[1]["finding"].startswith("test T1 (training;")
    # the energy error per cycle ∮ r dx = π·A·C (a viscous excess dissipates)
    assert [f["energy_error_Nmm"] for f in tests] == pytest.approx([math.pi * A * 30 for A in (0.2, 0.3, 0.4)],
                                                                   rel=1e-9)
    assert [f["score"] for f in found] == sorted((f["score"] for f in found), reverse=True)


def test_localise_names_a_force_channel_lag():
    """F(ψ − ωτ) with τ = 5 ms: the fundamental's phase falls as −ωτ over ω = 10 … 30 rad/s (R² = 1, ωτ_max =
    0.15 >= 0.05): a delay finding with slope −5 ms."""
    kinds, _ = _localise(C=0.0, tau=0.005)
    dl = kinds["delay"]
    assert dl["tau_s"] == pytest.approx(0.005, rel=1e-9) and dl["phase1_r2"] == pytest.approx(1.0, abs=1e-6)
    assert dl["finding"].startswith("delay signature: the phase of F against x falls linearly with ω across tests "
                                    "(slope -5 ms, R² 1.000")
    assert "delay" not in _localise(C=0.0, tau=0.0015)[0]  # ωτ_max = 0.045 < 0.05
    assert "delay" in _localise(C=0.0, tau=0.0017)[0]  # 0.051


def test_contract_ranking_best_and_chain_text_by_hand():
    """The JSON contract: ranking = the single effects and the chain's multi-effect steps, by LOTO NRMSE; best
    = the chain's last step (else the best single); left NRMSE = the last step's (else the baseline's);
    chain_text = the step texts joined by arrows and the dB left; private keys carry the objects."""
    from chainid.gap.problem import Candidate
    from chainid.gap.verdict import contract

    def cand(name, loto, hold, params=None):
        c = Candidate(name, params or {}, len(params or {}), nrmse_loto=loto, nrmse_holdout=hold)
        return c

    base = cand("baseline", 0.9, 0.8)
    f = cand("friction", 0.4, 0.3, {"friction.F_c": 12.0})
    s = cand("slack", 0.5, 0.6, {"slack.s": 0.1})
    fs = cand("friction+slack", 0.2, 0.1, {"friction.F_c": 11.0, "slack.s": 0.05})
    prob = SimpleNamespace(law="viscous", law_reason="given")
    model = SimpleNamespace(name="chain")
    fwd = {"path": [base, f, fs], "singles": [s, f], "stop": "S", "dropped": []}
    out = contract(prob, model, base, {"noise_sigma_N": 2.0}, fwd, "friction+slack", "", {"db_over_noise": 1.26},
                   [], [], [], [], ["h"], [])
    assert [r["effect"] for r in out["ranking"]] == ["friction+slack", "friction", "slack"]
    assert out["best"]["effect"] == "friction+slack" and out["left_nrmse_holdout"] == 0.1
    assert [st["effect"] for st in out["steps"]] == ["baseline", "friction", "slack"]
    # each step names its newest effect with that effect's parameters at the step's fit
    assert out["chain_text"] == ("baseline [held-out NRMSE 0.8] → friction F_c = 12 N [held-out NRMSE 0.3] → "
                                 "slack s = 0.05 mm [held-out NRMSE 0.1] → residual 1.3 dB over noise")
    assert out["baseline"]["model"] == "chain" and out["baseline"]["damping_law"] == "viscous"
    assert out["baseline"]["noise_sigma_N"] == 2.0 and out["mechanism"] == "friction+displacement offset"
    assert out["_best"] is fs and out["_path"] == [base, f, fs] and out["_problem"] is prob
    none = contract(prob, model, base, {}, {"path": [base], "singles": [s, f], "stop": "S", "dropped": []}, "none",
                    "", {"db_over_noise": 0.0}, [], [], [], [], ["h"], [])
    assert none["best"]["effect"] == "friction" and none["left_nrmse_holdout"] == 0.8
    assert none["steps"][0]["effect"] == "baseline" and len(none["steps"]) == 1
    empty = contract(prob, model, base, {}, {"path": [base], "singles": [], "stop": "S", "dropped": []}, "none",
                     "", {"db_over_noise": 0.0}, [], [], [], [], ["h"], [])
    assert empty["best"] is None and empty["_best"] is None
