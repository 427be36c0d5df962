"""A resonant device's mass fitted blind (``model=None``, no ``--mass``): m·ẍ·1e-3 + c·ẋ + k·x = F(t) with
m = 2 kg, k = 20 N/mm (ω_n = 100 rad/s, 15.9 Hz, inside the 2–30 Hz band of the force), c = 0.02 N·s/mm, driven
from rest by a random multisine force and integrated by ``solve_ivp`` (:func:`recovery_cases.resonant_set`).
"""
from __future__ import annotations

import pytest

import recovery_cases as rc

pytestmark = pytest.mark.slow


def _res():
    return rc.diagnosed("resonant", rc.resonant_set)[0]


def test_resonant_device_mass_spring_and_damper_fitted():
    res = _res()
    assert res["route"] == "time"
    p = rc.final_params(res)
    assert rc.rel_err(p["_mass_kg"], rc.RES_M) <= 0.05, p
    assert rc.rel_err(p["_base"]["k"], rc.RES_K) <= 0.05, p
    assert rc.rel_err(p["damping.c"], rc.RES_C) <= 0.10, p


def test_resonant_device_with_no_effect_is_none():
    res = _res()
    assert res["verdict"] == "none", res["chain_text"]
