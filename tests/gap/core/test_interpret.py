"""Interpretation of the chosen effects (chainid.gap.core.interpret): step texts, mechanisms, separating tests,
the step dict of the JSON."""
from __future__ import annotations

from types import SimpleNamespace

import pytest

from chainid.gap.core import interpret


def test_step_texts_by_hand():
    from chainid.gap.core.interpret import step_text

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
    # an sd the refits did not resolve (None in the JSON) says so, never "± 0"
    assert step_text({"effect": "friction", "params": {"friction.x_s": 1.4e-05},
                      "params_sd": {"friction.x_s": None}}) == "friction x_s = 1.4e-05 (sd not resolved) mm"


def test_mechanism_joins_families_once_and_separating_test_of_stiffness_pairs():
    from chainid.gap.core.interpret import mechanism, separating_test

    assert mechanism("stiffness_level+machine_compliance+sensor_delay", "") == "stiffness+instrumentation"
    assert mechanism("friction+hysteresis", "Dahl friction (x_h << A)") == "friction"
    assert mechanism("damping_law+backlash", "") == "damping form+play"
    assert separating_test("slack", "contact_law").startswith("tests over a wider mean-load range x0")
    assert separating_test("damping_law", "backlash").startswith("tests over a wider amplitude range at fixed ω")
    assert separating_test("friction", "backlash").startswith("tests over a wider amplitude range at fixed ω")


def test_interpretation_dahl_and_stiffness_level_by_hand():
    """Dahl friction when x_h < A_min/2; a stiffness level s on a model with a linear coefficient c_lin [mm/N] is
    a series compliance c_lin·(1/s − 1)."""
    from chainid.gap.core.interpret import interpretation

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


def test_bouc_wen_that_unloads_elastically_with_a_sharp_knee_reads_as_a_rounded_jenkins_slider():
    """dz/dx = (1/x_y)·[1 − (r·sgn(ẋz) + 1 − r)·|z|^n]: unloading (ẋz < 0) has slope (1 − (1 − 2r)·|z|^n)/x_y, the
    elastic 1/x_y for r = 1/2 — a Jenkins slider (slip force F_y, stick stiffness F_y/x_y = 3/0.02 = 150 N/mm)
    whose slip corner the knee n rounds.  Read so for |1 − 2r| <= 0.2, n >= 4 and x_y < A_min/2; not for r = 0.65
    (|1 − 2r| = 0.3), n = 3 or x_y = A_min/2; the mechanism is then friction."""
    from chainid.gap.core.interpret import interpretation, mechanism

    prob = SimpleNamespace(data=[SimpleNamespace(A=0.3), SimpleNamespace(A=0.1)], model=SimpleNamespace())
    base = SimpleNamespace(names=(), params={})
    p = {"bouc_wen.F_y": 3.0, "bouc_wen.x_y": 0.02, "bouc_wen.n": 6.0, "bouc_wen.r": 0.55}
    text = interpretation([base, SimpleNamespace(names=("bouc_wen",), params=p)], prob, "bouc_wen")
    assert text == ("Bouc–Wen with elastic unloading (r = 0.55) and a sharp knee (n = 6), yield travel x_y = 0.02 mm "
                    "<< A (>= 0.1 mm): an elastic–plastic slider, Coulomb friction F_y = 3 N with stick stiffness "
                    "F_y/x_y = 150 N/mm, its slip corner rounded (Jenkins friction)")
    assert mechanism("bouc_wen", text) == "friction" and mechanism("bouc_wen", "") == "hysteresis"
    for change in ({"bouc_wen.r": 0.65}, {"bouc_wen.n": 3.0}, {"bouc_wen.x_y": 0.05}):
        fin = SimpleNamespace(names=("bouc_wen",), params=p | change)
        assert interpretation([base, fin], prob, "bouc_wen") == "", change


def test_step_dict_is_the_json_contract_of_a_step():
    """The step's keys (docs/guide/trust.md): non-finite numbers None, spring.* parameters left out; the held-out
    fit % = 100·(1 − NRMSE_holdout), the residual over noise 10^(dB/20) (3 dB: 1.41254), ``worsened_holdout``
    when the step's held-out NRMSE is above the step before's, and ``c_e_tied_to_law``."""
    from chainid.gap.core.interpret import step_dict

    c = SimpleNamespace(names=("friction", "slack"), params={"spring.k": 1.0, "friction.F_c": 3.0, "slack.s": 0.1},
                        param_sd={"friction.F_c": float("nan"), "slack.s": 0.01, "spring.k": 0.5}, law="viscous",
                        nrmse_loto=0.1, nrmse_holdout=float("inf"), shrinkage=0.7, db_holdout=3.0,
                        step_test={"z": 4.5, "relative_gain": 0.3}, at_bound=("slack.s",))
    d = step_dict(c, 2)
    assert d.pop("residual_over_noise") == pytest.approx(1.4125375446, rel=1e-9)
    assert d == {
        "effect": "slack", "effects": ("friction", "slack"), "params": {"friction.F_c": 3.0, "slack.s": 0.1},
        "params_sd": {"friction.F_c": None, "slack.s": 0.01}, "damping_law": "viscous", "nrmse_loto": 0.1,
        "nrmse_holdout": None, "shrinkage": 0.7, "db_over_noise": 3.0, "z_loto": 4.5, "relative_gain_loto": 0.3,
        "at_bound": ["slack.s"], "fit_holdout_pct": None, "worsened_holdout": False, "c_e_tied_to_law": False}
    c.tied_law = "viscous"  # the harmonic route's fit tied each test's c_e to the law
    assert step_dict(c, 2)["c_e_tied_to_law"] is True
    c.step_test = {}
    d = step_dict(c, 0)
    assert d["effect"] == "baseline" and d["z_loto"] is None and d["relative_gain_loto"] is None
    # a finite held-out NRMSE 0.25 after a step at 0.2: fit 75 %, worse than the step before; at 0.3 before: not
    c.nrmse_holdout, c.db_holdout = 0.25, float("nan")
    d = step_dict(c, 1, SimpleNamespace(nrmse_holdout=0.2))
    assert d["fit_holdout_pct"] == pytest.approx(75.0, rel=1e-12) and d["residual_over_noise"] is None
    assert d["worsened_holdout"] is True
    assert step_dict(c, 1, SimpleNamespace(nrmse_holdout=0.3))["worsened_holdout"] is False


def test_mechanism_names_and_separating_tests():
    assert interpret.mechanism("friction+backlash+slack", "") == "friction+play+displacement offset"
    assert interpret.mechanism("stiffness_level+contact_law", "") == "stiffness"
    assert interpret.mechanism("hysteresis", "Dahl friction (x_h << A)") == "friction"
    assert interpret.mechanism("hysteresis", "") == "hysteresis"
    assert interpret.mechanism("none", "") == "none" and interpret.mechanism("unexplained", "") == "unexplained"
    assert interpret.separating_test("hysteresis", "friction").startswith("a small-amplitude test")
    assert "frequency range" in interpret.separating_test("sensor_delay", "friction")
    assert "amplitude range" in interpret.separating_test("damping_law", "slack")
    assert "mean-load range" in interpret.separating_test("slack", "stiffness_level")


def test_separating_test_of_a_richer_effect_against_its_member_and_a_second_cause():
    """``stribeck`` ~ ``friction+slack``: the Stribeck shape that Coulomb friction lacks, then what separates
    Stribeck from the second cause (slack: a stiffness-side effect, by the mean load); ``bouc_wen`` ~
    ``hysteresis+friction``: the Bouc–Wen loop, then friction's amplitude test."""
    from chainid.gap.core.interpret import RICHER_SHAPE, separating_test

    assert separating_test("stribeck", "friction+slack") == (
        RICHER_SHAPE["stribeck"] + "; then tests over a wider mean-load range x0 (stiffness-side effects scale "
        "differently with load) for slack")
    assert separating_test("hysteresis+friction", "bouc_wen") == (
        RICHER_SHAPE["bouc_wen"] + "; then tests over a wider amplitude range at fixed ω (Coulomb ∝ 1/A, viscous ∝ 1) "
        "for friction")


def test_separating_test_of_two_chains_that_differ_by_one_effect_each_is_that_pairs():
    """``friction+slack`` ~ ``hysteresis+slack`` differ only in friction against hysteresis: the small-amplitude
    test separates them, as it does the two effects alone."""
    from chainid.gap.core.interpret import separating_test

    assert separating_test("friction+slack", "hysteresis+slack") == separating_test("friction", "hysteresis")
    assert separating_test("friction+slack", "hysteresis+slack").startswith("a small-amplitude test")
    assert separating_test("sensor_delay+backlash", "friction+backlash").startswith("tests over a wider frequency")


def test_two_chains_whose_difference_lies_on_one_side_get_no_pair_advice():
    """``friction+hysteresis+slack`` ~ ``slack``: the difference (friction, hysteresis) is all on one side, so it is
    not a contest of friction against hysteresis; the general advice (the mean-load range) is given."""
    from chainid.gap.core.interpret import separating_test

    got = separating_test("friction+hysteresis+slack", "slack")
    assert not got.startswith("a small-amplitude test") and got.startswith("tests over a wider mean-load range")
