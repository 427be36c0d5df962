"""A baseline whose residual is the kinematic floor is ``none`` (:func:`chainid.gap.timedomain.route.kinematic_none`).

A force-driven resonant device in steady state (:func:`recovery_cases.resonant_noisy_x_set`: m = 2 kg, k = 20 N/mm,
c = 0.02 N·s/mm, a random multisine force 2–30 Hz, one whole period per record, σ_F = 0.05 N) with 5 µm of white
noise on x.  Even the true model leaves
the force noise plus m·ẍ's noise: x's noise through (2πf)² up to the cut, √((2/fs)·∫(2πf)⁴df)·σ_x·m·1e-3 ≈ 0.07 N
at a cut of 1.25× the band edge (37.5 Hz): about 4.5 dB over the force noise alone, and 1.4 N (29 dB) at 4× the
band.  The verdict must read that as noise, and only that: the rule never overrides a passing effect or a residual
the model-free learner predicts.
"""
from __future__ import annotations

from types import SimpleNamespace

import pytest

import recovery_cases as rc
from chainid.gap.timedomain.route import kinematic_none


def _prob(n: int = 1000, rel_sd: float = 0.0) -> SimpleNamespace:
    return SimpleNamespace(n_cells=lambda split: n, floor_rel_sd=lambda split: rel_sd)


def test_a_residual_at_the_kinematic_floor_reads_as_noise():
    # force noise 1 N², kinematic floor 2 N²: a residual of 2.02 N² is at the kinematic floor
    assert kinematic_none(None, 2.02, 2.0**0.5, 1.0, _prob(), {"missing_effect": False})


def test_a_residual_above_the_kinematic_floor_is_not_noise():
    # 3 N² against a floor of 2 N²: an excess of 1 N RMS, twice the half-sigma the rule forgives, with 1000 samples
    assert not kinematic_none(None, 3.0, 2.0**0.5, 1.0, _prob(), {"missing_effect": False})


def test_a_passing_effect_or_a_predictable_residual_keeps_the_excess():
    assert not kinematic_none(object(), 2.02, 2.0**0.5, 1.0, _prob(), {"missing_effect": False})
    assert not kinematic_none(None, 2.02, 2.0**0.5, 1.0, _prob(), {"missing_effect": True})
    assert not kinematic_none(None, 2.02, 0.0, 1.0, _prob(), {"missing_effect": False})


@pytest.mark.slow
def test_a_force_driven_device_with_a_noisy_displacement_is_none():
    res = rc.diagnosed("resonant_noisy_x", rc.resonant_noisy_x_set)[0]
    assert res["verdict"] == "none", (res["chain_text"], res["warnings"])
    assert any("kinematic floor" in w for w in res["warnings"]) and res["none_reading"] == "kinematic_floor"
    left = res["residual"]
    assert left["db_over_noise"] > 1.0  # above the force noise alone: the rule, not the plain floor, decided
    # the predicted floor is an honest bound: the residual at most 1 dB over it, and it at most 3 dB over the residual
    assert -3.0 < left["db_over_kinematic_floor"] < 1.0
    p = rc.final_params(res)
    assert rc.rel_err(p["_mass_kg"], rc.RES_M) <= 0.05, p
    assert rc.rel_err(p["_base"]["k"], rc.RES_K) <= 0.05, p
