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


# ---------------------------------------------------------------- seed-21 survivors (issue 20 §5)
def _runtime(s):
    """The string s built at run time (as from the command line: not the interned literal)."""
    return "".join(list(s))


def test_chain_practice_studlink_kind_from_a_runtime_string():
    """`--kind studlink` read from the command line is a run-time string: it must select the stud-link proof
    force of the makers' table (d = 50 R4: 2160 kN stud-link, 1920 kN studless; IACS W22 / DNV-OS-E302).
    Bug caught: `knd == "studlink"` → `knd is "studlink"` (true only for the interned literal)."""
    from chainid.chain import presets
    from chainid.model.practice import chain_practice

    c = presets.chain("studless:50")
    row = chain_practice(c, grade_name=_runtime("R4"), kind=_runtime("studlink"))
    assert row["kind"] == "studlink" and row["proof_load_N"] == pytest.approx(2160e3, rel=1e-3)
    assert row["working_load_N"] == pytest.approx(1080e3, rel=1e-3)
    assert chain_practice(c, grade_name="R4")["proof_load_N"] == pytest.approx(1920e3, rel=1e-3)
    # the DNV ratio is the model's EA over the DNV catalogue EA of that grade (its documented definition)
    assert row["ratio_model_dnv"] == pytest.approx(row["EA_model_N"] / row["EA_catalogue_dnv_R4_N"], rel=1e-12)


def test_make_effect_of_a_runtime_name():
    """An effect named at run time (CLI `--effect hysteresis:…`) is the Dahl element with F_h, x_h.
    Bug caught: `name == "hysteresis"` → `name is "hysteresis"`."""
    from chainid.model.effects import make_effect

    e = make_effect(_runtime("hysteresis"), F_scale=100.0, x_scale=2.0)
    assert e.name == "hysteresis" and e.param_names == ("F_h", "x_h")
    assert e.bounds == ((0.0, 500.0), (2e-3, 20.0))  # (0, 5 F_scale), (1e-3, 10) x_scale: the documented ranges


def test_explain_ratio_secant_by_root_finding():
    """The secant EA between 10 % and 50 % of the breaking force, from x(F) found by root-finding F_k(x) = F
    (brentq on the force kernel, not the displacement kernel): 0.4·MBL·L/(x₅₀ − x₁₀) over the catalogue EA."""
    from scipy.optimize import brentq

    from chainid.chain import presets
    from chainid.model import kernels
    from chainid.model.practice import chain_practice, explain_ratio

    c = presets.chain("studless:50")
    p = chain_practice(c)
    mbl = p["breaking_load_N"]
    x1, x2 = (brentq(lambda x, F=F: kernels.force(x, c) - F, 0.0, 1e4, xtol=1e-13, rtol=1e-14)
              for F in (0.1 * mbl, 0.5 * mbl))
    want = 0.4 * mbl * c.length_mm / (x2 - x1) / p["EA_catalogue_orcaflex_N"]
    assert explain_ratio(c)["secant_10_50_mbl"] == pytest.approx(want, rel=1e-9)


def test_stiffness_beyond_the_linear_switch_is_the_asymptote():
    """Above X_LINEAR (1e60 mm) and at +inf the stiffness is Eq. 16's limit 1/c_lin (the Hertz term vanishes as
    F^(-1/3)); c_lin of the built-in chain is 6.3358e-5 mm/N (Eq. 15, test_kernels' closed form)."""
    from chainid.model import kernels

    c_lin = kernels.coefficients()[0]
    assert c_lin == pytest.approx(6.3358e-5, rel=1e-4)
    k = kernels.stiffness(np.array([1e70, np.inf]))
    np.testing.assert_allclose(k, 1.0 / c_lin, rtol=1e-12)
    assert kernels.force(1e70) == pytest.approx(1e70 / c_lin, rel=1e-12)


@pytest.mark.parametrize("bad", [np.zeros((3, 4)), np.zeros(0), np.zeros((0, 2))])
def test_operators_refuse_a_non_series(bad):
    """The operators take one non-empty 1-D series (documented); a 2-D array is refused, not flattened.
    Bug caught: `x.ndim != 1 or x.size == 0` → `and`."""
    from chainid.model.operators import dahl, play

    with pytest.raises(ValueError, match="non-empty 1-D"):
        play(bad, 0.1)
    with pytest.raises(ValueError, match="non-empty 1-D"):
        dahl(bad, 1.0, 0.1)


def test_cycle_parts_total_mass_closed_form():
    """With a moving mass m = 3 kg set on a linear spring k = 100 N/mm (x_ref = 1 mm) whose own mass is 0.5 kg,
    the undamped force is k·(x − x_ref) + m·ẍ·1e-3 on x = 2 + 0.5·sin(ω t) (closed form, ẍ = −ω²·0.5·sin).
    Bug caught: the mass correction (m − m_base)·ẍ subtracted instead of added."""
    from types import SimpleNamespace

    w = 2 * math.pi * 3.0
    t = np.linspace(0.0, 1.0 / 3.0, 64, endpoint=False)
    x, xd, xdd = 2 + 0.5 * np.sin(w * t), 0.5 * w * np.cos(w * t), -0.5 * w * w * np.sin(w * t)
    d = SimpleNamespace(grid={"t": t, "x": x, "xd": xd, "xdd": xdd}, omega=w, A=0.5, x0=2.0, xfun=None,
                        gridmean=lambda y: np.asarray(y, float))
    m = AugmentedModel(LinearModel(100.0, 1.0, 0.5), mass_kg=3.0)
    Fn, v = m.cycle_parts(d)
    np.testing.assert_allclose(Fn, 100.0 * (x - 1.0) + 3.0 * xdd * 1e-3, rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(v, xd, rtol=1e-12)


@pytest.mark.parametrize("name", ["viscous_excess", "sensor_delay", "friction"])
def test_modify_model_refuses_an_effect_that_is_not_stiffness_side(name):
    """Only the four stiffness-side effects change the chain model; any other name is refused with the list
    (names after "slack" in the alphabet included: a comparison instead of equality would take them for slack).
    A stiffness-side effect changes only its own field: slack adds s, compliance adds c."""
    from chainid.chain.spec import default_chain
    from chainid.model.base import ChainModel
    from chainid.model.effects import modify_model

    m = ChainModel(default_chain())
    with pytest.raises(ValueError, match=rf"effect '{name}' is not a stiffness-side effect; those are: "
                                         "stiffness_level, contact_law, slack, machine_compliance"):
        modify_model(name, {"s": 0.5}, m)
    s = modify_model("slack", {"s": 0.5}, m)
    assert (s.slack, s.compliance, s.ea_scale) == (m.slack + 0.5, m.compliance, m.ea_scale)
    c = modify_model("machine_compliance", {"c": 1e-4}, m)
    assert (c.slack, c.compliance) == (m.slack, m.compliance + 1e-4)


@pytest.mark.parametrize("beta", [0.5, 0.8, 1.2])
def test_contact_power_law_meets_hertz_at_the_reference_force(beta):
    """ChainModel docstring: with β set, c is chosen so that the approach equals the variant's Hertz approach
    (times hertz_scale) at contact_ref_force; so both springs reach F_ref at the same elongation (root finding
    on each force, not the kernels' inverse), and a different β only bends the curve away from it."""
    from scipy.optimize import brentq

    from chainid.model.base import ChainModel

    kw = {"hertz_scale": 1.3, "contact_ref_force": 5e3, "ea_scale": 0.9, "compliance": 1e-6}
    hertz, power = ChainModel(**kw), ChainModel(contact_exponent=beta, **kw)

    def x_at(m, F):
        return brentq(lambda x: float(m.force(np.array([x]))[0]) - F, 1e-9, 50.0, xtol=1e-14, rtol=1e-14)

    assert x_at(power, 5e3) == pytest.approx(x_at(hertz, 5e3), rel=1e-9)
    assert x_at(power, 2e4) != pytest.approx(x_at(hertz, 2e4), rel=1e-4)
    c_lin, c_h = hertz.coefficients
    assert power.coefficients == pytest.approx((c_lin, c_h * 5e3 ** (2 / 3 - beta), beta), rel=1e-12)
    base = ChainModel()
    assert c_lin == pytest.approx(base.coefficients[0] / 0.9 + 1e-6, rel=1e-12)
    assert c_h == pytest.approx(base.coefficients[1] * 1.3, rel=1e-12)
    # x = +inf: F = inf; the tangent tends to 1/c_lin (β < 1), 1/(c_lin + c) (β = 1) or 0 (β > 1)
    k_inf = {0.5: 1 / c_lin, 0.8: 1 / c_lin, 1.2: 0.0}[beta]
    assert power.force(np.array([np.inf]))[0] == np.inf
    assert power.stiffness(np.array([np.inf]))[0] == pytest.approx(k_inf, rel=1e-12)
    one = ChainModel(contact_exponent=1.0, **kw)
    assert one.stiffness(np.array([np.inf]))[0] == pytest.approx(1 / sum(one.coefficients[:2]), rel=1e-12)


@pytest.mark.parametrize("field,ok,bad,msg", [
    ("contact_exponent", (0.2, 1.5), (0.19, 1.51), "valid range 0.2 to 1.5"),
    ("ea_scale", (1e-3, 1e3), (0.99e-3, 1.01e3, float("nan")), "valid range 0.001 to 1000"),
    ("hertz_scale", (1e-9,), (0.0, -1.0, float("inf")), "valid range > 0"),
    ("compliance", (0.0,), (-1e-9, float("nan")), "valid range >= 0 mm/N"),
    ("contact_ref_force", (1e-9,), (0.0, float("inf")), "valid range > 0 N"),
    ("slack", (-0.5, 0.0), (float("nan"),), "must be a finite number of mm"),
])
def test_chain_model_fields_ranges_inclusive_and_named(field, ok, bad, msg):
    from chainid.model.base import ChainModel

    for v in ok:
        ChainModel(**{field: v})
    for v in bad:
        with pytest.raises(ValueError, match=rf"ChainModel\.{field} = .* is invalid: {msg}"):
            ChainModel(**{field: v})
