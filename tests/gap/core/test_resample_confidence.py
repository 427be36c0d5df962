"""How a resampling's numbers enter a diagnosis result (``chainid.gap.core.resample.attach``): a step is
*confident* when at least ``CONFIDENT`` of the resamples choose it, and a result with a step below that is
``tentative``, with one warning naming each weak step and its share."""
from __future__ import annotations

from chainid.gap.core.resample import CONFIDENT, attach


def _result():
    return {"steps": [{"effect": "baseline"}, {"effect": "friction"}, {"effect": "slack"}], "warnings": []}


def _stab(*shares):
    steps = [{"effect": "baseline", "params_ci90": {}}]
    steps += [{"effect": e, "params_ci90": {}, "stability": s} for e, s in zip(("friction", "slack"), shares)]
    return {"resamples": 200, "steps": steps}


def test_every_step_at_or_above_the_bar_is_confident_without_a_warning():
    assert CONFIDENT == 0.8  # the bar the user guide states
    res = _result()
    attach(res, _stab(0.97, CONFIDENT))
    assert res["confidence"] == "confident" and res["warnings"] == []
    assert [st.get("stability") for st in res["steps"]] == [None, 0.97, 0.8]


def test_a_step_below_the_bar_makes_the_result_tentative_and_is_named():
    res = _result()
    attach(res, _stab(0.97, 0.64))
    assert res["confidence"] == "tentative"
    assert res["warnings"] == ["tentative: step(s) chosen by fewer than 80 % of 200 resamples (slack 64 %)"]
