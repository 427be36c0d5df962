"""The energy balance (chainid.dynamics.energy.balance) at the round-off level of the stored energies, and the
elastic energy of segments in series against Eq. 15 by hand (tests/paper_forms.py).  Units N·mm, N, mm, s."""
from __future__ import annotations

import numpy as np
import pytest

import paper_forms
from chainid.dynamics import ChainLine, Drive, simulate
from chainid.dynamics.energy import balance, elastic_energy_array


def test_round_off_of_the_stored_energy_is_not_a_balance_error():
    """A chain at rest stores E_el = 263 N·mm; its energies change only by round-off, whole ulps of 263
    (u = 2^−44 = 5.7e-14 N·mm): ΔE_el = 0, 4u, −2u, 4u and W = 0, 2u, 0, −2u, so the residual is 0, −2u, 2u, −6u
    (by hand) and the scale 4u.  This is not an integration error: the relative error is measured against 1e-9 of
    the stored energy (the documented floor), 6u/(1e-9·263) = 1.3e-6, not 6u/4u = 1.5; while a real error of
    1e-4 N·mm in a small exchange (scale 1.1e-3 N·mm, 4e-6 of the stored energy) is still reported as 1e-4/1.1e-3.
    Bug caught (found by this test): |r|/scale of round-off over round-off, a spurious 'not converged' warning
    (with strict: an error) for a line at rest."""
    E0, u = 263.0, 2.0 ** -44
    z = np.zeros(4)
    eb = balance(u * np.array([0.0, 2.0, 0.0, -2.0]), z, E0 + u * np.array([0.0, 4.0, -2.0, 4.0]), z)
    assert (eb["scale"], eb["worst_residual"], eb["finite"]) == (4 * u, -6 * u, True)
    assert eb["relative_error"] == pytest.approx(6 * u / (1e-9 * E0), rel=1e-12)
    el = E0 + np.array([0.0, 5e-4, 1e-3, 1e-3])
    W = el - E0 + np.array([0.0, 0.0, 0.0, 1e-4])  # residual 0, 0, 0, 1e-4
    eb = balance(W, z, el, z)
    assert eb["relative_error"] == pytest.approx(1e-4 / 1.1e-3, rel=1e-9)


@pytest.mark.parametrize("scheme", ["explicit", "implicit"])
def test_a_line_at_rest_stays_at_its_pretension_without_a_balance_warning(scheme):
    """Three segments of a 10-link chain at 2 kN, the drive held (law none): the static state is an equilibrium,
    so every segment keeps 2 kN (rel 1e-9) and ``strict`` (which turns a balance error above 1e-3 into an error)
    passes with a relative error below 1e-3.  Bug caught: round-off of the stored energy taken as the balance
    error (strict raised 'energy balance error 0.8 … not converged')."""
    res = simulate(ChainLine(n_links=10, n_masses=3, pretension_N=2_000.0), Drive("none"), 0.01, scheme=scheme,
                   n_out=20, strict=True)
    np.testing.assert_allclose(res.tension, 2_000.0, rtol=1e-9)
    assert res.energy_balance()["relative_error"] < 1e-3 and res.refinements == 0


def test_segments_in_series_store_the_whole_chains_eq15_energy():
    """20 links in 4 segments, each at its static elongation under F = 2 kN (pretension_elongation): the segments'
    energies add up to the whole chain's U = F·x − CL·F²/2 − ⅗·CH·F^(5/3) (Eq. 15 of the 20-link chain by hand;
    U = F·x − ∫x dF, additive in series at a common force).  Bug caught: a segment skipped in the sum."""
    CL, CH = paper_forms.coefficients(n=20)
    F = 2_000.0
    line = ChainLine(n_links=20, n_masses=4, pretension_N=F)
    c_lin, c_h = line.segment_coefficients()
    U = elastic_energy_array(line.pretension_elongation(), c_lin, c_h)
    x = CL * F + CH * F ** (2 / 3)
    assert U == pytest.approx(F * x - CL * F * F / 2 - 0.6 * CH * F ** (5 / 3), rel=1e-9)
