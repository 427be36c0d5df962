"""Why each candidate of a stopped step was not taken (chainid.gap.core.selection.rejections, stop_message): the
boundary of the significance rule, the order, and the stop text when the best by LOTO is already identified."""
from __future__ import annotations

from chainid.gap.core.selection import rejections, stop_message
from chainid.gap.harmonic.problem import Candidate


def _cand(name: str, loto: float, st: dict | None = None, at_bound: tuple = ()) -> Candidate:
    c = Candidate(name, {}, 1, nrmse_loto=loto, nrmse_holdout=0.5, at_bound=list(at_bound))
    if st is not None:
        c.step_test = st
    return c


def test_a_mean_gain_of_exactly_two_se_is_not_significant():
    """Rule 2 is strict: delta = 2·SE fails it (not significant); delta 2.01·SE passes, so the reason is
    materiality: 5 % gain, printed 5.0 % (needs >= 10 %)."""
    st = {"delta_loto": 0.2, "se_jackknife": 0.1, "relative_gain": 0.05}
    (r,) = rejections([_cand("slack", 0.4, st)])
    assert r["reason"] == ("not significant over the training units: mean log error ratio 0.2, jack-knife SE 0.1 "
                           "(needs > 2 SE)")
    (r,) = rejections([_cand("slack", 0.4, st | {"delta_loto": 0.201})])
    assert r["reason"] == "not material: lowers the LOTO NRMSE by 5.0 % (needs >= 10 %)"
    assert r["relative_gain_loto"] == 0.05


def test_rejections_best_loto_first_and_unscored_candidates_say_so():
    out = rejections([_cand("slack", 0.6), _cand("friction", 0.4), _cand("backlash", 0.5, at_bound=("backlash.b",))])
    assert [r["effect"] for r in out] == ["friction", "backlash", "slack"]
    assert out[0]["reason"] == "not scored against the chain"
    assert out[1]["reason"].startswith("parameter(s) backlash.b at the bound")


def test_stop_message_names_a_second_effect_only_when_the_best_is_pinned():
    """The best by LOTO without a pinned parameter is itself the best identified one: one clause; the effect that
    follows a pinned one is named in a second clause."""
    free = {"effect": "friction", "nrmse_loto": 0.4, "reason": "not material"}
    pinned = {"effect": "backlash", "nrmse_loto": 0.3, "reason": "parameter(s) backlash.b at the bound"}
    assert stop_message([free, pinned | {"nrmse_loto": 0.5}]) == (
        "no next effect passes the step rule: the best by LOTO, friction (LOTO NRMSE 0.4), was not taken: not "
        "material")
    assert stop_message([pinned, free]).endswith("; the best identified one, friction (LOTO NRMSE 0.4): not material")
    assert stop_message([pinned]) == ("no next effect passes the step rule: the best by LOTO, backlash (LOTO NRMSE "
                                      "0.3), was not taken: parameter(s) backlash.b at the bound")
    assert stop_message([]) == "no library effect left"
