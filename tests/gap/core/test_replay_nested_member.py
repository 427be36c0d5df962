"""A resample's replay judges nested shapes on the fitted parameters, as the diagnosis does: a friction with a
load-dependent part μ is not the member Bouc–Wen nests (:func:`chainid.gap.core.steprule.nested_pair`), so Bouc–Wen
is not given up for it, in the diagnosis' ``pick`` and in the replay on the resample that draws every unit once."""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np

from chainid.gap.core.resample import replay
from chainid.gap.core.steprule import pick
from chainid.gap.harmonic.problem import Candidate

UNITS = [f"u{i}" for i in range(12)]
#: the friction's per-unit LOTO errors, and Bouc–Wen's: half on six units, 1.3× on the others (5.4 % lower pooled
#: NRMSE, not significant over the units); the baseline 100 on every unit
FR = np.full(len(UNITS), 4.0)
BW = FR * np.array([0.5, 1.3] * 6)


def _cand(name: str, k: int, sse: np.ndarray, params: dict[str, float]) -> Candidate:
    c = Candidate(name, params, k)
    c.loto_num = dict(zip(UNITS, sse.tolist()))
    c.nrmse_loto = math.sqrt(float(sse.sum()) / (100.0 * len(UNITS)))
    c.bic = 10.0 * k
    return c


def _world(mu: float) -> tuple[dict, Candidate]:
    bw = _cand("bouc_wen", 4, BW, {"bouc_wen.F_y": 1.0})
    fr = _cand("friction", 3, FR, {"friction.F_c": 1.0, "friction.mu": mu, "friction.x_s": 0.0})
    base = _cand("", 0, np.full(len(UNITS), 100.0), {})
    return {("bouc_wen",): bw, ("friction",): fr}, base


def _hooks(cache: dict, base: Candidate) -> SimpleNamespace:
    def rescore(prob, c, mult):  # noqa: ANN001  the resample that draws every unit once: the diagnosis' numbers
        src = cache[tuple(sorted(c.names))] if c.names else base
        return dict(src.loto_num), src.nrmse_loto, False
    return SimpleNamespace(rescore=rescore)


def test_the_replay_keeps_bouc_wen_beside_a_friction_with_mu():
    cache, base = _world(mu=0.3)
    assert pick(list(cache.values()))[0].names == ["bouc_wen"]  # the diagnosis: no nested member, the best LOTO
    assert replay(None, _hooks(cache, base), cache, base, np.ones(len(UNITS)), 1) == ["bouc_wen"]


def test_the_replay_gives_bouc_wen_up_for_a_coulomb_friction_as_the_diagnosis_does():
    cache, base = _world(mu=0.0)
    assert pick(list(cache.values()))[0].names == ["friction"]
    assert replay(None, _hooks(cache, base), cache, base, np.ones(len(UNITS)), 1) == ["friction"]
