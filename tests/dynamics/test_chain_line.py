"""The chain line (chainid.dynamics.model): field bounds and derived numbers by hand, node masses and the shared
resistance, the viscous equivalent of a law at an operating point.  Units mm, N, s, kg."""
from __future__ import annotations

import numpy as np
import pytest

from chainid.dynamics import ChainLine, LoadStep


@pytest.mark.parametrize("kw, message", [
    (dict(n_masses=True), "n_masses = True is invalid: valid range an int >= 1"),
    (dict(n_links=True), "n_links = True is invalid: valid range an int >= 1"),
    (dict(n_masses=11), "n_masses = 11 is invalid: valid range 1 .. n_links = 10 (a segment holds >= 1 link)"),
    (dict(tensioner_stiffness=-1e-9), "tensioner_stiffness = -1e-09 is invalid: valid range >= 0 (finite)"),
    (dict(tail_mass_kg=float("inf")), "tail_mass_kg = inf is invalid: valid range >= 0 (finite)"),
    (dict(damping=-1.0), "damping = -1.0 is invalid: valid range >= 0 (finite)"),
    (dict(resistance_N=float("nan")), "resistance_N = nan is invalid: valid range >= 0 (finite)"),
    (dict(resistance_v_eps=0.0), "resistance_v_eps = 0.0 is invalid: valid range > 0 mm/s"),
    (dict(lumping="tail"), "lumping = 'tail' is invalid: valid range one of ['half', 'drive']"),
    (dict(damping_ref_links=0), "damping_ref_links = 0 is invalid: valid range an int >= 1"),
    (dict(dahl=((10.0, 0.0),)), "dahl = (10.0, 0.0) is invalid: valid range pairs (F_h > 0 N, x_h > 0 mm)"),
    (dict(coulomb_N=True), "coulomb_N = True is invalid: valid range >= 0 N (finite)"),
    (dict(loads=(LoadStep(0, 10.0, 0.0),)), "loads.node = 0 is invalid: valid range 1 .. n_masses = 2"),
    (dict(loads=(LoadStep(3, 10.0, 0.0),)), "loads.node = 3 is invalid: valid range 1 .. n_masses = 2"),
    (dict(loads=(LoadStep(2, 10.0, -0.1),)), "valid range finite force_N [N] and t_on >= 0 s"),
    (dict(loads=(LoadStep(2, float("nan"), 0.0),)), "valid range finite force_N [N] and t_on >= 0 s"),
    (dict(lumping="drive"), "tail_mass_kg = 0.0 is invalid: valid range > 0 kg with lumping='drive' and a "
                            "tensioner far end"),
])
def test_chain_line_refuses_each_field_at_its_bound(kw, message):
    """Each field of ChainLine outside its documented range is refused with the field, the value and the range
    (n_links = 10, n_masses = 2 unless given); the bound itself is accepted (see the next test)."""
    args = dict(n_links=10, n_masses=2) | kw
    with pytest.raises(ValueError) as exc:
        ChainLine(**args)
    assert message in str(exc.value)


def test_chain_line_accepts_its_bounds_and_its_derived_numbers_by_hand():
    """The bounds themselves are valid (n_masses = n_links, zeros, loads on node N at t_on = 0, one reference
    link, drive lumping with a tail mass or a fixed end); a massless chain is refused; from_length rounds to
    whole links of the 50 mm pitch, at least one; the steady-running drive tension is pretension + resistance
    with a tensioner end and the pretension with a fixed end."""
    ChainLine(n_links=10, n_masses=10, tensioner_stiffness=0.0, tail_mass_kg=0.0, damping=0.0, resistance_N=0.0,
              damping_ref_links=1, loads=(LoadStep(10, 5.0, 0.0),), coulomb_N=0.0)
    ChainLine(n_links=10, n_masses=2, lumping="drive", tail_mass_kg=1e-3)
    ChainLine(n_links=10, n_masses=2, lumping="drive", far_end="fixed")
    line = ChainLine(n_links=10, n_masses=2)
    with pytest.raises(ValueError, match=r"chain.mass_per_m = 0.0 is invalid: valid range > 0 kg/m"):
        ChainLine(n_links=10, n_masses=2, chain=line.chain.replace(mass_per_m=0.0))
    assert ChainLine.from_length(20.0, 1).n_links == 1  # 0.4 links -> at least one
    assert ChainLine.from_length(1_030.0, 2).n_links == 21 and ChainLine.from_length(1_070.0, 2).n_links == 21
    t = ChainLine(n_links=10, n_masses=2, pretension_N=800.0, resistance_N=150.0)
    assert t.static_tension_at_speed() == 950.0
    f = ChainLine(n_links=10, n_masses=2, pretension_N=800.0, resistance_N=150.0, far_end="fixed")
    assert f.static_tension_at_speed() == 800.0


def test_viscous_equivalent_refuses_an_operating_point_outside_its_range():
    """ω > 0 rad/s, A > 0 mm, x0 >= 0 mm (x0 = 0 accepted; a zero c_e is valid), each refusal naming the field,
    the value and the range."""
    from chainid.dynamics.model import viscous_equivalent

    assert viscous_equivalent(0.0, 1e-9, 1e-9, 0.0) == 0.0
    for args, message in (((0.0, 0.5, 2.0), "omega = 0.0 is invalid: valid range > 0 rad/s"),
                          ((float("inf"), 0.5, 2.0), "omega = inf is invalid: valid range > 0 rad/s"),
                          ((10.0, 0.0, 2.0), "A = 0.0 is invalid: valid range > 0 mm"),
                          ((10.0, 0.5, -1e-9), "x0 = -1e-09 is invalid: valid range >= 0 mm")):
        with pytest.raises(ValueError) as exc:
            viscous_equivalent(5.0, *args)
        assert str(exc.value) == message
    with pytest.raises(ValueError, match=r"c_e = -1.0 is invalid: valid range >= 0 N·s/mm"):
        viscous_equivalent(-1.0, 10.0, 0.5, 2.0)


def test_viscous_equivalent_of_a_law_at_the_operating_point():
    """A law object is evaluated at (ω, A, x0): Eq. 21 with α = (0.01, 0.2, 3, 4, 5) at ω = 10, A = 0.5 gives
    c_e = 1 + 2 + 0.75 + 2 + 5 = 10.75 N·s/mm (by hand); a number is taken as c_e itself.
    Bug caught: the law's first (only) value not the one taken."""
    from chainid.dynamics.model import viscous_equivalent
    from chainid.model.laws import PolynomialLaw

    assert viscous_equivalent(PolynomialLaw([0.01, 0.2, 3.0, 4.0, 5.0]), 10.0, 0.5, 2.0) == pytest.approx(10.75,
                                                                                                        rel=1e-12)
    assert viscous_equivalent(7, 10.0, 0.5, 2.0) == 7.0
    with pytest.raises(ValueError, match="c_e"):
        viscous_equivalent(PolynomialLaw([0.0, 0.0, 0.0, 0.0, -1.0]), 10.0, 0.5, 2.0)


def test_node_masses_half_and_drive_lumping_with_a_tail_mass():
    """20 links of the built-in chain in 4 segments of 5 links: each segment m_s = mass_per_m·5·pitch·1e-3 kg.
    `half`: m_s/2 at the ends, m_s inside; `drive`: m_s on each drive-side node; the tail mass 5 kg on the far-end
    node only (by hand)."""
    from chainid.chain.spec import default_chain

    c = default_chain()
    ms = c.mass_per_m * 5 * c.pitch * 1e-3
    half = ChainLine(n_links=20, n_masses=4, tail_mass_kg=5.0).node_masses()
    np.testing.assert_allclose(half, [ms / 2, ms, ms, ms, ms / 2 + 5.0], rtol=1e-12)
    drive = ChainLine(n_links=20, n_masses=4, tail_mass_kg=5.0, lumping="drive").node_masses()
    np.testing.assert_allclose(drive, [ms, ms, ms, ms, 5.0], rtol=1e-12)


# ---------------------------------------------------------------- survivors of the blind seed-23 run
@pytest.mark.parametrize("far_end", ["fixed", "tensioner"])
def test_resistance_is_shared_over_the_moving_nodes_by_mass(far_end):
    """R_i ∝ the lumped mass of each moving node, summing to R: node 0 (the drive's) carries none, and a fixed far
    end (it does not move) none either.  4 segments, half lumping, tail mass 2 kg: masses m/2, m, m, m, m/2 + 2
    (m = one segment's mass); R = 100 N.  Bug caught: ``far_end == "fixed"`` → ``< "fixed"`` (a fixed end's
    node kept its share)."""
    from chainid.dynamics import ChainLine

    line = ChainLine(n_links=8, n_masses=4, far_end=far_end, resistance_N=100.0, tail_mass_kg=2.0)
    ms = line.chain.mass_per_m * line.segment_lengths()[0] * 1e-3
    w = np.array([0.0, ms, ms, ms, 0.5 * ms + 2.0])
    if far_end == "fixed":
        w[-1] = 0.0
    np.testing.assert_allclose(line.resistance_per_node(), 100.0 * w / w.sum(), rtol=1e-12)
    assert line.resistance_per_node().sum() == pytest.approx(100.0, rel=1e-12)


def test_zero_links_and_a_zero_length_are_refused_by_their_own_names():
    """n_links = 0 is refused as n_links (an int >= 1), before the n_masses check; a chain of length 0 mm is
    refused by from_length (> 0 mm), not rounded up to one link.
    Bugs caught: ``n_links < 1`` → ``< 0`` (the error then names n_masses), ``length_mm > 0`` → ``>= 0``."""
    with pytest.raises(ValueError) as exc:
        ChainLine(n_links=0, n_masses=1)
    assert str(exc.value) == "n_links = 0 is invalid: valid range an int >= 1 (chain length / pitch > 0)"
    with pytest.raises(ValueError) as exc:
        ChainLine.from_length(0.0, 1)
    assert str(exc.value) == "length_mm = 0.0 is invalid: valid range > 0 mm"


def test_a_line_without_a_moving_node_shares_no_resistance():
    """One segment with a fixed far end: node 0 is the drive's and node 1 is anchored, so no node moves and the
    resistance R = 100 N goes nowhere: R_i = 0 on both nodes (not 0/0).  Bug caught: ``tot > 0`` → ``tot >= 0``."""
    line = ChainLine(n_links=10, n_masses=1, far_end="fixed", resistance_N=100.0)
    r = line.resistance_per_node()
    assert r.tolist() == [0.0, 0.0]


def test_the_coulomb_element_defaults_to_the_specimens_link_stiffness():
    """specimen_elements: no Coulomb element without coulomb_N; with coulomb_N = 50 N its stick stiffness defaults to
    the specimen's link stiffness 1/c_lin with c_lin of Eq. 15 by hand (tests/paper_forms.py: c_lin ∝ n, so an
    8-link specimen is twice as stiff), c_lin/ea_scale and + compliance applied each on its own; a given
    coulomb_stiffness is used as it is, after the hysteresis elements.
    Bugs caught: ``coulomb_N > 0`` → ``>= 0``, the reference links, ``ea_scale != 1 or compliance`` → ``and``."""
    import paper_forms

    cl16, cl8 = paper_forms.coefficients(n=16)[0], paper_forms.coefficients(n=8)[0]
    kw = dict(n_links=32, n_masses=2)
    assert ChainLine(**kw).specimen_elements() == []
    cases = [(dict(), 1 / cl16), (dict(damping_ref_links=8), 1 / cl8), (dict(ea_scale=2.0), 2 / cl16),
             (dict(compliance=1e-6), 1 / (cl16 + 1e-6)), (dict(ea_scale=2.0, compliance=1e-6), 1 / (cl16 / 2 + 1e-6))]
    for extra, k in cases:
        (el,) = ChainLine(**kw, coulomb_N=50.0, **extra).specimen_elements()
        assert el[0] == pytest.approx(k, rel=1e-9) and el[1] == 50.0, extra
    els = ChainLine(**kw, coulomb_N=50.0, coulomb_stiffness=5_000.0, hysteresis=((2_000.0, 100.0),)).specimen_elements()
    assert els == [(2_000.0, 100.0), (5_000.0, 50.0)]
