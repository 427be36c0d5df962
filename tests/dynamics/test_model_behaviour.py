"""The chain line (chainid.dynamics.model) against hand numbers and the paper's Eq. 15 typed in tests/paper_forms.py:
the split into segments with a remainder, the series scaling of dampers and Jenkins elements, the static state at
the pretension and its tangent, the fixture mass, and the refusals not pinned elsewhere.  Units mm, N, s, kg."""
from __future__ import annotations

import math

import numpy as np
import pytest

import paper_forms
from chainid.dynamics import ChainLine, LoadStep, viscous_equivalent
from chainid.chain.spec import default_chain

PITCH, MASS_PER_M = 50.0, 4.0  # the built-in 14x50 chain: 50 mm pitch, 4 kg/m


def test_the_remainder_links_go_to_the_first_segments():
    """11 links in 4 segments: divmod(11, 4) = (2, 3), so the first 3 segments hold 3 links and the last 2 (sum 11);
    lengths n_s·50 mm = 150, 150, 150, 100; the line is 550 mm long with 5 nodes (by hand).
    Bugs caught: ``j < extra`` → ``j <= extra`` (four segments of 3), the remainder given to the last segments."""
    line = ChainLine(n_links=11, n_masses=4)
    assert line.links_per_segment().tolist() == [3, 3, 3, 2]
    assert line.segment_lengths().tolist() == [150.0, 150.0, 150.0, 100.0]
    assert line.length_mm == 550.0 and line.n_nodes == 5
    assert ChainLine(n_links=12, n_masses=4).links_per_segment().tolist() == [3, 3, 3, 3]


def test_half_lumping_of_unequal_segments_and_the_drive_fixture_mass():
    """11 links in 4 segments (150, 150, 150, 100 mm at 4 kg/m: 0.6, 0.6, 0.6, 0.4 kg), half lumping, a 2 kg fixture
    on node 0 and a 1 kg tail: masses 0.3 + 2, 0.6, 0.6, 0.5, 0.2 + 1 kg (by hand).
    Bugs caught: the fixture mass on the wrong node, the halves shifted by one node."""
    line = ChainLine(n_links=11, n_masses=4, drive_mass_kg=2.0, tail_mass_kg=1.0)
    np.testing.assert_allclose(line.node_masses(), [2.3, 0.6, 0.6, 0.5, 1.2], rtol=1e-12)
    drive = ChainLine(n_links=11, n_masses=4, drive_mass_kg=2.0, tail_mass_kg=1.0, lumping="drive")
    np.testing.assert_allclose(drive.node_masses(), [2.6, 0.6, 0.6, 0.4, 1.0], rtol=1e-12)


def test_segment_dampers_scale_as_dampers_in_series():
    """c_e = 6 N·s/mm of the 16-link specimen in segments of 4, 3, 3 links (10 links, N = 3): c·n_ref/n_s = 24, 32,
    32 N·s/mm; with damping_ref_links = 8: 12, 16, 16 (by hand).
    Bugs caught: n_ref/n_s inverted, damping_ref_links ignored (``is None`` flipped)."""
    np.testing.assert_allclose(ChainLine(n_links=10, n_masses=3, damping=6.0).segment_damping(), [24.0, 32.0, 32.0],
                               rtol=1e-12)
    line = ChainLine(n_links=10, n_masses=3, damping=6.0, damping_ref_links=8)
    assert line.reference_links() == 8
    np.testing.assert_allclose(line.segment_damping(), [12.0, 16.0, 16.0], rtol=1e-12)


def test_jenkins_elements_stiffen_in_short_segments_and_keep_their_slip_force():
    """Two Jenkins elements (2000 N/mm, 100 N) and (600 N/mm, 20 N) of the 16-link specimen in segments of 4, 3, 3
    links: k·16/n_s = 8000, 32000/3, 32000/3 and 2400, 3200, 3200 N/mm; f stays 100 and 20 N; shape (3, 2).  No
    element at all: shape (3, 0).  Bugs caught: k·n_s/n_ref, the slip force scaled, the element order."""
    line = ChainLine(n_links=10, n_masses=3, hysteresis=((2_000.0, 100.0), (600.0, 20.0)))
    k, f = line.segment_elements()
    np.testing.assert_allclose(k, [[8_000.0, 2_400.0], [32_000.0 / 3, 3_200.0], [32_000.0 / 3, 3_200.0]], rtol=1e-12)
    assert f.tolist() == [[100.0, 20.0]] * 3
    k0, f0 = ChainLine(n_links=10, n_masses=3).segment_elements()
    assert k0.shape == (3, 0) and f0.shape == (3, 0)


def test_static_elongations_add_up_to_the_whole_chains_eq15():
    """20 links in 4 segments of 5 at 2 kN: segment j stretches c_lin,j·F + c_h,j·F^(2/3) with the 20-link chain's
    coefficients (Eq. 15 by hand) split as c_lin·5/20 and c_h·(5, 5, 5, 4)/19 contacts; in series the four give the
    whole chain's x(2 kN).  Bugs caught: F^(2/3) as F^(1/3) (``u*u`` → ``u``), the cube root, the split."""
    CL, CH = paper_forms.coefficients(n=20)
    F = 2_000.0
    line = ChainLine(n_links=20, n_masses=4, pretension_N=F)
    want = CL / 4 * F + CH * np.array([5, 5, 5, 4]) / 19 * F ** (2 / 3)
    np.testing.assert_allclose(line.pretension_elongation(), want, rtol=1e-9)
    assert line.pretension_elongation().sum() == pytest.approx(paper_forms.x_of_F(F, n=20), rel=1e-9)
    assert ChainLine(n_links=20, n_masses=4).pretension_elongation().tolist() == [0.0] * 4


def test_static_elongation_with_a_slack_and_a_linear_contact():
    """Contact exponent β = 1 (reference force 1e4 N: c_h·1e4^(2/3 − 1)) and a specimen slack 0.2 mm, 16 links in 4
    segments (r = 1/4): x = s·r + (c_lin + c_h)·F is linear, so at 1 kN every segment but the last (3 contacts)
    stretches 0.05 + (CL/4 + CH·4/15·1e4^(−1/3))·1000 mm (Eq. 15 coefficients by hand).
    Bugs caught: the slack not scaled or not added, the extended path's inverse."""
    CL, CH = paper_forms.coefficients()
    F = 1_000.0
    line = ChainLine(n_links=16, n_masses=4, pretension_N=F, contact_exponent=1.0, slack=0.2)
    fac = 1e4 ** (2 / 3 - 1.0)
    want = 0.05 + (CL / 4 + CH * np.array([4, 4, 4, 3]) / 15 * fac) * F
    np.testing.assert_allclose(line.pretension_elongation(), want, rtol=1e-9)
    np.testing.assert_allclose(line.static_tangent(), 1.0 / (CL / 4 + CH * np.array([4, 4, 4, 3]) / 15 * fac),
                               rtol=1e-9)


def test_static_tangent_is_eq16_of_every_segment():
    """The tangent at 2 kN of 5-link segments of a 20-link chain: 1/(c_lin,j + ⅔·c_h,j·F^(−1/3)) (Eq. 15
    differentiated by hand); the last segment (one contact fewer) is the stiffer.
    Bugs caught: the tangent of the whole chain, the contact term's factor or power."""
    CL, CH = paper_forms.coefficients(n=20)
    F = 2_000.0
    k = ChainLine(n_links=20, n_masses=4, pretension_N=F).static_tangent()
    want = 1.0 / (CL / 4 + (2 / 3) * CH * np.array([5, 5, 5, 4]) / 19 * F ** (-1 / 3))
    np.testing.assert_allclose(k, want, rtol=1e-7)
    assert k[3] > k[0]


def test_from_length_passes_the_chain_and_the_fields_on():
    """1000 mm of a 40 mm pitch chain is 25 links; the keyword fields reach the line; with the default chain (50 mm)
    it is 20 links; a chain of None means the built-in chain.
    Bugs caught: the default pitch used for a given chain, the keywords dropped."""
    chain = default_chain().replace(pitch=40.0)
    line = ChainLine.from_length(1_000.0, 5, chain=chain, pretension_N=500.0, far_end="fixed")
    assert (line.n_links, line.n_masses, line.pretension_N, line.far_end) == (25, 5, 500.0, "fixed")
    assert line.length_mm == pytest.approx(1_000.0, rel=1e-12)
    assert ChainLine.from_length(1_000.0, 5).n_links == 20
    assert ChainLine(n_links=4, n_masses=2, chain=None).chain == default_chain()
    with pytest.raises(ValueError, match=r"^length_mm = nan is invalid: valid range > 0 mm$"):
        ChainLine.from_length(float("nan"), 1)


@pytest.mark.parametrize("kw, message", [
    (dict(n_masses=0), "n_masses = 0 is invalid: valid range an int >= 1"),
    (dict(n_masses=2.0), "n_masses = 2.0 is invalid: valid range an int >= 1"),
    (dict(n_links=10.0), "n_links = 10.0 is invalid: valid range an int >= 1 (chain length / pitch > 0)"),
    (dict(pretension_N=-1.0), "pretension_N = -1.0 is invalid: valid range >= 0 (finite)"),
    (dict(pretension_N="5"), "pretension_N = '5' is invalid: valid range >= 0 (finite)"),
    (dict(resistance_v_eps=float("inf")), "resistance_v_eps = inf is invalid: valid range > 0 mm/s"),
    (dict(far_end="free"), "far_end = 'free' is invalid: valid range one of ['fixed', 'tensioner']"),
    (dict(hysteresis=((0.0, 10.0),)), "hysteresis = (0.0, 10.0) is invalid: valid range pairs (k > 0 N/mm, f > 0 N), "
                                      "finite"),
    (dict(hysteresis=((10.0, 0.0),)), "hysteresis = (10.0, 0.0) is invalid"),
    (dict(hysteresis=((10.0, math.inf),)), "hysteresis = (10.0, inf) is invalid"),
    (dict(hysteresis=((10.0, 5.0, 1.0),)), "hysteresis = (10.0, 5.0, 1.0) is invalid"),
    (dict(dahl=((0.0, 0.1),)), "dahl = (0.0, 0.1) is invalid: valid range pairs (F_h > 0 N, x_h > 0 mm), finite"),
    (dict(dahl=((5.0,),)), "dahl = (5.0,) is invalid"),
    (dict(coulomb_N=-0.5), "coulomb_N = -0.5 is invalid: valid range >= 0 N (finite)"),
    (dict(coulomb_N=math.inf), "coulomb_N = inf is invalid: valid range >= 0 N (finite)"),
    (dict(coulomb_stiffness=0.0), "coulomb_stiffness = 0.0 is invalid: valid range > 0 N/mm (finite) or None"),
    (dict(coulomb_stiffness=math.inf), "coulomb_stiffness = inf is invalid"),
    (dict(loads=(LoadStep(1, math.inf, 0.0),)), "loads = LoadStep(node=1, force_N=inf, t_on=0.0) is invalid: valid "
                                                "range finite force_N [N] and t_on >= 0 s"),
    (dict(loads=(LoadStep(1, 5.0, math.inf),)), "loads = LoadStep(node=1, force_N=5.0, t_on=inf) is invalid"),
])
def test_fields_outside_their_range_are_refused_by_name(kw, message):
    """Each refusal names the field, the value and the range (10 links, 2 segments unless given).
    Bugs caught: ``n_masses < 1`` → ``< 0``, the int test dropped, ``v >= 0`` → ``v >= -1``, the finiteness tests
    dropped, ``k > 0`` → ``k >= 0``, the pair length unchecked, ``in FAR_ENDS`` negated."""
    with pytest.raises(ValueError) as exc:
        ChainLine(**(dict(n_links=10, n_masses=2) | kw))
    assert str(exc.value).startswith(message)


def test_element_fields_are_normalised_and_integer_types_accepted():
    """Lists of ints become tuples of float pairs; numpy ints count as ints; zero pretension is valid.
    Bug caught: the normalised tuples not stored back."""
    line = ChainLine(n_links=np.int64(10), n_masses=np.int32(2), hysteresis=[[2_000, 100]], dahl=[[30, 1]],
                     pretension_N=0)
    assert line.hysteresis == ((2_000.0, 100.0),) and line.dahl == ((30.0, 1.0),)
    assert all(isinstance(x, float) for x in line.hysteresis[0] + line.dahl[0])
    assert line.links_per_segment().tolist() == [5, 5]


def test_a_fixed_end_or_a_tail_mass_allows_drive_lumping_and_the_refusal_names_the_tail():
    """Drive lumping puts no mass on node N: with a tensioner far end a tail mass > 0 is required (a tiny one is
    enough), a fixed far end needs none.  Bug caught: ``tail_mass_kg <= 0`` → ``< 0``."""
    with pytest.raises(ValueError, match=r"^tail_mass_kg = 0 is invalid: valid range > 0 kg with lumping='drive'"):
        ChainLine(n_links=10, n_masses=2, lumping="drive", tail_mass_kg=0)
    assert ChainLine(n_links=10, n_masses=2, lumping="drive", tail_mass_kg=1e-9).node_masses()[-1] == 1e-9


@pytest.mark.parametrize("kw", [dict(pretension_N=np.int64(100)), dict(coulomb_N=np.int64(5)),
                                dict(pretension_N=np.float32(3.0)), dict(damping=np.float64(2.5))])
def test_numpy_numbers_are_accepted_as_the_lines_fields(kw):
    line = ChainLine(n_links=4, n_masses=2, **kw)
    (name, v), = kw.items()
    assert getattr(line, name) == float(v)


@pytest.mark.parametrize("kw", [dict(pretension_N=True), dict(damping=np.bool_(True)), dict(coulomb_N=False)])
def test_a_bool_is_refused_where_a_number_belongs(kw):
    (name, _), = kw.items()
    with pytest.raises(ValueError, match=name):
        ChainLine(n_links=4, n_masses=2, **kw)


def test_a_line_from_a_numpy_length_and_a_numpy_viscous_constant():
    # 1000 mm of 50 mm links: 20 links, by hand; a numpy constant c_e is itself at any operating point
    assert ChainLine.from_length(np.int64(1000), 2).n_links == round(1000 / default_chain().pitch)
    assert viscous_equivalent(np.float32(3.0), 10.0, 0.1, 0.0) == 3.0
    with pytest.raises(ValueError, match="law_or_ce"):
        viscous_equivalent("3", 10.0, 0.1, 0.0)
