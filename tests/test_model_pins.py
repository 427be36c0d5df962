"""Pins of chainid.model's effect operators, model file checks and helpers to closed forms (survivors of the
mutation run, issue 20 §5).  Units: mm, N, s, kg."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.model.augmented import AugmentedModel
from chainid.model.base import LinearModel
from chainid.model.effects import dahl_operator, parse_effect, series_compliance_force
from chainid.model.modelfile import model_from_dict, model_to_dict
from chainid.model.timedamping import Damping, dominant


def test_series_compliance_closed_form():
    """A spring k = 100 N/mm in series with c = 0.01 mm/N: F = k·x/(1 + c·k) = 50·x.
    Bug caught: the Newton step's denominator 1 + c·k changed."""
    x = np.array([0.0, 0.5, 2.0])
    np.testing.assert_allclose(series_compliance_force(LinearModel(100.0, 0.0), x, 0.01), 50.0 * x, rtol=1e-12)


def test_dahl_monotone_loading_closed_form():
    """From z = 0 on a monotone ramp: z = F_h·(1 − exp(−x/x_h)) (exact between samples).
    Bug caught: the operator's second output (the dissipation) returned instead of the force."""
    x = np.linspace(0.0, 1.0, 101)
    np.testing.assert_allclose(dahl_operator(x, 10.0, 0.2, periodic=False), 10.0 * (1 - np.exp(-x / 0.2)),
                               rtol=1e-9, atol=1e-12)


def _ramp():
    t = np.linspace(0.0, 1.0, 201)
    x = t.copy()  # mm, 1 mm/s
    return t, x, np.ones_like(t), np.zeros_like(t)


def test_effect_hook_backlash_on_a_ramp():
    """Backlash b = 0.2 mm (play half-width 0.1 mm) on a ramp from rest: F = k·max(0, x − 0.1).
    Bug caught: the memory operators' non-periodic rerun dispatched to the wrong effect."""
    model = LinearModel(100.0, 0.0)
    t, x, xd, xdd = _ramp()
    F = parse_effect("backlash:b=0.2", model)(t, x, xd, xdd, 100.0 * x)
    np.testing.assert_allclose(F, 100.0 * np.maximum(0.0, x - 0.1), atol=1e-9)


def test_effect_hook_friction_slides_after_stick():
    """Friction F_c = 30 N with stick travel x_s = 0.05 mm: past the stick travel the ramp slides, F = k·x + F_c.
    Bug caught: the friction rerun overwritten by another effect's branch."""
    model = LinearModel(100.0, 0.0)
    t, x, xd, xdd = _ramp()
    F = parse_effect("friction:F_c=30,x_s=0.05", model)(t, x, xd, xdd, 100.0 * x)
    late = x > 0.5
    np.testing.assert_allclose(F[late], 100.0 * x[late] + 30.0, rtol=1e-9)


def test_dominant_frequency_between_fft_bins():
    """A sine of 10.37 cycles over the record: ω from the refined spectral peak within 1e-4 (hand: 2π·10.37/T).
    Bug caught: the parabolic interpolation's coefficients."""
    T = 4.0
    t = np.linspace(0.0, T, 2048, endpoint=False)
    w = 2 * math.pi * 10.37 / T
    om, A, x0 = dominant(t, 0.7 + 2.0 * np.sin(w * t + 0.3))
    assert om == pytest.approx(w, rel=1e-4)
    assert A == pytest.approx(2.0, rel=1e-2)
    # the mean over a non-whole number of cycles is off by at most A/(π·n_cycles) = 2/(π·10.37) = 0.061 mm
    assert x0 == pytest.approx(0.7, abs=2.0 / (math.pi * 10.37))


def _model_dict():
    m = AugmentedModel(LinearModel(100.0, 0.0), [], Damping("viscous", {"c": 1.0}), 0.0, 0.0)
    return model_to_dict(m)


@pytest.mark.parametrize("kind", ["a-other-model", "zz-other-model"])
def test_model_file_refuses_any_other_kind(kind):
    """kind must equal 'chainid-augmented-model' (one sorting before, one after it are both refused).
    Bug caught: the equality test made an ordering."""
    d = _model_dict()
    d["kind"] = kind
    with pytest.raises(ValueError, match="kind = "):
        model_from_dict(d)


def test_model_file_linear_base_needs_k():
    d = _model_dict()
    assert model_from_dict(d).base.k == 100.0
    del d["base"]["k"]
    with pytest.raises(ValueError, match="a linear base needs k"):
        model_from_dict(d)


def test_augmented_force_refuses_repeated_time():
    """Two equal time stamps are not strictly increasing.  Bug caught: <= 0 made < 0."""
    m = AugmentedModel(LinearModel(100.0, 0.0), [], Damping("viscous", {"c": 1.0}), 0.0, 0.0)
    with pytest.raises(ValueError, match="strictly increasing"):
        m.force([0.0, 0.1, 0.1, 0.2], [0.0, 1.0, 1.0, 2.0])


def test_effect_force_stiffness_side_adds_the_inertia():
    """Effect.force of stiffness_level: m·ẍ·1e-3 plus the changed chain's force (ChainModel(ea_scale=s) built
    directly).  Bug caught: the inertia and the force combined by anything but a sum."""
    from dataclasses import replace

    from chainid.model.base import ChainModel
    from chainid.model.effects import make_effect

    model = ChainModel()
    x = np.linspace(0.5, 2.0, 7)
    xdd = np.linspace(-3e3, 3e3, 7)  # mm/s²
    F, _, _ = make_effect("stiffness_level").force({"scale": 0.8}, model, np.linspace(0, 1, 7), x,
                                                   np.zeros(7), xdd, 10.0, 0.75, 1.25)
    expect = model.mass_kg * xdd * 1e-3 + replace(model, ea_scale=0.8).force(x)
    np.testing.assert_allclose(F, expect, rtol=1e-12)
    assert model.mass_kg > 0


def test_format_practice_lists_the_explanation():
    """The audit text ends its chain part with the ratios behind the EA ratio (one line, 3 decimals)."""
    from chainid.model.practice import explain_ratio, format_practice, practice_section

    text = format_practice(practice_section())
    e = explain_ratio()
    line = next(ln for ln in text.splitlines() if "why the model is softer" in ln)
    assert f"ratio {e['ratio']:.3f}" in line and f"shear {e['shear']:.3f}" in line
