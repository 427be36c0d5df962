"""A model file as segment elements (chainid.dynamics.segment_model): effects and time-domain damping forms by hand."""
from __future__ import annotations

import pytest

from model_texts import SPECIMEN


def _segment_model(tmp_path, text, name="m.toml"):
    from chainid.dynamics.segment_model import segment_kwargs

    p = tmp_path / name
    p.write_text(SPECIMEN + text)
    return p, segment_kwargs


def test_segment_model_effects_and_time_domain_forms_by_hand(tmp_path):
    """A model file's effects and damping forms as segment elements (the module's table), by hand:
    friction F_c = 100 N, x_s = 0.05 mm, mu = 0.01 at 2000 N pretension → a Jenkins element of slip force
    100 + 0.01·2000 = 120 N and stiffness 120/0.05 = 2400 N/mm (below the 16-link specimen's link stiffness
    1/c_lin, Eq. 15 typed in tests/paper_forms.py), with a note; a hysteresis effect → a Dahl element (F_h, x_h),
    x_h 0.05 mm by default, none for F_h = 0; damping dahl (F_h, x_h), viscous c, none; a stick stiffer than the
    link → the Coulomb element with a note; a second such stick is refused; an unsupported effect or a negative c
    is refused naming it.
    Bugs caught: mu·pretension dropped, the stiffness bound inverted, defaults changed, branches swapped."""
    import paper_forms

    k_link = 1.0 / paper_forms.coefficients()[0]
    assert 2400.0 < k_link
    fr = '[[effects]]\nname = "friction"\n[effects.params]\nF_c = {F_c}\nx_s = {x_s}\nmu = {mu}\n'
    dahl = '[[effects]]\nname = "hysteresis"\n[effects.params]\nF_h = {F_h}\n'
    p, seg = _segment_model(tmp_path, fr.format(F_c=100.0, x_s=0.05, mu=0.01) + dahl.format(F_h=30.0) + dahl.format(F_h=0.0)
                            + '[damping]\nform = "dahl"\n[damping.params]\nF_h = 20.0\nx_h = 0.5\n')
    kw, notes = seg(p, pretension_N=2000.0)
    assert kw["hysteresis"] == ((2400.0, 120.0),) and kw["dahl"] == ((30.0, 0.05), (20.0, 0.5))
    assert kw["coulomb_N"] == 0.0 and kw["damping"] == 0.0 and kw["damping_ref_links"] == 16
    assert len(notes) == 1 and "mu = 0.01" in notes[0] and "slip force 120 N" in notes[0]
    p, seg = _segment_model(tmp_path, fr.format(F_c=50.0, x_s=50.0 / k_link * 1.001, mu=0.0)
                            + '[damping]\nform = "viscous"\n[damping.params]\nc = 7.5\n')
    kw, notes = seg(p)
    (k, f), = kw["hysteresis"]  # just below the link stiffness: a Jenkins element
    assert k == pytest.approx(k_link / 1.001, rel=1e-9) and f == 50.0 and kw["coulomb_N"] == 0.0
    assert kw["damping"] == 7.5 and notes == []
    p, seg = _segment_model(tmp_path, fr.format(F_c=50.0, x_s=50.0 / k_link * 0.999, mu=0.0)
                            + '[damping]\nform = "none"\n')
    kw, notes = seg(p)
    assert kw["hysteresis"] == () and kw["coulomb_N"] == 50.0 and kw["damping"] == 0.0
    assert len(notes) == 1 and "stiffer than the link" in notes[0] and "Coulomb friction 50 N" in notes[0]
    p, seg = _segment_model(tmp_path, fr.format(F_c=50.0, x_s=0.0, mu=0.0)
                            + '[damping]\nform = "coulomb"\n[damping.params]\nF_c = 20.0\nx_s = 0.0\n')
    with pytest.raises(ValueError, match="a second Coulomb element with a \\(near-\\)rigid stick; valid: one"):
        seg(p)
    p, seg = _segment_model(tmp_path, '[[effects]]\nname = "hardening"\n[effects.params]\nk3 = 2.0\n'
                            '[damping]\nform = "none"\n')
    with pytest.raises(ValueError, match="effect 'hardening' is not supported by dynamics segments: a chain base has "
                                         "no linear spring to harden"):
        seg(p)
    p, seg = _segment_model(tmp_path, '[damping]\nform = "viscous"\n[damping.params]\nc = -1.0\n')
    with pytest.raises(ValueError, match=r"c = -1 N·s/mm is invalid: valid range >= 0"):
        seg(p)
