"""A resample's replay of the chain (:func:`chainid.gap.core.resample.replay`) makes the final chain's split too: a
Stribeck law standing in for a slack becomes friction plus slack when that set was fitted and fits as well with no
more parameters on the resample."""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np

from chainid.gap.core.resample import replay
from chainid.gap.core.steprule import LOOKAHEAD
from chainid.gap.harmonic.problem import Candidate


def _cand(names, n_params, bound=()):
    c = Candidate("+".join(names), {f"{n}.p": 1.0 for n in names}, n_params, at_bound=list(bound))
    c.bic = 0.0
    return c


def _hooks(loto):
    """Rescoring by table: sorted names → pooled LOTO NRMSE; per-test SSE 100·NRMSE²·(1, 1.05, 0.95)."""
    def rescore(prob, c, mult):  # noqa: ANN001
        r = loto[tuple(sorted(c.names))]
        return dict(zip("ABC", (100 * r * r * f for f in (1.0, 1.05, 0.95)))), r, False
    return SimpleNamespace(rescore=rescore)


def test_replay_splits_a_richer_effect_when_the_simpler_pair_was_fitted():
    """Step 1 takes Stribeck (0.039); slack on top (0.0374) is not material (4 %), so the forward replay stops at
    Stribeck; friction plus slack (0.0373, 5 parameters as Stribeck's) is within TIE and first by BIC: the replay's
    chain is friction then slack.  Without that set in the cache, or with one parameter more, it stays Stribeck."""
    names = {("stribeck",): 5, ("friction",): 4, ("slack",): 2, ("slack", "stribeck"): 6, ("friction", "slack"): 5}
    loto = {(): 1.0, ("stribeck",): 0.039, ("friction",): 0.084, ("slack",): 0.154, ("slack", "stribeck"): 0.0374,
            ("friction", "slack"): 0.0373}
    cache = {k: _cand(list(k), n) for k, n in names.items()}
    for k, c in cache.items():
        c.bic = 3000 * math.log(loto[k] ** 2) + c.n_params * math.log(3000)
    base = _cand([], 0)
    mult = np.ones(3)
    assert replay(None, _hooks(loto), cache, base, mult, 3) == ["friction", "slack"]
    assert replay(None, _hooks(loto), cache, base, mult, 1) == ["stribeck"]  # no room for a second effect
    more = dict(cache) | {("friction", "slack"): _cand(["friction", "slack"], 6)}
    more[("friction", "slack")].bic = cache[("friction", "slack")].bic
    assert replay(None, _hooks(loto), more, base, mult, 3) == ["stribeck"]
    less = {k: c for k, c in cache.items() if k != ("friction", "slack")}
    assert replay(None, _hooks(loto), less, base, mult, 3) == ["stribeck"]


def test_replay_exchanges_within_a_family_when_the_swapped_set_was_fitted():
    """Forward: friction (0.12; Bouc–Wen alone 0.16, beyond the look-ahead's 30 %), then slack (0.080; 0.30 alone).
    The swapped set Bouc–Wen plus slack was fitted (0.070, better by more than TIE): the replay's chain is Bouc–Wen
    then slack, ordered as the diagnosis rebuilds it (Bouc–Wen alone 0.16 before slack alone 0.30).  With the
    swapped set's Bouc–Wen parameter at a bound, or the set not fitted, it stays friction then slack."""
    names = {("friction",): 3, ("slack",): 2, ("friction", "slack"): 4, ("bouc_wen", "slack"): 6, ("bouc_wen",): 5}
    loto = {(): 1.0, ("friction",): 0.12, ("slack",): 0.30, ("friction", "slack"): 0.080, ("bouc_wen", "slack"): 0.070,
            ("bouc_wen",): 0.16}
    assert 0.16 > (1 + LOOKAHEAD) * 0.12
    cache = {k: _cand(list(k), n) for k, n in names.items()}
    base = _cand([], 0)
    mult = np.ones(3)
    assert 0.070 < (1 - 0.05) * 0.080
    assert replay(None, _hooks(loto), cache, base, mult, 3) == ["bouc_wen", "slack"]
    pinned = dict(cache) | {("bouc_wen", "slack"): _cand(["bouc_wen", "slack"], 6, bound=("bouc_wen.p",))}
    assert replay(None, _hooks(loto), pinned, base, mult, 3) == ["friction", "slack"]
    less = {k: c for k, c in cache.items() if k != ("bouc_wen", "slack")}
    assert replay(None, _hooks(loto), less, base, mult, 3) == ["friction", "slack"]
