"""Every library effect belongs to a physical family in the verdict's ``mechanism`` (Stribeck friction is friction,
Bouc–Wen hysteresis is hysteresis, a dead band is play, a hardening spring is stiffness, a fixture mass is
inertia), so a real MR damper named ``bouc_wen+stribeck`` reads ``hysteresis+friction``."""
from __future__ import annotations

from chainid.gap.core.interpret import MECHANISM, mechanism
from chainid.model.effects import EFFECT_NAMES


def test_every_library_effect_has_a_family():
    assert set(EFFECT_NAMES) <= set(MECHANISM)


def test_the_new_effects_read_as_their_physics():
    assert mechanism("bouc_wen+stribeck", "") == "hysteresis+friction"
    assert mechanism("deadband+hardening", "") == "play+stiffness"
    assert mechanism("fixture_mass", "") == "inertia"
    assert mechanism("stribeck+friction", "") == "friction"
