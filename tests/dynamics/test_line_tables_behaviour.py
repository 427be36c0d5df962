"""The per-segment tables of a chain line (chainid.dynamics.line_tables) on UNEQUAL segments and edge cases, by hand
from the paper's Eq. 15 coefficients (tests/paper_forms.py): the split of the kernel, the series ratio, the
modifiers applied alone, the default Stribeck stick, an empty element table.  Units mm, N, s."""
from __future__ import annotations

import numpy as np
import pytest

import paper_forms
from chainid.dynamics import ChainLine
from chainid.dynamics.line_tables import (deadband_stiffness, element_arrays, element_stiffness, series_ratio,
                                          spring_coefficients)

CL16 = paper_forms.coefficients()[0]


def test_unequal_segments_split_the_link_and_contact_compliances():
    """10 links in 3 segments of 4, 3, 3 links: c_lin,j = CL(10)·n_s/10 and c_h,j = CH(10)·contacts/9 with contacts
    4, 3, 2 (the last segment holds one link end without a contact; Eq. 15 coefficients by hand); in series they
    are the 10-link chain.  Bugs caught: the contact taken from the first segment, c_h over n instead of n − 1."""
    CL, CH = paper_forms.coefficients(n=10)
    c_lin, c_h = spring_coefficients(ChainLine(n_links=10, n_masses=3))
    np.testing.assert_allclose(c_lin, CL * np.array([4, 3, 3]) / 10, rtol=1e-9)
    np.testing.assert_allclose(c_h, CH * np.array([4, 3, 2]) / 9, rtol=1e-9)
    assert c_h.sum() == pytest.approx(CH, rel=1e-9)


def test_a_one_link_chain_has_no_contact():
    """One link, one segment: c_lin of Eq. 15 with n = 1 (2·(ΔL₁ + ΔL₂ + ΔL₃)), no contact at all: c_h = 0, finite
    (not 0/0).  Bug caught: ``n_links > 1`` → ``>= 1`` (a nan contact coefficient)."""
    c_lin, c_h = spring_coefficients(ChainLine(n_links=1, n_masses=1))
    assert c_lin[0] == pytest.approx(paper_forms.coefficients(n=1)[0], rel=1e-9)
    assert c_h.tolist() == [0.0]


def test_each_kernel_modifier_alone_and_the_series_ratio_of_a_given_specimen():
    """10 links in segments of 4, 3, 3 of an 8-link specimen: r = n_s/8 = 0.5, 0.375, 0.375.  hertz_scale 2 alone
    doubles c_h and leaves c_lin; ea_scale 4 alone quarters c_lin and leaves c_h; compliance 1e-6 mm/N alone adds
    1e-6·r to c_lin (by hand).  Bugs caught: a ``!= 1.0`` test flipped, the compliance scaled by 1/r or by the
    chain's default 16 links."""
    kw = dict(n_links=10, n_masses=3, damping_ref_links=8)
    base_l, base_h = spring_coefficients(ChainLine(**kw))
    np.testing.assert_allclose(series_ratio(ChainLine(**kw)), [0.5, 0.375, 0.375], rtol=1e-15)
    c_lin, c_h = spring_coefficients(ChainLine(**kw, hertz_scale=2.0))
    np.testing.assert_allclose(c_h, 2.0 * base_h, rtol=1e-15)
    np.testing.assert_allclose(c_lin, base_l, rtol=1e-15)
    c_lin, c_h = spring_coefficients(ChainLine(**kw, ea_scale=4.0))
    np.testing.assert_allclose(c_lin, base_l / 4.0, rtol=1e-15)
    np.testing.assert_allclose(c_h, base_h, rtol=1e-15)
    c_lin, _ = spring_coefficients(ChainLine(**kw, compliance=1e-6))
    np.testing.assert_allclose(c_lin, base_l + 1e-6 * np.array([0.5, 0.375, 0.375]), rtol=1e-12)


def test_a_stribeck_stick_defaults_to_the_specimens_link_stiffness_scaled_in_series():
    """A Stribeck element without its own stick stiffness: the 16-link specimen's 1/c_lin (Eq. 15 by hand) over
    r = n_s/16 per segment of 4, 3, 3 links: 4/CL, 16/(3CL), 16/(3CL) N/mm; kind 2; the stable step's element
    stiffness is that stick (by hand).  Bugs caught: ``stribeck_stiffness is None`` flipped, k·r instead of k/r."""
    line = ChainLine(n_links=10, n_masses=3, stribeck=((80.0, 60.0, 2.0, 15.0),))
    hf, hx, hd, hq, tabs = element_arrays(line)
    want = np.array([16 / 4, 16 / 3, 16 / 3]) / CL16
    np.testing.assert_allclose(hx[:, 0], want, rtol=1e-9)
    assert hd.tolist() == [[2]] * 3 and hf.tolist() == [[80.0]] * 3
    np.testing.assert_allclose(hq[:, 0, 1], 2.0 * np.array([4, 3, 3]) / 16, rtol=1e-15)
    np.testing.assert_allclose(element_stiffness(line), want, rtol=1e-9)


def test_jenkins_and_dahl_columns_on_unequal_segments():
    """A Jenkins element (k 2000 N/mm, f 100 N) and a Dahl element (F_h 30 N, x_h 0.2 mm) of the 16-link specimen on
    segments of 4, 3, 3 links (r = 0.25, 0.1875, 0.1875): Jenkins stick travel f/(k/r) = 0.0125, 0.009375 mm, Dahl
    travel x_h·r = 0.05, 0.0375 mm; stiffest tangents k/r + 2F_h/(x_h·r) = 8000 + 1200 and 32000/3 + 1600 N/mm.
    Bugs caught: the ratio of the first segment used for all, a Dahl travel scaled by 1/r."""
    line = ChainLine(n_links=10, n_masses=3, hysteresis=((2_000.0, 100.0),), dahl=((30.0, 0.2),))
    hf, hx, hd, _, _ = element_arrays(line)
    np.testing.assert_allclose(hx, [[0.0125, 0.05], [0.009375, 0.0375], [0.009375, 0.0375]], rtol=1e-12)
    assert hd.tolist() == [[0, 1]] * 3 and hf.tolist() == [[100.0, 30.0]] * 3
    np.testing.assert_allclose(element_stiffness(line), [9_200.0, 32_000 / 3 + 1_600.0, 32_000 / 3 + 1_600.0],
                               rtol=1e-12)


def test_a_line_without_elements_has_empty_tables_and_no_extra_stiffness():
    """No play, Jenkins, Dahl, Stribeck or Bouc–Wen element: tables of shape (3, 0), (3, 0, 3), an int64 kind table,
    no Bouc–Wen travel table (0, 2, 2); element stiffness 0 and no dead-band tangent (0 N/mm) in every segment.
    Bugs caught: a Coulomb element added at coulomb_N = 0, the dead band's 0 default replaced."""
    line = ChainLine(n_links=10, n_masses=3, pretension_N=1_000.0)
    hf, hx, hd, hq, tabs = element_arrays(line)
    assert hf.shape == hx.shape == hd.shape == (3, 0) and hq.shape == (3, 0, 3) and tabs.shape == (0, 2, 2)
    assert hd.dtype == np.int64 and tabs.flags["C_CONTIGUOUS"]
    assert element_stiffness(line).tolist() == [0.0] * 3
    assert deadband_stiffness(line, 500.0).tolist() == [0.0] * 3


def test_a_linear_dead_bands_tangent_is_its_scaled_stiffness_at_any_force():
    """p = 1: F = k_d·(|u| − g) is linear, so its tangent is k_d/r at every force: k_d = 300 N/mm of the 16-link
    specimen on segments of 8 links (r = 1/2) gives 600 N/mm at 10 N and at 5 kN (by hand).
    Bugs caught: the exponent (p − 1)/p → p/(p − 1) (0^0 … or a force-dependent tangent), k_d·r^p."""
    line = ChainLine(n_links=16, n_masses=2, pretension_N=1_000.0, deadband=(300.0, 0.05, 1.0, 0.0))
    for F in (10.0, 5_000.0):
        np.testing.assert_allclose(deadband_stiffness(line, F), [600.0, 600.0], rtol=1e-12)
    line2 = ChainLine(n_links=16, n_masses=2, pretension_N=1_000.0, deadband=(300.0, 0.05, 2.0, 0.0))
    # p = 2, segment k_d = 300·2² = 1200: F = 1200·pen², tangent 2·1200·pen = 2·√(1200·F) = 2·√(1.2e6) at 1 kN
    np.testing.assert_allclose(deadband_stiffness(line2, 1_000.0), 2.0 * np.sqrt(1.2e6), rtol=1e-12)
