"""An ``unexplained`` verdict still reports the part it explains: effects that passed the step rule and lower the
held-out error by less than the naming threshold are returned as ``partial`` and named in the verdict's text as a
part of the gap, not its cause."""
from __future__ import annotations

from types import SimpleNamespace

import pytest

from chainid.gap.core.summary import summary
from chainid.gap.core.verdict import MIN_SHRINK, partial_explanation

BASE = SimpleNamespace(nrmse_holdout=0.2089, names=[], shrinkage=0.0)


def _final(h: float) -> SimpleNamespace:
    return SimpleNamespace(nrmse_holdout=h, names=["hysteresis.F_h@p_bar"], shrinkage=1 - h / BASE.nrmse_holdout)


def test_a_significant_chain_below_the_threshold_is_a_partial_explanation():
    part = partial_explanation("unexplained", _final(0.1253), BASE)
    assert part["effects"] == "hysteresis"
    assert part["shrinkage"] == pytest.approx(1 - 0.1253 / 0.2089, rel=1e-12)
    assert part["min_shrink"] == MIN_SHRINK == 0.5


@pytest.mark.parametrize("verdict, final", [("hysteresis", _final(0.05)), ("unexplained", None),
                                            ("unexplained", _final(0.25)), ("none", None)])
def test_no_partial_when_named_absent_or_not_lower(verdict, final):
    assert partial_explanation(verdict, final, BASE) is None


def test_the_verdict_text_names_the_part():
    res = {"baseline": {"model": "linear device", "damping_law": "viscous", "nrmse_train": 0.38, "nrmse_holdout": 0.2089,
                        "db_over_noise": 22.4, "excess_rms_N": 1.4, "noise_sigma_N": 0.088},
           "where": [], "ranking": [], "steps": [], "verdict": "unexplained", "left_nrmse_holdout": 0.1253,
           "residual": {"db_over_noise": 18.0, "stationary": True},
           "partial": partial_explanation("unexplained", _final(0.1253), BASE)}
    line = next(s for s in summary(res).splitlines() if s.startswith("VERDICT"))
    assert ("VERDICT: unexplained — hysteresis passed the step rule and holds on the held-out data (held-out NRMSE "
            "0.2089 → 0.1253, 40 %), but closes less than 50 % of the held-out gap: a part of it, not its cause") in line
