"""A model file as chain-line fields (chainid.dynamics.segment_model.segment_kwargs): effects that add up, effects
at zero that add nothing (and no note), the stick rule against the MODIFIED link stiffness, and the operating
point of a law at a slack specimen's pretension, by hand from Eq. 15 (tests/paper_forms.py).  Units mm, N, s, kg."""
from __future__ import annotations

import pytest

import paper_forms
from chainid.dynamics.segment_model import segment_kwargs
from model_texts import SPECIMEN

CL, CH = paper_forms.coefficients()


def _effect(name, **params):
    return f'[[effects]]\nname = "{name}"\n[effects.params]\n' + "".join(f"{k} = {v!r}\n" for k, v in params.items())


def _file(tmp_path, text, base_extra=""):
    p = tmp_path / "m.toml"
    p.write_text(SPECIMEN.replace('variant = "paper"\n', 'variant = "paper"\n' + base_extra) + text)
    return p


def test_fixture_masses_and_memory_elements_add_up(tmp_path):
    """Two fixture masses 1.5 + 2 kg → drive_mass_kg 3.5 with one note each; two Bouc–Wen effects → two elements in
    file order; a hysteresis effect and a dahl damping → two Dahl elements.
    Bugs caught: ``+=`` → ``=`` (the last one only), the notes of the first lost."""
    text = (_effect("fixture_mass", m_f=1.5) + _effect("fixture_mass", m_f=2.0)
            + _effect("bouc_wen", F_y=60.0, x_y=0.02, n=2.0, r=0.5)
            + _effect("bouc_wen", F_y=30.0, x_y=0.04, n=1.0, r=1.0)
            + _effect("hysteresis", F_h=40.0, x_h=0.1) + '[damping]\nform = "dahl"\n[damping.params]\nF_h = 20.0\n'
            'x_h = 0.3\n')
    kw, notes = segment_kwargs(_file(tmp_path, text))
    assert kw["drive_mass_kg"] == 3.5
    assert kw["bouc_wen"] == ((60.0, 0.02, 2.0, 0.5), (30.0, 0.04, 1.0, 1.0))
    assert kw["dahl"] == ((40.0, 0.1), (20.0, 0.3))
    assert len(notes) == 2 and "m_f = 1.5 kg" in notes[0] and "m_f = 2 kg" in notes[1]


def test_effects_at_zero_add_nothing_and_no_note(tmp_path):
    """friction F_c = 0 (no mu), backlash b = 0, deadband k_d = 0, fixture m_f = 0: no element, no play, no dead band,
    no mass and not a single note.  Bugs caught: ``F_c <= 0`` → ``< 0`` (a (0, 0) Jenkins element), ``b > 0`` →
    ``>= 0`` (a note for no play), ``k_d > 0`` → ``>= 0`` (a dead band of zero stiffness), ``m_f > 0`` → ``>= 0``."""
    text = (_effect("friction", F_c=0.0, x_s=0.01) + _effect("backlash", b=0.0) + _effect("deadband", k_d=0.0, g=0.1)
            + _effect("fixture_mass", m_f=0.0))
    kw, notes = segment_kwargs(_file(tmp_path, text))
    assert kw["hysteresis"] == () and kw["coulomb_N"] == 0.0 and kw["backlash_mm"] == 0.0
    assert kw["deadband"] == () and kw["drive_mass_kg"] == 0.0
    assert notes == []


def test_a_friction_of_mu_alone_slips_at_mu_times_the_pretension(tmp_path):
    """friction F_c = 0, mu = 0.01, x_s = 0.01 mm at 2 kN: slip force 0.01·2000 = 20 N, stick 20/0.01 = 2000 N/mm
    (below the link's 1/CL), with the mu note; at zero pretension nothing.
    Bug caught: the mu part added after the zero test (no element)."""
    p = _file(tmp_path, _effect("friction", F_c=0.0, mu=0.01, x_s=0.01))
    kw, notes = segment_kwargs(p, pretension_N=2_000.0)
    assert kw["hysteresis"] == ((pytest.approx(2_000.0, rel=1e-12), pytest.approx(20.0, rel=1e-12)),)
    assert len(notes) == 1 and "slip force 20 N" in notes[0]
    kw, _ = segment_kwargs(p)
    assert kw["hysteresis"] == ()


def test_the_stick_rule_uses_the_modified_link_stiffness(tmp_path):
    """A stiffness_level effect of scale 2 (c_lin/2): the specimen's link stiffness is 2/CL (Eq. 15 by hand).  A
    stick of 1.5/CL (F_c = 60 N, x_s = 60·CL/1.5) is softer: a Jenkins element (1.5/CL, 60 N), no note; a stick of
    2.5/CL is stiffer: the Coulomb element, its note giving the link stiffness 2/CL to 4 digits.
    Bug caught: the rule against the file's base before the stiffness-side effects (1/CL: the first stick would be
    Coulomb)."""
    level = _effect("stiffness_level", scale=2.0)
    kw, notes = segment_kwargs(_file(tmp_path, level + _effect("friction", F_c=60.0, x_s=60.0 * CL / 1.5)))
    ((k, f),) = kw["hysteresis"]
    assert k == pytest.approx(1.5 / CL, rel=1e-9) and f == 60.0 and kw["coulomb_N"] == 0.0 and notes == []
    assert kw["ea_scale"] == 2.0
    kw, notes = segment_kwargs(_file(tmp_path, level + _effect("friction", F_c=60.0, x_s=60.0 * CL / 2.5)))
    assert kw["hysteresis"] == () and kw["coulomb_N"] == 60.0
    assert len(notes) == 1 and f"stiffer than the link ({2 / CL:.4g} N/mm)" in notes[0]


def test_a_law_is_resolved_at_the_slack_specimens_tangent(tmp_path):
    """A specimen with slack s = 0.1 mm at 2 kN: x0 = s + CL·F + CH·F^(2/3) and the tangent there is that of Eq. 15
    at F, 1/(CL + ⅔·CH·F^(−1/3)) (the slack shifts the curve, not its slope); the note names it to 6 digits.
    Bug caught: x0 without the slack (the tangent taken at a lower force)."""
    law = '[damping]\nform = "law"\nlaw = "coulomb"\ncoefficients = [50.0]\nrule = "viscous"\n'
    kw, notes = segment_kwargs(_file(tmp_path, law, "slack = 0.1\n"), pretension_N=2_000.0, omega=40.0,
                               amplitude=0.2)
    ke = 1.0 / (CL + (2.0 / 3.0) * CH * 2_000.0 ** (-1.0 / 3.0))
    assert kw["slack"] == 0.1
    assert f"k_e = {ke:.6g} N/mm" in notes[0]
