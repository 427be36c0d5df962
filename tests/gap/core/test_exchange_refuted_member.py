"""The exchange pass follows ``pick``'s second choice: a family swap to a member that a richer shape nesting it beats
significantly (the set with that shape in its place fitted, its parameters inside their bounds) is refused, in the
diagnosis' exchange (:func:`chainid.gap.core.steprule.refuted_member`) and in the resample's replay of it."""
from __future__ import annotations

import math

import numpy as np

from chainid.gap.core.candidate import Candidate
from chainid.gap.core.resample import exchange_replay
from chainid.gap.core.steprule import TIE, refuted_member, swap_acceptable

UNITS = [f"b{i}" for i in range(12)]
ALT = np.array([1.0, 1.0] * 6)
FR = np.full(len(UNITS), 4.0)
BW = FR * np.array([0.5, 1.3] * 6)  # 5.4 % lower pooled than the friction, not significant over the units
HY = BW * np.array([1.01, 0.99] * 6) / 0.93**2  # 7 % above Bouc–Wen on every unit: significant; near-tie of FR


def _cand(names: list[str], n_params: int, sse: np.ndarray, at_bound: tuple[str, ...] = ()) -> Candidate:
    return Candidate("+".join(names), {}, n_params, nrmse_loto=math.sqrt(float(sse.sum()) / 1200.0),
                     loto_num=dict(zip(UNITS, sse.tolist())), at_bound=list(at_bound), bic=10.0 * n_params)


def _world(bw_bound: tuple[str, ...] = ()) -> dict[tuple[str, ...], Candidate]:
    return {("friction", "stiffness_level"): _cand(["stiffness_level", "friction"], 4, FR),
            ("hysteresis", "stiffness_level"): _cand(["stiffness_level", "hysteresis"], 3, HY),
            ("bouc_wen", "stiffness_level"): _cand(["stiffness_level", "bouc_wen"], 5, BW, bw_bound)}


def test_the_swap_alone_would_take_the_hysteresis():
    w = _world()
    fr, hy = w[("friction", "stiffness_level")], w[("hysteresis", "stiffness_level")]
    assert hy.nrmse_loto <= (1 + TIE) * fr.nrmse_loto and swap_acceptable(hy, fr, "hysteresis")


def test_a_swap_to_a_member_the_richer_shape_beats_is_refuted():
    w = _world()
    hy = w[("hysteresis", "stiffness_level")]
    assert refuted_member(hy, ["stiffness_level", "hysteresis"], "hysteresis", w.get)
    assert not refuted_member(w[("friction", "stiffness_level")], ["stiffness_level", "friction"], "friction", w.get)


def test_a_richer_shape_at_a_bound_refutes_nothing():
    w = _world(bw_bound=("bouc_wen.n",))
    hy = w[("hysteresis", "stiffness_level")]
    assert not refuted_member(hy, ["stiffness_level", "hysteresis"], "hysteresis", w.get)


def test_the_replay_keeps_the_friction():
    w = _world()
    chain, cur = exchange_replay(["stiffness_level", "friction"], w[("friction", "stiffness_level")], w, lambda c: c)
    assert chain == ["stiffness_level", "friction"] and cur is w[("friction", "stiffness_level")]
    del w[("bouc_wen", "stiffness_level")]  # without the richer set fitted, the swap stands
    chain, _ = exchange_replay(["stiffness_level", "friction"], w[("friction", "stiffness_level")], w, lambda c: c)
    assert chain == ["stiffness_level", "hysteresis"]
