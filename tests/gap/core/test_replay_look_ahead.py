"""A resample's replay of the chain (:func:`chainid.gap.core.resample.replay`) looks one step ahead at a close
runner-up as the forward selection does (:func:`chainid.gap.core.steprule.look_ahead`, one function for both):
on the tables of the selection's look-ahead tests, the replay on the resample that draws every test once chooses
the first step the selection chose."""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from chainid.gap.core.resample import replay
from chainid.gap.harmonic.problem import Candidate
from selection_tables import table_world

TABLE = {("friction",): (0.5, (25.0, 25.0, 16.0), (), 1),
         ("slack",): (0.95, (90.0, 90.0, 90.0), (), 1),
         ("sensor_delay",): (0.51, (26.0, 26.0, 17.0), (), 1),
         ("friction", "slack"): (0.44, (20.0, 20.0, 13.0), (), 2),
         ("friction", "sensor_delay"): (0.49, (24.5, 24.5, 15.5), (), 2),
         ("sensor_delay", "slack"): (0.35, (12.0, 12.0, 8.0), ("slack.p",), 2)}
#: the runner-up's extension carried by one test (rule 2), and free (the look-ahead takes the runner-up)
ONE_TEST = TABLE | {("sensor_delay", "slack"): (0.35, (12.0, 26.0, 17.0), (), 2)}
FREE = TABLE | {("sensor_delay", "slack"): (0.35, (12.0, 12.0, 8.0), (), 2)}


def _cache(table):
    out = {}
    for key, (loto, sse, bound, k) in table.items():
        c = Candidate("+".join(key), {f"{n}.p": 1.0 for n in key}, k, at_bound=list(bound))
        c.nrmse_loto, c.loto_num, c.bic = loto, dict(zip("ABC", sse)), 10.0 * k
        out[key] = c
    return out


def _hooks(table, floor):
    """Rescoring by table (the resample that draws each test once: the diagnosis' own numbers)."""
    def rescore(prob, c, mult):  # noqa: ANN001
        key = tuple(sorted(c.names))
        if not key:
            return {"A": 100.0, "B": 100.0, "C": 100.0}, 1.0, False
        loto, sse, _, _ = table[key]
        return dict(zip("ABC", sse)), loto, key in floor
    return SimpleNamespace(rescore=rescore)


@pytest.mark.parametrize("world, floor, first", [
    (TABLE, (), "friction"), (ONE_TEST, (), "friction"), (FREE, (), "sensor_delay"),
    (FREE, {("sensor_delay",)}, "friction")], ids=["pinned", "one_test", "free", "runner_up_at_floor"])
def test_replay_takes_the_first_step_the_selection_takes(monkeypatch, world, floor, first):
    sel, base, _ = table_world(monkeypatch, world, floor)
    out = sel.forward_select(None, ["friction", "slack", "sensor_delay"], base, 1.0, max_effects=2)
    assert out["path"][1].names == [first]
    base.bic = 0.0
    chain = replay(None, _hooks(world, floor), _cache(world), base, np.ones(3), 2)
    assert chain[0] == first, chain


def test_replay_without_the_runner_up_extensions_keeps_the_greedy_choice():
    """The diagnosis never fitted the runner-up's extension (it was not explored there): the replay cannot look
    ahead through it and keeps the best step."""
    world = {k: v for k, v in FREE.items() if k != ("sensor_delay", "slack")}
    base = Candidate("baseline", {}, 0)
    base.bic = 0.0
    assert replay(None, _hooks(world, ()), _cache(world), base, np.ones(3), 2)[0] == "friction"


def test_replay_without_the_choice_extensions_keeps_the_greedy_choice():
    """The runner-up's extensions were fitted and the choice's were not (another resample's diagnosis): the two paths
    cannot be compared alike, so the replay keeps the best step rather than favour the path it can see."""
    world = {k: v for k, v in FREE.items() if k != ("friction", "slack")}
    base = Candidate("baseline", {}, 0)
    base.bic = 0.0
    assert replay(None, _hooks(world, ()), _cache(world), base, np.ones(3), 2)[0] == "friction"
