"""When a split (a richer effect replaced by its simpler member plus a next effect) may replace the chain's step
(chainid.gap.core.steprule.split_acceptable): its leave-one-test-out NRMSE lower by more than TIE, or within TIE
and first in the near-tie order (fewer parameters at a bound, fewer parameters, lower BIC); never more parameters,
never one of its new effects' parameters at a bound."""
from __future__ import annotations

from types import SimpleNamespace

import pytest

from chainid.gap.core.steprule import TIE, split_acceptable


def _c(loto, n=3, bic=0.0, at_bound=()):
    return SimpleNamespace(nrmse_loto=loto, n_params=n, bic=bic, at_bound=tuple(at_bound))


FULL = _c(1.0, n=3, bic=10.0)


@pytest.mark.parametrize("c, ok, why", [
    (_c(1.0 - 1.5 * TIE, bic=20.0), True, "lower by more than TIE: taken whatever its BIC"),
    (_c(1.0 - 0.5 * TIE, bic=20.0), False, "lower, but within TIE and later in the near-tie order (higher BIC)"),
    (_c(1.0 + 0.5 * TIE, bic=5.0), True, "within TIE (even higher) and first in the near-tie order"),
    (_c(1.0 + 1.5 * TIE, bic=5.0), False, "higher by more than TIE"),
    (_c(0.5, n=4), False, "more parameters than the step it splits"),
    (_c(0.5, at_bound=("friction.F_c",)), False, "a new effect's parameter at its bound"),
    (_c(0.5, at_bound=("hysteresis.F_h",)), True, "a bound hit by an effect the split does not bring"),
])
def test_a_split_replaces_the_step_only_by_the_documented_rule(c, ok, why):
    assert 0 < TIE < 0.5
    assert split_acceptable(c, FULL, ["stribeck", "friction"]) is ok, why
