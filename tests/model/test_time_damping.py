"""Time-domain damping (chainid.model.timedamping): Eq. 21's design columns, the damping forms, a law resolved to
a viscous c or a test's fitted value, the hysteretic rule's energy per cycle, the dominant frequency.
Units mm, N, s, rad/s."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.model import ChainModel
from chainid.model.timedamping import Damping, design, dominant


MODEL = ChainModel()


def test_hysteretic_rule_keeps_the_energy_per_cycle():
    w, A, c = 2.0, 0.3, 50.0
    d = Damping("law", law="viscous", coefficients=[c], rule="hysteretic").resolve(w, A, 0.0, x0=0.0)
    t = np.linspace(0, 3 * 2 * math.pi / w, 6001)
    F, dE = d.force(A * np.sin(w * t), A * w * np.cos(w * t))
    assert np.sum(dE[-2000:]) == pytest.approx(math.pi * c * w * A * A, rel=1e-9)  # viscous c: W = πcωA²
    # the compensating spring removes the in-phase first harmonic; the quadrature one is c·ω·A
    psi = w * t[-2001:-1]
    assert 2 * np.mean(F[-2001:-1] * np.sin(psi)) == pytest.approx(0.0, abs=1e-3 * c * w * A)
    assert 2 * np.mean(F[-2001:-1] * np.cos(psi)) == pytest.approx(c * w * A, rel=2e-3)


def test_dominant_frequency_and_amplitude_of_a_ramped_record():
    from chainid.records.simulate import TestSpec, simulate_test

    r = simulate_test(TestSpec("a", 3.0, 5.0, 0.4), MODEL, 1.0, ramp_rate=0.08973, n_cycles=8)
    w, A, x0 = dominant(r.t, r.x)
    assert w == pytest.approx(3.0, rel=2e-3) and A == pytest.approx(0.4, rel=5e-3) and x0 == pytest.approx(5.0, rel=1e-3)


W, A, X0 = 2 * math.pi * 2.0, 0.5, 3.0  # 2 Hz, 0.5 mm about 3 mm


# ---------------------------------------------------------------- timedamping
def test_design_columns_closed_form():
    """Eq. 21's columns (ω², ω, A², A, 1); coulomb 4/(πωA); hysteretic k_e/ω; sums side by side."""
    w, a, ke = np.array([2.0, 5.0]), np.array([0.5, 0.25]), np.array([100.0, 300.0])
    np.testing.assert_allclose(design("polynomial", w, a, ke), [[4, 2, 0.25, 0.5, 1], [25, 5, 0.0625, 0.25, 1]])
    np.testing.assert_allclose(design("viscous+coulomb+hysteretic", w, a, ke),
                               [[1, 4 / (math.pi * 1.0), 50.0], [1, 4 / (math.pi * 1.25), 60.0]], rtol=1e-14)
    with pytest.raises(ValueError, match="unknown"):
        design("cubic", w, a, ke)


def test_law_resolves_to_viscous_c_or_the_fitted_test_value():
    """viscous+coulomb c = c₁ + 4·F_f/(πωA) = 2 + 4·30/(π·10·0.5) (by hand); a test the law was fitted on uses its
    own c_e only when asked (fitted=True)."""
    d = Damping("law", law="viscous+coulomb", coefficients=[2.0, 30.0], per_test={"T1": 9.0})
    c = 2.0 + 120.0 / (math.pi * 5.0)
    assert d.ce(10.0, 0.5, 123.0) == pytest.approx(c, rel=1e-14)
    assert d.resolve(10.0, 0.5, 123.0).params == {"c": pytest.approx(c, rel=1e-14)}
    assert d.resolve(10.0, 0.5, 123.0, test="T1", fitted=True).params == {"c": 9.0}
    assert d.resolve(10.0, 0.5, 123.0, test="T1").params["c"] == pytest.approx(c, rel=1e-14)
    assert d.resolve(10.0, 0.5, 123.0, test="T2", fitted=True).params["c"] == pytest.approx(c, rel=1e-14)
    h = Damping("law", law="hysteretic", coefficients=[0.2]).resolve(10.0, 0.5, 150.0)
    assert h.form == "viscous" and h.params["c"] == pytest.approx(0.2 * 150.0 / 10.0, rel=1e-14)  # η·k_e/ω


def test_hysteretic_rule_dissipates_the_viscous_energy_per_cycle_in_quadrature():
    """Rule `hysteretic`: the Iwan distribution of equal energy per cycle: on x = x0 + A sin ψ its steady loop has
    the viscous loop's energy π·c·ω·A² and (the compensating spring) no in-phase first harmonic.
    c = 3 N·s/mm, ω = 4π rad/s, A = 0.5 mm: π·3·4π·0.25 = 29.61 N·mm."""
    d = Damping("law", law="viscous", coefficients=[3.0], rule="hysteretic").resolve(W, A, 0.0, x0=X0)
    assert d.form == "hysteretic" and d.params["eta_k"] == pytest.approx(3.0 * W, rel=1e-14)
    assert d.params["x_max"] == A and d.params["x_c"] == X0
    psi = np.linspace(0.0, 2 * math.pi, 4000, endpoint=False)
    x = X0 + A * np.sin(psi)
    F, _ = d.force(x, W * A * np.cos(psi), periodic=True)
    energy = -float(np.sum(F * np.gradient(np.sin(psi), psi) * A)) * (psi[1] - psi[0])  # ∮F dx with dx = A cos ψ dψ
    assert abs(energy) == pytest.approx(math.pi * 3.0 * W * A * A, rel=0.02)
    assert abs(2 * np.mean(F * np.sin(psi))) < 0.02 * abs(2 * np.mean(F * np.cos(psi)))


def test_damping_forms_closed_form():
    """none → 0; viscous c·ẋ; coulomb without stick F_c·sgn(ẋ) (0 at a reversal sample); a law unresolved is
    refused; an unknown form / parameter / rule or a negative value is refused naming it."""
    x = np.array([0.0, 1.0, 2.0, 1.0, 0.0])
    xd = np.array([1.0, 2.0, 0.0, -2.0, -1.0])
    assert not np.any(Damping("none").force(x, xd)[0])
    np.testing.assert_allclose(Damping("viscous", {"c": 2.5}).force(x, xd)[0], 2.5 * xd)
    np.testing.assert_allclose(Damping("coulomb", {"F_c": 40.0}).force(x, xd, periodic=False)[0],
                               [40.0, 40.0, 0.0, -40.0, -40.0])
    with pytest.raises(ValueError, match="resolved"):
        Damping("law", law="viscous", coefficients=[1.0]).force(x, xd)
    for kw, msg in ((dict(form="viscid"), "form"), (dict(form="coulomb", params={"c": 1.0}), "unknown parameter"),
                    (dict(form="coulomb", params={"F_c": -1.0}), "out of range"),
                    (dict(form="law", law="viscous", coefficients=[1.0, 2.0]), "1 coefficient"),
                    (dict(form="viscous", rule="stiff"), "rule")):
        with pytest.raises(ValueError, match=msg):
            Damping(**kw)
    assert Damping("viscous", {"c": -0.5}).params["c"] == -0.5  # an identified viscous c may be negative


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


@pytest.mark.parametrize("cycles", [3.5, 5.2])
def test_dominant_frequency_of_a_few_cycles_between_bins(cycles):
    """3.5 and 5.2 cycles of a sine over the record (2048 samples over 4 s): ω within 1e-4 of 2π·cycles/T (hand;
    measured 5e-6 and 2e-6) and A within 1 % of 2 mm.  With so few cycles the phase-drift refinement cannot repair
    a wrong start, so the spectral peak's parabola must be right.  Bug caught (seed 27): the parabola's offset
    ``0.5·(a − c)/den`` → ``0.5·(a − c) % den`` (ω 37 % low at 3.5 cycles, 2e-4 low at 5.2)."""
    T = 4.0
    t = np.linspace(0.0, T, 2048, endpoint=False)
    w = 2 * math.pi * cycles / T
    om, A, _ = dominant(t, 0.7 + 2.0 * np.sin(w * t + 0.3))
    assert om == pytest.approx(w, rel=1e-4)
    assert A == pytest.approx(2.0, rel=1e-2)


FEATURE = {"c": 2.0, "b_w": 0.1, "b_A": -1.0, "w_ref": 10.0, "A_ref": 1.0}


@pytest.mark.parametrize("w, A, c", [
    (10.0, 1.0, 2.0),            # the reference point
    (15.0, 1.2, 2.3),            # inside the box: 2 + 0.1·5 − 1·0.2
    (2.0, 1.0, 1.5),             # below the box in ω: the law at ω = 5
    (30.0, 3.0, 2.5),            # beyond both: at (20, 1.5), 2 + 1 − 0.5
    (10.0, 0.1, 2.5),            # below the box in A: at A = 0.5
])
def test_a_feature_law_is_held_at_its_box(w, A, c):
    """A law over record features is not extrapolated: a record outside the box [w_lo, w_hi] × [A_lo, A_hi] it was
    identified on takes the law at the nearest point of the box (by hand); without a box the law is linear
    everywhere."""
    d = Damping("feature", FEATURE | {"w_lo": 5.0, "w_hi": 20.0, "A_lo": 0.5, "A_hi": 1.5})
    assert d.resolve(w, A, 0.0).params["c"] == pytest.approx(c, rel=1e-12)
    free = 2.0 + 0.1 * (w - 10.0) - 1.0 * (A - 1.0)
    assert Damping("feature", FEATURE).resolve(w, A, 0.0).params["c"] == pytest.approx(free, rel=1e-12)


@pytest.mark.parametrize("box, key", [({"w_lo": 5.0}, "w_lo"), ({"A_lo": 2.0, "A_hi": 1.0}, "A_lo")])
def test_a_feature_laws_box_needs_both_ends_in_order(box, key):
    with pytest.raises(ValueError, match=f"{key} <= "):
        Damping("feature", FEATURE | box)


def test_each_laws_coefficient_count_is_its_design_matrix_columns_in_the_law_module():
    """``LAWS`` (the count a model file's law must carry) against the other place the laws live, the design
    matrices of :mod:`chainid.model.laws` (Table 1 / Eq. 21 forms: polynomial 5, each simple term 1, a sum the sum).
    A law with that count is accepted, with one more refused."""
    from chainid.model.laws import law_from_dict
    from chainid.model.timedamping import LAWS

    w, a, x0 = np.array([2.0, 5.0]), np.array([0.5, 0.25]), np.array([3.0, 3.0])
    for name, n in LAWS.items():
        law = law_from_dict({"name": name, "params": None}, MODEL)
        assert law.design(w, a, x0).shape == (2, n), name
        Damping("law", law=name, coefficients=[1.0] * n)
        with pytest.raises(ValueError, match=f"has {n} coefficient"):
            Damping("law", law=name, coefficients=[1.0] * (n + 1))


def test_a_form_without_its_optional_parameters_adds_no_force_of_them():
    """Defaults of the forms (a hand-edited model file may leave keys out): viscous without ``c`` is no force;
    hysteretic without ``k_comp`` / ``x_c`` is the bare Iwan element, no compensating spring."""
    from chainid.model import operators as ops

    t = np.linspace(0.0, 1.0, 401)
    x, xd = 0.3 * np.sin(2 * math.pi * t), 0.6 * math.pi * np.cos(2 * math.pi * t)
    F, dE = Damping("viscous", {}).force(x, xd)
    assert np.all(F == 0.0) and np.all(dE == 0.0)
    F, _ = Damping("hysteretic", {"eta_k": 40.0, "x_max": 0.3, "n": 8}).force(x, xd)
    Fc, xs = ops.iwan_for_loss(40.0, 0.3, 8)
    bare, _ = ops.iwan(x, Fc, xs, periodic=False)
    np.testing.assert_allclose(F, bare, rtol=0, atol=1e-12 * np.max(np.abs(bare)))
    assert np.max(np.abs(bare)) > 1.0  # a real force, so a spring k_comp·(x − x_c) would show
    F, _ = Damping("hysteretic", {"eta_k": 40.0, "x_max": 0.3, "n": 8, "k_comp": 25.0}).force(x, xd)
    np.testing.assert_allclose(F, bare - 25.0 * x, rtol=0, atol=1e-12 * np.max(np.abs(bare)))  # x_c = 0 mm
