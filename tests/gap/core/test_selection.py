"""The forward selection of effects (chainid.gap.core.selection) on hand-made tables of fits: the step rule, near
ties, look-ahead, exchange and backward passes, the noise floor, the library and the baseline candidate."""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from chainid.gap.core import selection as fw
from chainid.gap.core.selection import TIE, pick as _pick
from chainid.gap.harmonic.problem import Candidate
from selection_tables import table_world


def _world(monkeypatch, table, floor=()):
    """Fits looked up in ``table`` (:func:`selection_tables.table_world`, BIC 10 per parameter)."""
    return table_world(monkeypatch, table, floor)


TABLE = {("friction",): (0.5, (25.0, 25.0, 16.0), (), 1),
         ("slack",): (0.95, (90.0, 90.0, 90.0), (), 1),
         ("friction", "slack"): (0.48, (24.0, 24.0, 15.0), (), 2)}


def test_forward_selection_stops_on_an_immaterial_step_by_hand(monkeypatch):
    """Step 1: friction lowers the LOTO NRMSE by 50 % with g_i = ½ln(100/25), ½ln(100/25), ½ln(100/16) (all > 0,
    mean far above 2 SE): kept; slack (5 %) is not material.  Step 2: slack on top lowers it by 4 % (1 − 0.48/0.5)
    with a mean log error ratio above 2 SE: significant but not material, the chain stops, and the stop text names
    the best rejected candidate and the rule it failed with its numbers.  With slack on top at 0.40 (20 %, material)
    but carried by one test (g = ½ln(25/10), 0, 0: mean = SE, not > 2 SE) it stops as not significant."""
    sel, base, calls = _world(monkeypatch, TABLE)
    out = sel.forward_select(None, ["friction", "slack"], base, 1.0)
    assert [c.names for c in out["path"]] == [[], ["friction"]]
    assert sorted(c.name for c in out["singles"]) == ["friction", "slack"]
    g = 0.5 * np.log(np.array([25.0, 25.0, 16.0]) / [24.0, 24.0, 15.0])
    se = float(np.std(g, ddof=1)) / math.sqrt(3)
    assert g.mean() > 2 * se  # significant: the rule it fails is materiality (4 % < 10 %)
    assert out["stop"] == ("no next effect passes the step rule: the best by LOTO, slack (LOTO NRMSE 0.48), was not "
                           "taken: not material: lowers the LOTO NRMSE by 4.0 % (needs >= 10 %)")
    (rej,) = out["rejected"]
    assert (rej["effect"], rej["nrmse_loto"]) == ("slack", 0.48)
    assert rej["relative_gain_loto"] == pytest.approx(1 - 0.48 / 0.5, rel=1e-12)
    st = out["path"][1].step_test
    g1 = 0.5 * np.log(100.0 / np.array([25.0, 25.0, 16.0]))
    assert st["delta_loto"] == pytest.approx(g1.mean(), rel=1e-12)
    assert st["se_jackknife"] == pytest.approx(np.std(g1, ddof=1) / math.sqrt(3), rel=1e-12)
    assert st["relative_gain"] == pytest.approx(0.5, rel=1e-12)
    assert out["confounded"] == [] and out["dropped"] == [] and out["swapped"] == []
    one = dict(TABLE) | {("friction", "slack"): (0.40, (10.0, 25.0, 16.0), (), 2)}
    g = 0.5 * np.log(np.array([25.0, 25.0, 16.0]) / [10.0, 25.0, 16.0])
    se = float(np.std(g, ddof=1)) / math.sqrt(3)
    assert g.mean() == pytest.approx(se, rel=1e-12)  # not > 2 SE
    sel, base, _ = _world(monkeypatch, one)
    out = sel.forward_select(None, ["friction", "slack"], base, 1.0)
    assert [c.names for c in out["path"]] == [[], ["friction"]]
    assert out["stop"] == ("no next effect passes the step rule: the best by LOTO, slack (LOTO NRMSE 0.4), was not "
                           f"taken: not significant over the training units: mean log error ratio {g.mean():.3g}, "
                           f"jack-knife SE {se:.2g} (needs > 2 SE)")


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
    assert out["stop"] == ("no next effect passes the step rule: the best by LOTO, friction (LOTO NRMSE 0.5), was not "
                           "taken: parameter(s) friction.p at the bound of their physical range: its form does not fit "
                           "what is left")
    assert len(out["path"]) == 1 and len(out["singles"]) == 2
    # the best identified one (no parameter at a bound) is named too when it is another: slack, 1 − 0.95 = 5 %
    sel, base, _ = _world(monkeypatch, pinned | {("slack",): (0.95, (90.0, 90.0, 90.0), (), 1)})
    out = sel.forward_select(None, ["friction", "slack"], base, 1.0)
    assert out["stop"] == ("no next effect passes the step rule: the best by LOTO, friction (LOTO NRMSE 0.5), was not "
                           "taken: parameter(s) friction.p at the bound of their physical range: its form does not fit "
                           "what is left; the best identified one, slack (LOTO NRMSE 0.95): not material: lowers the "
                           "LOTO NRMSE by 5.0 % (needs >= 10 %)")
    assert len(out["path"]) == 1


def test_forward_selection_near_tie_is_confounded_and_look_ahead_takes_the_runner_up(monkeypatch):
    """Hysteresis (2 parameters) within TIE = 5 % of friction (1): friction is chosen, the pair is reported as
    confounded.  The runner-up is within LOOKAHEAD = 30 %; its best extension (hysteresis+slack, a step the rule
    takes) must beat the choice's best (friction+slack, 0.44, a 12 % step) by more than TIE to be taken: 0.43 is not
    (> 0.95·0.44 = 0.418), 0.40 is."""
    base_table = dict(TABLE) | {("hysteresis",): (0.51, (26.0, 26.0, 17.0), (), 2),
                                ("friction", "slack"): (0.44, (20.0, 20.0, 13.0), (), 2),
                                ("friction", "hysteresis"): (0.49, (24.5, 24.5, 15.5), (), 3)}
    sel, base, _ = _world(monkeypatch, base_table | {("hysteresis", "slack"): (0.43, (20.5, 20.5, 13.3), (), 3)})
    out = sel.forward_select(None, ["friction", "slack", "hysteresis"], base, 1.0, max_effects=2)
    assert [c.names for c in out["path"]][1:] == [["friction"], ["friction", "slack"]]
    assert out["confounded"][0] == {"step": 1, "pair": ["friction", "hysteresis"], "loto": [0.5, 0.51]}
    sel, base, _ = _world(monkeypatch, base_table | {("hysteresis", "slack"): (0.40, (10.0, 10.0, 6.0), (), 3)})
    out = sel.forward_select(None, ["friction", "slack", "hysteresis"], base, 1.0, max_effects=2)
    assert [c.names for c in out["path"]][1:] == [["hysteresis"], ["hysteresis", "slack"]]


def test_step_rule_boundaries():
    """Rule 2: mean log ratio > Z = 2 jack-knife SE (strict); rule 3: relative gain >= MIN_GAIN = 10 %."""
    from chainid.gap.harmonic.problem import Candidate
    from chainid.gap.core.selection import loto_jackknife, passes, step_test

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


def test_look_ahead_counts_only_extensions_the_step_rule_would_take(monkeypatch):
    """Friction (0.5) is chosen over sensor_delay (0.51, within LOOKAHEAD).  Sensor_delay+slack (0.35) would beat
    friction+slack (0.44, a 12 % step that passes) by more than TIE, but it is not a step the rule takes: with
    slack's parameter at a bound (rule 4), or carried by one test (SSE 12, 26, 17 after 26, 26, 17: g = (0.39, 0, 0),
    mean = SE, not > 2 SE: rule 2); friction+sensor_delay (0.49) is a 3.9 % step from sensor_delay (rule 3).  The
    runner-up's path ends at 0.51, so friction stays.  With slack inside its bounds and the gain on every test the
    runner-up is taken (0.35 < 0.95·0.44); with the runner-up at its training noise floor (rule 1) it is not."""
    table = dict(TABLE) | {("sensor_delay",): (0.51, (26.0, 26.0, 17.0), (), 1),
                           ("friction", "slack"): (0.44, (20.0, 20.0, 13.0), (), 2),
                           ("friction", "sensor_delay"): (0.49, (24.5, 24.5, 15.5), (), 2),
                           ("sensor_delay", "slack"): (0.35, (12.0, 12.0, 8.0), ("slack.p",), 2)}
    one_test = table | {("sensor_delay", "slack"): (0.35, (12.0, 26.0, 17.0), (), 2)}
    free = table | {("sensor_delay", "slack"): (0.35, (12.0, 12.0, 8.0), (), 2)}
    for world, floor, runner_up in ((table, (), False), (one_test, (), False), (free, (), True),
                                    (free, {("sensor_delay",)}, False)):
        sel, base, _ = _world(monkeypatch, world, floor)
        out = sel.forward_select(None, ["friction", "slack", "sensor_delay"], base, 1.0, max_effects=2)
        first = "sensor_delay" if runner_up else "friction"
        assert out["path"][1].names == [first], (world, floor)


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


def _cand(nums: dict[str, float], loto: float) -> Candidate:
    c = Candidate("x", {}, 0, nrmse_loto=loto)
    c.loto_num = nums
    return c


def test_step_rule_by_hand():
    # g_i = ½ ln(a_i/b_i): every test's error falls 4× → g = ln 2 each, no spread: significant
    a = {"1": 4.0, "2": 8.0, "3": 12.0}
    d, se = fw.loto_jackknife(_cand(a, 1.0), _cand({k: v / 4 for k, v in a.items()}, 0.5))
    assert d == pytest.approx(math.log(2.0), rel=1e-12)
    assert se == pytest.approx(0.0, abs=1e-12)
    # one test improves 100×, the others not at all: mean g = ½ ln(100)/3, sd/√3 of [2.303, 0, 0]
    d, se = fw.loto_jackknife(_cand(a, 1.0), _cand({"1": 0.04, "2": 8.0, "3": 12.0}, 0.9))
    g = np.array([0.5 * math.log(100.0), 0.0, 0.0])
    assert d == pytest.approx(g.mean(), rel=1e-12)
    assert se == pytest.approx(g.std(ddof=1) / math.sqrt(3), rel=1e-12)
    assert not d > fw.Z * se  # one test cannot carry a step
    # the step rule as applied: significance over the tests and a material drop (>= 10 %) of the pooled error
    st = fw.step_test(_cand(a, 1.0), _cand({"1": 0.04, "2": 8.0, "3": 12.0}, 0.8))
    assert st["relative_gain"] == pytest.approx(0.2) and not fw.passes(st)  # material, but carried by one test
    assert fw.passes(fw.step_test(_cand(a, 1.0), _cand({k: v / 4 for k, v in a.items()}, 0.5)))
    # significant but not material: every test 1 % better, pooled NRMSE only 0.5 % lower
    st = fw.step_test(_cand(a, 1.0), _cand({k: v * 0.99 for k, v in a.items()}, 0.995))
    assert st["relative_gain"] == pytest.approx(0.005, rel=1e-9) and not fw.passes(st)
    # noise floor: χ² ratio within 5 sd of 1, or an excess below half the sample noise
    assert fw.at_noise_floor(1.0, 1.0, 10.0, 100)
    assert fw.at_noise_floor(30.0, 1.0, 12.0, 100)  # excess √29 = 5.4 N < 6 N
    assert not fw.at_noise_floor(50.0, 1.0, 12.0, 100)  # excess 7 N > 6 N, ratio 50 ≫ 1.7


# ---------------------------------------------------------------- near-tie order
def _c(name, loto, at_bound, n_params, bic):
    c = Candidate(name=name, params={}, n_params=n_params)
    c.nrmse_loto, c.at_bound, c.bic = loto, list(at_bound), bic
    return c


def test_near_tie_order_pinned_then_count_then_bic():
    """Within TIE of the best LOTO: fewer pinned parameters first, then fewer parameters, then BIC.
    Bugs caught: the key's order changed, the tie band ignored or widened to everything."""
    a = _c("a", 1.0, ["a.p"], 1, 0.0)  # best LOTO but pinned at a bound
    b = _c("b", 1.0 + 0.5 * TIE, [], 3, 100.0)  # within the tie band, nothing pinned
    far = _c("far", 1.0 + 3 * TIE, [], 1, -1e9)  # outside the band: never chosen
    chosen, ties = _pick([a, b, far])
    assert chosen is b and ties == [a]
    d = _c("d", 1.0, [], 2, 50.0)
    e = _c("e", 1.0 + 0.9 * TIE, [], 1, 100.0)
    assert _pick([d, e])[0] is e  # fewer parameters beats a better BIC
    f = _c("f", 1.0, [], 1, 10.0)
    g = _c("g", 1.0 + 0.9 * TIE, [], 1, 5.0)
    assert _pick([f, g])[0] is g  # then BIC
    h = _c("h", 1.0, [], 2, 50.0)
    i = _c("i", 1.0 + 1.01 * TIE, [], 1, 1.0)
    assert _pick([h, i])[0] is h  # just outside the band: the LOTO winner


def test_at_noise_floor_chi2_band():
    """Within 5 standard deviations of a χ² mean: ratio < 1 + 5·sqrt(2/n) = 1.5 for n = 200 bins (systematic part
    well above half σ, so only the ratio decides).  Bug caught: 2/n made an integer division (threshold 1)."""
    from chainid.gap.core.selection import at_noise_floor

    assert at_noise_floor(1.4, 1.0, 0.1, 200) is True
    assert at_noise_floor(1.6, 1.0, 0.1, 200) is False
    assert at_noise_floor(4.0, 1.0, 4.0, 200) is True  # excess sqrt(3) = 1.73 < 0.5·4


def test_two_for_one_reports_identified_pairs_within_the_tie(monkeypatch):
    """``refine.two_for_one``: a stiffness-side effect of the final chain (contact_law) against every pair of the other
    members of its family that are allowed and not in the chain; a pair is reported when its LOTO NRMSE is within
    ``TIE`` (5 %) of the chain's and none of its parameters is at a bound (rule 4).  The pair is fitted with the
    chain's other effects, warm-started from their parameters (the replaced effect's dropped)."""
    from chainid.gap.core import selection as fw

    full = Candidate("friction+contact_law", {"friction.F_c": 3.0, "contact_law.scale": 1.2,
                                              "contact_law.exponent": 1.4}, 3)
    full.nrmse_loto = 1.0
    # (LOTO, at_bound) per pair: within the tie and free | within but pinned | free but 20 % worse
    table = {("stiffness_level", "slack"): (1.04, []), ("stiffness_level", "machine_compliance"):
             (1.04, ["machine_compliance.c"]), ("slack", "machine_compliance"): (1.2, [])}
    seen = []

    def fake(prob, names, start, base_hold):  # noqa: ANN001
        seen.append((list(names), dict(start)))
        loto, ab = table[tuple(names[1:])]
        c = Candidate("+".join(names), {}, 2)
        c.nrmse_loto, c.at_bound = loto, list(ab)
        return c

    from chainid.gap.core import refine

    monkeypatch.setattr(refine, "fit_score", fake)
    allowed = ["friction", "contact_law", "stiffness_level", "slack", "machine_compliance"]
    out = refine.two_for_one(None, full, allowed, 1.0)
    assert [o["report"] for o in out] == [{"step": 2, "pair": ["contact_law", "stiffness_level+slack"],
                                           "loto": [1.0, 1.04]}]
    assert out[0]["cand"].name == "friction+stiffness_level+slack"
    assert [s[0] for s in seen] == [["friction", "stiffness_level", "slack"],
                                    ["friction", "stiffness_level", "machine_compliance"],
                                    ["friction", "slack", "machine_compliance"]]
    assert all(s[1] == {"friction.F_c": 3.0} for s in seen)
    # a member not allowed is not tried; an effect outside the family (friction) has no alternatives
    seen.clear()
    assert refine.two_for_one(None, full, ["friction", "contact_law", "stiffness_level", "slack"], 1.0)[0]["report"][
        "pair"] == ["contact_law", "stiffness_level+slack"]
    assert [s[0] for s in seen] == [["friction", "stiffness_level", "slack"]]
    seen.clear()
    only_friction = Candidate("friction", {"friction.F_c": 3.0}, 1)
    assert refine.two_for_one(None, only_friction, allowed, 1.0) == [] and seen == []


def test_train_floor_is_five_chi2_standard_deviations_by_hand():
    """``train_floor``: at the noise floor when r²/f² < 1 + 5·sqrt(2/n) (the χ² mean 1 with standard deviation
    sqrt(2/n) over n noise cells).  n = 200 cells (the problem's n_cells):
    threshold 1 + 5·0.1 = 1.5 by hand; 1.45 is at the floor, 1.55 not, f² = 0 never.  Bug caught:
    ``5 * sqrt`` → ``5 % sqrt`` (threshold 1.0: nothing above the noise itself counts)."""
    from chainid.gap.core.selection import train_floor

    def prob(r2, f2):
        return SimpleNamespace(noise_db=lambda ev, which: (r2, f2, None), n_cells=lambda which: 200)

    cand = SimpleNamespace(_ev={})
    assert train_floor(prob(1.45, 1.0), cand) is True
    assert train_floor(prob(1.55, 1.0), cand) is False
    assert train_floor(prob(2.9, 2.0), cand) is True  # 1.45
    assert not train_floor(prob(0.0, 0.0), cand)


def test_library_drops_aliases_and_restricts_to_the_given_effects():
    """machine_compliance is the same physics as stiffness_level for the diagnosis (ALIASES): considered only
    when stiffness_level is not; ``effects`` restricts the library."""
    from chainid.gap.core.selection import library

    prob = SimpleNamespace(applicable=lambda: ["friction", "machine_compliance", "stiffness_level", "slack"])
    assert library(prob, None) == ["friction", "stiffness_level", "slack"]
    assert library(prob, ["machine_compliance", "slack"]) == ["machine_compliance", "slack"]
    assert library(prob, ["backlash"]) == []


def test_baseline_candidate_of_a_chain_and_of_a_linear_spring():
    """The chain model as given (no parameters) or the linear spring re-fitted; scored with shrinkage 0."""
    from chainid.gap.harmonic.problem import Candidate
    from chainid.gap.core.selection import baseline_candidate

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
