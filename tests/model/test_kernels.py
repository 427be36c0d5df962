"""The stiffness kernels (chainid.model.kernels) against an independent implementation of the paper's closed forms
(tests/paper_forms.py), and their properties: round trips, derivatives, domain guards, the linear asymptote.
Units mm, N, N/mm."""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import chainid
from chainid.chain.spec import ChainSpec, default_chain
from chainid.model import kernels
from chainid.model.base import ChainModel, LinearModel

import paper_forms


def paper_coefficients(d, pitch, width, n, E, nu, contact="outer", kappa=1.0):
    """Eq. 5, 7 (k0 = M1/F), 10, 14, 15 typed from the paper, in plain floats."""
    R, L = (width + d) / 2, (pitch - width) / 2
    A = math.pi * d**2 / 4
    J1 = math.pi * d**4 / 64
    alpha = R - d**2 / (8 * R * (1 - math.sqrt(1 - (d / (2 * R)) ** 2)))
    J2 = J1 + alpha**2 * A
    G = E / (2 * (1 + nu))
    k0 = (math.pi - 2) * R**2 * J1 / (4 * J2 * L + 2 * J1 * math.pi * R)
    dl1 = 2 * k0**2 * L / (E * J1) + L / (2 * E * A)
    dl2 = R * math.pi / (8 * E * A) + kappa * R * math.pi / (8 * G * A)
    dl3 = R / (2 * E * J2) * (math.pi / 2 * (2 * k0 - R) ** 2 + 2 * R * (2 * k0 - R) + R**2 * math.pi / 4)
    rho_p = R + d / 2 if contact == "outer" else R - d / 2
    rho = 0.5 * (4 / d - 2 / rho_p)
    # Eq. 14 written with rho: delta = (9 F² (1-ν²)² rho / (4 E²))^(1/3)
    ch = (9 * (1 - nu**2) ** 2 * rho / (4 * E**2)) ** (1 / 3)
    return 2 * n * (dl1 + dl2 + dl3), (n - 1) * ch


chains = st.builds(
    lambda d, wr, pr, n, E, nu: ChainSpec(d=d, width=d * wr, pitch=d * max(wr * pr, 2.0), n=n, E=E, nu=nu,
                                          mass_per_m=1.0),
    st.floats(5, 60), st.floats(1.05, 2.0), st.floats(1.5, 4.0), st.integers(2, 200),
    st.floats(5e4, 3e5), st.floats(0.05, 0.49),
)


@pytest.mark.parametrize("variant,contact,kappa", [("paper", "outer", 1.0), ("inner_bend", "inner", 1.0),
                                                   ("shear", "outer", 10 / 9), ("inner_bend_shear", "inner", 10 / 9)])
def test_coefficients_match_independent_closed_forms(variant, contact, kappa):
    c = default_chain()
    got = kernels.coefficients(c, variant)
    exp = paper_coefficients(c.d, c.pitch, c.width, c.n, c.E, c.nu, contact, kappa)
    assert got[0] == pytest.approx(exp[0], rel=1e-12)
    assert got[1] == pytest.approx(exp[1], rel=1e-12)


@settings(max_examples=60, deadline=None)
@given(chains)
def test_coefficients_random_chains(chain):
    got = kernels.coefficients(chain)
    exp = paper_coefficients(chain.d, chain.pitch, chain.width, chain.n, chain.E, chain.nu)
    assert got[0] == pytest.approx(exp[0], rel=1e-10)
    assert got[1] == pytest.approx(exp[1], rel=1e-12)


def test_builtin_chain_at_paper_pretension():
    # golden value from the paper's closed forms typed in tests/paper_forms.py (section properties, k0 = M1/F,
    # Hertz delta of Eq. 14, Eq. 15), evaluated in plain Python: 1.905814 mm at the test pretension 11117 N
    x_indep = paper_forms.x_of_F(11117.0)
    assert x_indep == pytest.approx(1.905814, abs=1e-6)
    assert chainid.displacement(11117.0) == pytest.approx(x_indep, rel=1e-12)
    assert chainid.force(2.2) == pytest.approx(paper_forms.F_of_x(2.2), rel=1e-12)
    assert chainid.stiffness(2.2) == pytest.approx(paper_forms.k_e(2.2), rel=1e-12)


def test_displacement_of_zero_force_is_zero():
    # x(0) = 0 exactly: F = 0 is the unloaded chain, a valid input (not an error)
    assert chainid.displacement(0.0) == 0.0
    np.testing.assert_array_equal(chainid.displacement(np.array([0.0, 0.0])), [0.0, 0.0])
    assert chainid.displacement(np.array([0.0, 11117.0]))[1] == pytest.approx(paper_forms.x_of_F(11117.0), rel=1e-12)


@settings(max_examples=200, deadline=None)
@given(st.floats(-9, 3), chains, st.sampled_from(kernels.VARIANTS))
def test_round_trip_relative_1e12(log_x, chain, variant):
    x = 10.0**log_x
    F = chainid.force(x, chain) if variant == "paper" else kernels.force(x, chain, variant)
    back = kernels.displacement(F, chain, variant)
    assert abs(back - x) <= 1e-12 * x


def test_round_trip_dense_grid_builtin():
    x = np.logspace(-9, 3, 20001)
    back = chainid.displacement(chainid.force(x))
    assert np.max(np.abs(back - x) / x) <= 1e-12


@settings(max_examples=100, deadline=None)
@given(st.floats(-6, 2.5), chains)
def test_stiffness_is_the_derivative_of_force(log_x, chain):
    x = 10.0**log_x
    h = 1e-4 * x
    fd = (kernels.force(x + h, chain) - kernels.force(x - h, chain)) / (2 * h)
    # central difference error ~ h² F''' / 6: relative ~1e-8 for this smooth power law
    assert kernels.stiffness(x, chain) == pytest.approx(fd, rel=1e-6)


@settings(max_examples=60, deadline=None)
@given(chains)
def test_stiffness_positive_increasing_zero_only_at_zero(chain):
    x = np.concatenate([[0.0], np.logspace(-8, 3, 400)])
    k = kernels.stiffness(x, chain)
    assert k[0] == 0.0
    assert np.all(k[1:] > 0)
    assert np.all(np.diff(k) > 0)


def test_single_link_has_no_contact_and_constant_stiffness():
    c = default_chain().replace(n=1)
    c_lin, c_h = kernels.coefficients(c)
    assert c_h == 0.0
    k = kernels.stiffness(np.array([0.0, 0.01, 1.0]), c)
    assert np.allclose(k, 1.0 / c_lin, rtol=1e-12)
    assert kernels.force(1.0, c) == pytest.approx(1.0 / c_lin, rel=1e-12)


def test_domain_guards():
    assert chainid.force(0.0) == 0.0
    assert np.all(chainid.force(np.array([-1.0, -1e-300])) == 0.0)
    assert chainid.stiffness(-0.5) == 0.0
    assert math.isnan(chainid.force(float("nan")))
    assert math.isnan(chainid.stiffness(float("nan")))
    assert math.isnan(chainid.displacement(float("nan")))
    with pytest.raises(ValueError, match="F = -1.0 N is invalid"):
        chainid.displacement(-1.0)


def test_shapes_preserved():
    x = np.linspace(0.1, 3, 12).reshape(3, 4)
    assert chainid.force(x).shape == (3, 4)
    assert chainid.stiffness(x).shape == (3, 4)
    assert isinstance(chainid.force(2.2), float)


def test_parallel_kernels_match_serial():
    mod = kernels.variant_module("paper")
    c = kernels.coefficients()
    x = np.linspace(0, 5, 10001)
    assert np.array_equal(mod.force_parallel(x, *c), mod.force_array(x, *c))
    assert np.array_equal(mod.stiffness_parallel(x, *c), mod.stiffness_array(x, *c))


def test_damping_residual_units():
    # F_c = F - m ẍ 1e-3 - F_k: with ẍ = 1e6 mm/s² and m = 3.2 kg the inertia is 3200 N
    x = np.array([2.2])
    Fc = kernels.damping_residual(np.array([20000.0]), x, np.array([1e6]))
    assert Fc[0] == pytest.approx(20000.0 - 3200.0 - chainid.force(2.2), rel=1e-12)


def test_damping_residual_explicit_mass():
    # F_c = F - m xddot 1e-3 - F_k(x), with an explicit mass_kg that must override the chain's 3.2 kg:
    # 10 kg x 1e6 mm/s^2 x 1e-3 = 10000 N; F_k(2.2 mm) = 13325.415 N from the closed form (paper_forms)
    Fk = paper_forms.F_of_x(2.2)
    F, x, a = np.array([30000.0, 30000.0]), np.array([2.2, 2.2]), np.array([1e6, -2e5])
    got = kernels.damping_residual(F, x, a, mass_kg=10.0)
    np.testing.assert_allclose(got, [30000.0 - 10000.0 - Fk, 30000.0 + 2000.0 - Fk], rtol=1e-12)
    got0 = kernels.damping_residual(F, x, a, mass_kg=0.0)
    np.testing.assert_allclose(got0, [30000.0 - Fk, 30000.0 - Fk], rtol=1e-12)
    # default: the chain's own mass, 4.0 kg/m x 0.8 m = 3.2 kg
    np.testing.assert_allclose(kernels.damping_residual(F, x, a), [30000.0 - 3200.0 - Fk, 30000.0 + 640.0 - Fk],
                               rtol=1e-12)


def test_inner_bend_needs_width_above_d():
    # ChainSpec refuses width <= d itself (the next link's bar must pass), so no variant sees it
    with pytest.raises(ValueError, match=r"ChainSpec\.width = 18\.0 .*20\.0 < width"):
        kernels.coefficients(ChainSpec(d=20, pitch=60, width=18, n=4, mass_per_m=1), "inner_bend")
    with pytest.raises(ValueError, match="width"):  # width = d: the limit is strict (width > d)
        ChainSpec(d=20, pitch=60, width=20.0, n=4, mass_per_m=1)
    assert kernels.coefficients(ChainSpec(d=20, pitch=60, width=20.5, n=4, mass_per_m=1), "inner_bend")[1] > 0


def test_chain_model_effect_parameters():
    m = ChainModel(slack=0.3, compliance=1e-5)
    x = np.array([0.2, 0.3, 2.5])
    F = m.force(x)
    assert F[0] == 0 and F[1] == 0
    # series compliance: x - slack = x_chain(F) + compliance*F
    assert chainid.displacement(F[2]) + 1e-5 * F[2] == pytest.approx(2.2, rel=1e-12)


def test_linear_model_fit():
    x = np.linspace(-10, 10, 50)
    m = LinearModel.fit(x, 300.0 * (x - 1.5))
    assert m.k == pytest.approx(300.0, rel=1e-12) and m.x_ref == pytest.approx(1.5, rel=1e-12)


def test_unknown_variant():
    with pytest.raises(ValueError, match="variant = 'foo' is invalid"):
        kernels.force(1.0, None, "foo")


def test_contact_power_kernel_reduces_to_hertz():
    x = np.logspace(-6, 2.5, 500)
    hertz = ChainModel()
    same = ChainModel(contact_exponent=2.0 / 3.0)
    assert np.allclose(same.force(x), hertz.force(x), rtol=1e-12, atol=0)
    assert np.allclose(same.stiffness(x), hertz.stiffness(x), rtol=1e-11, atol=0)


@settings(max_examples=100, deadline=None)
@given(st.floats(-9, 3), st.floats(0.3, 1.4))
def test_contact_power_round_trip_and_derivative(log_x, beta):
    m = ChainModel(contact_exponent=beta)
    mod = kernels.power_module()
    x = 10.0**log_x
    F = float(m.force(np.array([x]))[0])
    assert abs(mod.displacement(F, *m.coefficients) - x) <= 1e-12 * x
    h = 1e-4 * x
    fd = (m.force(np.array([x + h]))[0] - m.force(np.array([x - h]))[0]) / (2 * h)
    assert float(m.stiffness(np.array([x]))[0]) == pytest.approx(fd, rel=1e-6)


@settings(max_examples=60, deadline=None)
@given(st.lists(st.one_of(st.floats(-9, 3).map(lambda v: 10.0**v),
                          st.sampled_from([-1.0, 0.0, math.nan, math.inf])), min_size=1, max_size=40),
       st.floats(0.3, 1.4))
def test_contact_power_array_solves_every_sample_in_any_order(xs, beta):
    """force_array starts each sample's Newton at the last sample's root (from below it, from above, across
    12 decades, after a zero, a NaN or an infinite x): every tension is still the root, its closed-form
    displacement (Eq. 15, free exponent) back to x within 1e-12, and the same as the sample solved alone
    (x = inf: F = inf, alone or in an array)."""
    m = ChainModel(contact_exponent=beta)
    mod = kernels.power_module()
    x = np.array(xs)
    F = mod.force_array(x, *m.coefficients)
    for xi, Fi in zip(x, F):
        if math.isnan(xi):
            assert math.isnan(Fi)
        elif math.isinf(xi):
            assert Fi == math.inf and mod.force(xi, *m.coefficients) == math.inf
        elif xi <= 0.0:
            assert Fi == 0.0
        else:
            assert abs(mod.displacement(Fi, *m.coefficients) - xi) <= 1e-12 * xi
            assert Fi == pytest.approx(mod.force(xi, *m.coefficients), rel=1e-13)


def test_conformal_contact_is_stiffer_at_small_x():
    # β → 1 (conformal, plastic set) at the same approach at 10 kN: stiffer below 10 kN
    x = np.array([0.3])
    assert ChainModel(contact_exponent=0.95).stiffness(x)[0] > ChainModel().stiffness(x)[0]
    assert ChainModel(hertz_scale=0.5).force(x)[0] > ChainModel().force(x)[0]
    with pytest.raises(ValueError, match="contact_exponent"):
        ChainModel(contact_exponent=3.0)


def test_cli_stiffness_json(capsys):
    import json

    from chainid import cli

    assert cli.main(["stiffness", "--x", "2.2", "--F", "11117", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    # the machine contract: exact key sets (a renamed key breaks every consumer)
    # the contract keys plus the load-limit warnings (Hertz contact beyond the elastic limit at 11 kN)
    assert set(doc) == {"chain", "variant", "c_lin_mm_per_N", "c_hertz_mm_per_N23", "points", "warnings"}
    assert any("elastic" in w for w in doc["warnings"])
    assert set(doc["chain"]) >= {"d", "pitch", "width", "n", "E", "nu", "mass_per_m"}
    pts = doc["points"]
    assert len(pts) == 2 and all(set(p) == {"x_mm", "F_k_N", "k_e_N_per_mm"} for p in pts)
    cl, ch = paper_forms.coefficients()
    assert doc["variant"] == "paper"
    assert doc["c_lin_mm_per_N"] == pytest.approx(cl, rel=1e-12)
    assert doc["c_hertz_mm_per_N23"] == pytest.approx(ch, rel=1e-12)
    assert pts[0]["x_mm"] == 2.2 and pts[0]["F_k_N"] == pytest.approx(paper_forms.F_of_x(2.2), rel=1e-12)
    assert pts[0]["k_e_N_per_mm"] == pytest.approx(paper_forms.k_e(2.2), rel=1e-12)
    assert pts[1]["F_k_N"] == pytest.approx(11117.0, rel=1e-12)
    assert pts[1]["x_mm"] == pytest.approx(paper_forms.x_of_F(11117.0), rel=1e-12)
    # --F with a variant: the elongation comes from that variant's Eq. 15 (shear: kappa = 10/9)
    assert cli.main(["stiffness", "--F", "11117", "--variant", "shear", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["variant"] == "shear"
    assert doc["points"][0]["x_mm"] == pytest.approx(paper_forms.x_of_F(11117.0, kappa=10 / 9), rel=1e-12)
    assert doc["points"][0]["F_k_N"] == pytest.approx(11117.0, rel=1e-12)
    assert cli.main(["stiffness"]) == 2


def test_stiffness_beyond_the_linear_switch_is_the_asymptote():
    """Above X_LINEAR (1e60 mm) and at +inf the stiffness is Eq. 16's limit 1/c_lin (the Hertz term vanishes as
    F^(-1/3)); c_lin of the built-in chain is 6.3358e-5 mm/N (Eq. 15, test_kernels' closed form)."""
    from chainid.model import kernels

    c_lin = kernels.coefficients()[0]
    assert c_lin == pytest.approx(6.3358e-5, rel=1e-4)
    k = kernels.stiffness(np.array([1e70, np.inf]))
    np.testing.assert_allclose(k, 1.0 / c_lin, rtol=1e-12)
    assert kernels.force(1e70) == pytest.approx(1e70 / c_lin, rel=1e-12)
