"""Issue 18: the diagnosis on any excitation — one band-limited random case per effect family, recovered blind
in the time domain (parameters within 10 %).

The records are built here from the library's operators run causally over x(t) (not through the time-domain
route of the diagnosis); the chain model's own force; white force noise of 5 N."""
from __future__ import annotations

import pytest

from chainid.gap import diagnose
from transient_forms import chain_set

CASES = [
    ("friction", {"F_c": 60.0}, {"friction.F_c": 60.0}),
    ("hysteresis", {"F_h": 80.0, "x_h": 0.02}, {"hysteresis.F_h": 80.0, "hysteresis.x_h": 0.02}),
    ("backlash", {"b": 0.03}, {"backlash.b": 0.03}),
    ("stiffness_level", {"scale": 0.8}, {"stiffness_level.scale": 0.8}),
    ("slack", {"s": 0.05}, {"slack.s": 0.05}),
    ("sensor_delay", {"tau": 0.02}, {"sensor_delay.tau": 0.02}),
]


@pytest.mark.parametrize("effect,p,expect", CASES, ids=[c[0] for c in CASES])
def test_random_excitation_recovers_each_family(effect, p, expect):
    model, recs = chain_set(effect, p)
    res = diagnose(recs, ["r2"], model, quiet=True)
    assert res["route"] == "time"
    # the family is named first (a family member of the same physics may stand in for contact_law/level)
    assert res["steps"][1]["effect"] == effect, res["chain_text"]
    got = res["steps"][1]["params"]
    for k, v in expect.items():
        assert got[k] == pytest.approx(v, rel=0.10), (k, got)
    assert res["steps"][-1]["shrinkage"] >= 0.5
    # the noise floor is estimated from the records themselves: σ = 5 N simulated
    assert res["baseline"]["noise_sigma_N"] == pytest.approx(5.0, rel=0.10)


def test_no_effect_is_none():
    model, recs = chain_set("none", {})
    res = diagnose(recs, ["r2"], model, quiet=True)
    assert res["verdict"] == "none", res["chain_text"]
