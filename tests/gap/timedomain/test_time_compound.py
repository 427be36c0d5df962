"""Compound cases on non-harmonic records that the selection used to get wrong, each for a stated reason (records
from the benchmark's own simulator, ``chainid.records.excitation`` and the library's causal operators, independent of
the diagnosis; the true strengths from the documented effect sizes ``effect_spec``).

* Friction seen through a lagging force channel (random): the presliding travel x_s sits at 0, where the friction
  force is strongly nonlinear in it; the linear leave-one-block-out prediction of a large x_s step made one
  block's left-out error 140× its fitted error, the backward pass dropped the lag, verdict ``unexplained``.
  Now a large leave-out step is checked on the nonlinear model (:mod:`chainid.gap.timedomain.problem`).
* The same pair on a sweep: the family exchange swapped friction for Dahl hysteresis with x_h pinned at its floor
  (Coulomb friction under another name) and then dropped the lag; a swap must now obey rule 4.
* A stiffness level with a slack (sweep) against one Hertz law with a fitted exponent: same parameter count,
  within the tie band; the step rule's near-tie order (fewer pinned, fewer parameters, then BIC) now decides
  between them too, and the other is reported as confounded."""
from __future__ import annotations

import numpy as np
import pytest

from chainid.gap import diagnose
from chainid.gap.benchmark.nonharmonic import effect_spec, records, time_grid


def _run(seed):
    case = next(c for c in time_grid() if c["seed"] == seed)
    recs, dev = records(case)
    res = diagnose(recs, [case["hold"]], dev["nominal"], uncertainty=False, quiet=True)
    return case, dev, res


def _true(effect, case, dev):
    wmax = 2 * np.pi * max(m.f_dom for m in dev["motions"])
    lv = case["levels"][case["effects"].index(effect)]
    return float(effect_spec(effect, lv, dev["S"], 1.0, 1.0, wmax).split("=")[1])


@pytest.mark.slow
@pytest.mark.parametrize("seed,excitation", [(100028, "random"), (101028, "sweep")])
def test_friction_seen_through_a_lagging_force_channel(seed, excitation):
    case, dev, res = _run(seed)
    assert case["truth"] == ["friction", "sensor_delay"] and case["excitation"] == excitation
    assert set(res["verdict"].split("+")) == {"friction", "sensor_delay"}, res["chain_text"]
    assert res["steps"][-1]["shrinkage"] >= 0.5
    if excitation == "sweep":
        return  # named right; the lag (1.4 noise σ alone) is recovered only to about 30 % there (not asserted)
    p = res["steps"][-1]["params"]
    assert p["sensor_delay.tau"] == pytest.approx(_true("sensor_delay", case, dev), rel=0.15)
    # friction F_c + mu·|F_k|: its level at the records' mean load
    Fk = float(np.mean([np.mean(np.abs(dev["nominal"].force(m.x))) for m in dev["motions"]]))
    assert p["friction.F_c"] + p["friction.mu"] * Fk == pytest.approx(_true("friction", case, dev), rel=0.15)


@pytest.mark.slow
def test_stiffness_level_and_slack_against_one_contact_law():
    case, dev, res = _run(101026)
    assert case["truth"] == ["stiffness_level", "slack"] and case["excitation"] == "sweep"
    assert set(res["verdict"].split("+")) == {"stiffness_level", "slack"}, res["chain_text"]
    assert res["steps"][-1]["params"]["stiffness_level.scale"] == pytest.approx(case["ea_scale"], rel=0.05)
    pairs = [tuple(c["pair"]) for c in res["confounded"]]
    assert ("stiffness_level+slack", "contact_law") in pairs
