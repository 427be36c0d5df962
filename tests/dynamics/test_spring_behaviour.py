"""The segment spring of the chain line (chainid.dynamics.springs): force, tangent and stored energy of the Hertz
(β flag 0) and free-exponent (β > 0) springs, and the static elongation with and without a dead band, each against
scipy (brentq, quad) or a closed form.  Units mm, N, N/mm, N·mm."""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

from chainid.dynamics.springs import SP_COLUMNS, spring_energy, spring_force, spring_stiffness, static_elongations

CL, CH = 1.6e-5, 2.2e-4  # mm/N and mm/N^β: a segment of a few links of the 14x50 chain (order of magnitude)


def _inverse(a, cl, ch, beta):
    """F with cl·F + ch·F^β = a (β = 2/3 for the Hertz flag 0), by brentq at 1e-14 relative."""
    b = 2.0 / 3.0 if beta == 0.0 else beta
    return brentq(lambda F: cl * F + ch * F ** b - a, 0.0, a / cl, xtol=1e-300, rtol=1e-14, maxiter=500)


@pytest.mark.parametrize("beta", [0.0, 0.5, 1.4])
def test_spring_force_inverts_the_compliance_of_its_exponent(beta):
    """x(F) = c_lin·F + c_h·F^β, inverted by brentq, at a = 0.01, 0.05, 0.3 mm: the Hertz flag 0 means β = 2/3 (the
    generated paper kernel), any other flag is the exponent itself; no force at a <= 0 (slack).
    Bugs caught: the β flag test inverted (β = 0 sent to the power kernel: F^0), the branches swapped."""
    for a in (0.01, 0.05, 0.3):
        assert spring_force(a, CL, CH, beta) == pytest.approx(_inverse(a, CL, CH, beta), rel=1e-10)
    assert spring_force(0.0, CL, CH, beta) == 0.0
    assert spring_force(-0.02, CL, CH, beta) == 0.0


@pytest.mark.parametrize("beta", [0.0, 0.5, 1.4])
def test_spring_tangent_is_the_inverse_of_the_compliance_slope(beta):
    """k = 1/(dx/dF) = 1/(c_lin + β·c_h·F^(β−1)) at the force the spring carries (β = 2/3 for the flag 0), by hand at
    a = 0.02 and 0.2 mm, and equal to a central difference of spring_force (h = 1e-7 mm); 0 when slack.
    Bug caught: the tangent's β flag test inverted (the Hertz tangent taken from the power kernel)."""
    b = 2.0 / 3.0 if beta == 0.0 else beta
    for a in (0.02, 0.2):
        F = _inverse(a, CL, CH, beta)
        k = 1.0 / (CL + b * CH * F ** (b - 1.0))
        assert spring_stiffness(a, CL, CH, beta) == pytest.approx(k, rel=1e-9)
        h = 1e-7
        fd = (spring_force(a + h, CL, CH, beta) - spring_force(a - h, CL, CH, beta)) / (2 * h)
        assert spring_stiffness(a, CL, CH, beta) == pytest.approx(fd, rel=1e-5)
    assert spring_stiffness(-0.01, CL, CH, beta) == 0.0


@pytest.mark.parametrize("beta", [0.0, 0.4, 1.3])
def test_spring_energy_is_the_integral_of_its_force(beta):
    """U(a) = ∫₀^a F(a') da' (scipy quad over an independent brentq inverse of the compliance) at a = 0.02, 0.1,
    0.4 mm, for the Hertz flag and two free exponents; U = 0 at and below a = 0.
    Bugs caught: the closed form's ½·c_lin, its (β + 1) divisor, the Hertz branch sent to the power formula."""
    for a in (0.02, 0.1, 0.4):
        ref = quad(lambda s: _inverse(s, CL, CH, beta) if s > 0 else 0.0, 0.0, a, epsabs=0.0, epsrel=1e-11,
                   limit=200)[0]
        assert spring_energy(a, CL, CH, beta) == pytest.approx(ref, rel=1e-8)
    assert spring_energy(0.0, CL, CH, beta) == 0.0
    assert spring_energy(-0.1, CL, CH, beta) == 0.0


def _sp(beta=0.0, s=0.0, kd=0.0, g=0.0, p=1.0, xc=0.0):
    row = dict(beta=beta, slack=s, k_d=kd, g=g, p=p, x_c=xc)
    return np.array([[row[c] for c in SP_COLUMNS]])


@pytest.mark.parametrize("beta, s", [(0.0, 0.0), (0.0, 0.3), (1.3, -0.05), (0.5, 0.2)])
def test_static_elongation_without_a_dead_band_is_slack_plus_compliance(beta, s):
    """Without a dead band the static elongation at T is the closed form s + c_lin·T + c_h·T^β (β = 2/3 for the flag
    0), for T = 0, 40 N and 5 kN, one segment per row (two rows with different coefficients).
    Bugs caught: the cube root squared (T^(2/3)) garbled, the β flag test inverted, the slack dropped or negated."""
    b = 2.0 / 3.0 if beta == 0.0 else beta
    cl, ch = np.array([CL, 2.0 * CL]), np.array([CH, 0.5 * CH])
    sp = np.vstack([_sp(beta, s), _sp(beta, s)])
    for T in (0.0, 40.0, 5_000.0):
        want = s + cl * T + ch * T ** b
        np.testing.assert_allclose(static_elongations(T, cl, ch, sp), want, rtol=1e-12, atol=1e-15)


@pytest.mark.parametrize("T, kd, g, p, xc", [
    (2_000.0, 5e4, 0.01, 1.5, 0.0),    # the stops carry most of the load
    (2_000.0, 5e4, 0.01, 1.0, 0.05),   # linear stops reached well after the spring took load
    (300.0, 2e3, 0.0, 2.0, -0.02),     # no gap, stops centred below the slack point
    (2_000.0, 5e4, 5.0, 1.5, 0.0),     # the gap is never closed: the spring alone
])
def test_static_elongation_with_a_dead_band_solves_the_force_balance(T, kd, g, p, xc):
    """With a dead band the static elongation e solves spring(e − s) + k_d·sgn(u)·max(|u| − g, 0)^p = T, u = e − x_c
    (the total is nondecreasing in e): brentq on that balance, written out here with an independent inverse of the
    Hertz compliance, to 1e-9 mm (s = 0.02 mm).
    Bugs caught: the bisection's comparison or its halves swapped, the bracket's growth test inverted, the dead band
    left out of the balance."""
    s = 0.02

    def total(e):
        a = e - s
        fs = 0.0 if a <= 0 else _inverse(a, CL, CH, 0.0)
        u = e - xc
        fd = kd * math.copysign(max(abs(u) - g, 0.0) ** p, u) if abs(u) > g else 0.0
        return fs + fd - T

    want = brentq(total, -10.0, 10.0, xtol=1e-13, rtol=1e-15, maxiter=500)
    got = static_elongations(T, np.array([CL]), np.array([CH]), _sp(0.0, s, kd, g, p, xc))[0]
    assert got == pytest.approx(want, abs=1e-9)
    if g < 1.0:
        assert got < s + CL * T + CH * T ** (2.0 / 3.0) - 1e-4  # the stops carry part of T: shorter than the spring
