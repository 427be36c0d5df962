"""The line's element tables (chainid.dynamics.line_tables): the stiffest tangent of each memory element, which the
stable step must see, against the elements' laws by hand.  Units mm, N, kg."""
from __future__ import annotations

import numpy as np
import pytest

from chainid.dynamics import ChainLine
from chainid.dynamics.line_tables import element_stiffness


@pytest.mark.parametrize("r", [0.25, 0.5, 0.75, 1.0])
def test_a_bouc_wen_element_is_stiffest_unloading_at_max_1_2r_times_its_yield_slope(r):
    """Bouc–Wen (F_y = 5 N, x_y = 0.1 mm, n = 2, r) in a line of two 5-link segments: the stiffest tangent is
    unloading, max(1, 2r)·F_y/x_y, per segment scaled as the line scales its elements (reference links / links
    per segment = 16/5): 160 N/mm for r <= 0.5, 240 at 0.75, 320 at 1 (by hand)."""
    line = ChainLine(n_links=10, n_masses=2, pretension_N=1000.0, bouc_wen=((5.0, 0.1, 2.0, r),))
    scale = line.reference_links() / line.links_per_segment()
    assert scale.tolist() == [3.2, 3.2]
    np.testing.assert_allclose(element_stiffness(line), max(1.0, 2 * r) * 5.0 / 0.1 * scale, rtol=1e-12)


def test_spring_table_scales_travels_and_the_dead_band_stiffness_in_series():
    """16 links in 4 segments of a 16-link specimen: r = n_s/n_ref = 1/4.  Specimen slack 0.08 mm, dead band
    (k_d = 400 N/mm^1.5, g = 0.1 mm, p = 1.5, x_c = 0.6 mm), contact exponent 0.9: every row is (β, s·r, k_d·r^−p,
    g·r, p, x_c·r) = (0.9, 0.02, 3200, 0.025, 1.5, 0.15) by hand; without effects (0, 0, 0, 0, 1, 0) (a neutral p).
    ``extended_spring`` is False for the plain kernel and True for each of a contact exponent, a (negative) slack,
    a dead band and a play.  Bugs caught: r^−p → r^p, a travel not scaled, the default p, a flag of extended_spring
    dropped (a ``!=`` or ``>`` flipped, an ``or`` made ``and``)."""
    from chainid.dynamics.line_tables import extended_spring, spring_table

    kw = dict(n_links=16, n_masses=4, pretension_N=1_000.0)
    line = ChainLine(**kw, slack=0.08, deadband=(400.0, 0.1, 1.5, 0.6), contact_exponent=0.9)
    np.testing.assert_allclose(spring_table(line), np.tile([0.9, 0.02, 3200.0, 0.025, 1.5, 0.15], (4, 1)), rtol=1e-12)
    plain = ChainLine(**kw)
    assert spring_table(plain).tolist() == [[0.0, 0.0, 0.0, 0.0, 1.0, 0.0]] * 4
    assert extended_spring(plain) is False
    for extra in (dict(contact_exponent=0.9), dict(slack=-0.1), dict(deadband=(1.0, 0.0, 1.0, 0.0)),
                  dict(backlash_mm=0.01)):
        assert extended_spring(ChainLine(**kw, **extra)) is True, extra


def test_series_segments_sum_to_the_modified_specimen():
    """16 links in 4 segments (4, 4, 4, 4 links; contacts 4, 4, 4, 3 of the specimen's 15), ea_scale 2, compliance
    1e-6 mm/N, hertz_scale 1.5, contact exponent 0.9 with F_ref = 5 kN: by hand (Eq. 15 coefficients CL, CH of
    tests/paper_forms.py) c_lin,j = CL/4/2 + 1e-6/4 and c_h,j = 1.5·CH·(contacts_j/15)·5000^(2/3 − 0.9); in series
    they give the modified specimen x(F) = (CL/2 + 1e-6)·F + 1.5·CH·5000^(2/3 − 0.9)·F^0.9 at every F.
    Bug caught: the machine compliance scaled by n_ref/n_s instead of n_s/n_ref."""
    import paper_forms

    from chainid.dynamics.line_tables import spring_coefficients

    CL, CH = paper_forms.coefficients()
    line = ChainLine(n_links=16, n_masses=4, ea_scale=2.0, compliance=1e-6, hertz_scale=1.5, contact_exponent=0.9,
                     contact_ref_force=5_000.0)
    c_lin, c_h = spring_coefficients(line)
    fac = 1.5 * 5_000.0 ** (2 / 3 - 0.9)
    np.testing.assert_allclose(c_lin, CL / 8 + 0.25e-6, rtol=1e-9)
    np.testing.assert_allclose(c_h, fac * CH * np.array([4, 4, 4, 3]) / 15, rtol=1e-9)
    for F in (10.0, 2_000.0):
        x = np.sum(c_lin * F + c_h * F ** 0.9)
        assert x == pytest.approx((CL / 2 + 1e-6) * F + fac * CH * F ** 0.9, rel=1e-9)


def test_element_table_columns_of_every_kind_scaled_in_series():
    """The element table of 16 links in 4 segments (r = 1/4) with a play b = 0.08 mm, a Jenkins element (2000 N/mm,
    100 N), a Coulomb element (50 N, stick 5000 N/mm), a Dahl element (30 N, 0.2 mm), a Stribeck element (80 N,
    60 N, 2 mm/s, 15 N; stick 4000 N/mm) and three Bouc–Wen elements, two sharing (n, r) = (2.5, 0.6): columns in
    the documented order play, Jenkins, Coulomb, Dahl, Stribeck, Bouc–Wen, by hand
    hf = 0, 100, 50, 30, 80, 150, 100, 50;  hx = b/2·r = 0.01, f·r/k = 0.0125 and 0.0025, x_h·r = 0.05, k/r = 16000,
    x_y·r = 0.01, 0.02, 0.005;  hd = 4, 0, 0, 1, 2, 3, 3, 3;  Stribeck extras (dF_s, v_s·r, dF) = (60, 0.5, 15);
    Bouc–Wen extras (table, n, r) = (0, 2.5, 0.6) twice and (1, 1, 1), one travel table per distinct (n, r) (the
    operator's bouc_wen_table).  Bugs caught: the play's half-width, a travel or stiffness not scaled, the column
    order, the table index shared wrongly."""
    from chainid.dynamics.line_tables import element_arrays
    from chainid.model.operators import bouc_wen_table

    line = ChainLine(n_links=16, n_masses=4, pretension_N=1_000.0, backlash_mm=0.08, hysteresis=((2_000.0, 100.0),),
                     coulomb_N=50.0, coulomb_stiffness=5_000.0, dahl=((30.0, 0.2),),
                     stribeck=((80.0, 60.0, 2.0, 15.0),), stribeck_stiffness=4_000.0,
                     bouc_wen=((150.0, 0.04, 2.5, 0.6), (100.0, 0.08, 2.5, 0.6), (50.0, 0.02, 1.0, 1.0)))
    hf, hx, hd, hq, tabs = element_arrays(line)
    assert hf.shape == (4, 8) and hq.shape == (4, 8, 3)
    np.testing.assert_allclose(hf, np.tile([0.0, 100.0, 50.0, 30.0, 80.0, 150.0, 100.0, 50.0], (4, 1)), rtol=1e-15)
    np.testing.assert_allclose(hx, np.tile([0.01, 0.0125, 0.0025, 0.05, 16_000.0, 0.01, 0.02, 0.005], (4, 1)),
                               rtol=1e-12)
    assert hd.tolist() == [[4, 0, 0, 1, 2, 3, 3, 3]] * 4
    want_q = np.zeros((8, 3))
    want_q[4] = (60.0, 0.5, 15.0)
    want_q[5] = want_q[6] = (0.0, 2.5, 0.6)
    want_q[7] = (1.0, 1.0, 1.0)
    np.testing.assert_allclose(hq, np.broadcast_to(want_q, (4, 8, 3)), rtol=1e-15)
    assert tabs.shape[:2] == (2, 2)
    for i, (n, r) in enumerate(((2.5, 0.6), (1.0, 1.0))):
        _, xi, Z = bouc_wen_table(n, r)
        np.testing.assert_array_equal(tabs[i], np.stack([xi, Z]))


def test_element_stiffness_of_jenkins_stribeck_and_dahl_in_series():
    """The stiffest tangent of each element per segment of 4 links (r = 1/4, the stable step's term): a sticking
    Jenkins element k/r = 8000 N/mm, a sticking Stribeck slider k/r = 16 000 N/mm, a Dahl element at a reversal
    2F_h/(x_h·r) = 2·30/0.05 = 1200 N/mm, a play none: 25 200 N/mm in all (by hand).
    Bugs caught: the Stribeck column's stiffness, the Jenkins f/x, a play counted."""
    line = ChainLine(n_links=16, n_masses=4, pretension_N=1_000.0, backlash_mm=0.08, hysteresis=((2_000.0, 100.0),),
                     dahl=((30.0, 0.2),), stribeck=((80.0, 60.0, 2.0, 15.0),), stribeck_stiffness=4_000.0)
    np.testing.assert_allclose(element_stiffness(line), 25_200.0, rtol=1e-12)
    only_play = ChainLine(n_links=16, n_masses=4, pretension_N=1_000.0, backlash_mm=0.08)
    assert element_stiffness(only_play).tolist() == [0.0] * 4
