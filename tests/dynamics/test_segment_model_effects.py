"""A diagnosed model file's effects as the segments of a chain line (``dynamics --segment-model``), by hand.

Each library effect of a model file becomes the line's field stated in chainid.dynamics.segment_model's table:
numbers typed from the file (the stiffness-side effects composed on the base kernel, the link stiffness 1/c_lin of
Eq. 15 by hand in tests/paper_forms.py), the covariate terms resolved by p + slope·(cov − ref), the feature damping
c + b_w·(ω − w_ref) + b_A·(A − A_ref); the refusals and notes named.  And the CLI end to end: a model file with
``hysteresis+backlash`` and a delay written by save_model runs (rc 0) with a note for the delay.
Units mm, N, s, kg.
"""
import json
import math

import numpy as np
import pytest

import paper_forms
from chainid.cli import main
from chainid.dynamics.segment_model import segment_kwargs
from chainid.model import ChainModel
from chainid.model.augmented import AugmentedModel
from chainid.model.modelfile import save_model
from chainid.model.timedamping import Damping
from model_texts import SPECIMEN

CL, CH = paper_forms.coefficients()


def _file(tmp_path, text, name="m.toml"):
    p = tmp_path / name
    p.write_text(SPECIMEN.replace('variant = "paper"\n', 'variant = "paper"\nea_scale = 1.25\n') + text)
    return p


def _effect(name, **params):
    return f'[[effects]]\nname = "{name}"\n[effects.params]\n' + "".join(f"{k} = {v!r}\n" for k, v in params.items())


def test_stiffness_side_effects_compose_on_the_base_kernel(tmp_path):
    """Base ea_scale 1.25 × stiffness_level 2 = 2.5; contact_law scale 0.8, beta 0.9 → hertz_scale 0.8, exponent 0.9;
    slack 0.05 mm; machine_compliance 1e-6 mm/N → compliance; the friction stick rule and the Stribeck stick use the
    modified link stiffness 1/(c_lin/2.5 + 1e-6) (c_lin of Eq. 15 by hand)."""
    p = _file(tmp_path, _effect("stiffness_level", scale=2.0) + _effect("contact_law", scale=0.8, beta=0.9)
              + _effect("slack", s=0.05) + _effect("machine_compliance", c=1e-6)
              + _effect("stribeck", F_c=30.0, dF_s=20.0, v_s=2.0, dF=-5.0))
    kw, notes = segment_kwargs(p)
    assert kw["ea_scale"] == pytest.approx(2.5, rel=1e-15) and kw["hertz_scale"] == pytest.approx(0.8, rel=1e-15)
    assert kw["contact_exponent"] == 0.9 and kw["slack"] == 0.05 and kw["compliance"] == 1e-6
    assert kw["stribeck"] == ((30.0, 20.0, 2.0, -5.0),)
    assert kw["stribeck_stiffness"] == pytest.approx(1.0 / (CL / 2.5 + 1e-6), rel=1e-9)
    assert notes == []


def test_memory_and_mass_effects_map_to_the_line(tmp_path):
    """hysteresis → Dahl (F_h, x_h); bouc_wen → (F_y, x_y, n, r); backlash b → backlash_mm with a note that it is not
    passive; deadband → (k_d, g, p, x_c); fixture_mass m_f → drive_mass_kg with a note; a delay → a note; the model's
    effects at zero amplitude add nothing."""
    text = (_effect("hysteresis", F_h=90.0, x_h=0.04) + _effect("bouc_wen", F_y=60.0, x_y=0.02, n=2.5, r=0.7)
            + _effect("backlash", b=0.03) + _effect("deadband", k_d=4e3, g=0.1, p=1.5, x_c=0.6)
            + _effect("fixture_mass", m_f=2.5) + _effect("bouc_wen", F_y=0.0) + _effect("stribeck", F_c=0.0))
    p = tmp_path / "m.toml"
    p.write_text(SPECIMEN.replace("delay_s = 0.0", "delay_s = 0.004") + text)
    kw, notes = segment_kwargs(p)
    assert kw["dahl"] == ((90.0, 0.04),) and kw["bouc_wen"] == ((60.0, 0.02, 2.5, 0.7),)
    assert kw["backlash_mm"] == 0.03 and kw["deadband"] == (4e3, 0.1, 1.5, 0.6)
    assert kw["drive_mass_kg"] == 2.5 and kw["stribeck"] == () and kw["hysteresis"] == ()
    assert len(notes) == 3
    assert "b = 0.03 mm) is not passive" in notes[0]
    assert "m_f = 2.5 kg is added to the driven node 0" in notes[1]
    assert notes[2] == "the model's delay tau = 0.004 s is a measurement lag; the chain is simulated without it"


_SEG, _FILE = "--segment-model", "model file"  # who names the refusal: segment_kwargs, or the model file's schema


@pytest.mark.parametrize("text, src, words", [
    (_effect("hardening", k3=5.0), _SEG, "effect 'hardening' is not supported by dynamics segments: a chain base has "
                                         "no linear spring to harden"),
    (_effect("backlash", b=0.01) + _effect("backlash", b=0.02), _SEG, "effect 'backlash': a second backlash effect; "
                                                                      "valid: one"),
    (_effect("deadband", k_d=1.0) + _effect("deadband", k_d=2.0), _SEG, "a second deadband effect; valid: one"),
    (_effect("stribeck", F_c=10.0, dF=12.0), _SEG, "dF = 12 N is out of range: valid range |dF| <= F_c = 10 N"),
    # a parameter outside its physical range is refused by the model file's schema when the file is read (the
    # same error in every command; ranges of docs/reference/contracts.md: friction F_c >= 0 and <= 1e9 N,
    # bouc_wen n 0.1 to 20, stiffness_level scale 1e-3 to 1e3)
    (_effect("friction", F_c=-1.0), _FILE, "effects[0].params.F_c = -1.0 is out of range: valid range >= 0 and "
                                           "<= 1e+09 N"),
    (_effect("bouc_wen", F_y=5.0, n=30.0), _FILE, "effects[0].params.n = 30.0 is out of range: valid range >= 0.1 "
                                                  "and <= 20"),
    (_effect("stiffness_level", scale=0.0), _FILE, "effects[0].params.scale = 0.0 is out of range: valid range "
                                                   ">= 0.001 and <= 1000"),
])
def test_refusals_name_the_effect_and_the_range(tmp_path, text, src, words):
    p = _file(tmp_path, text)
    with pytest.raises(ValueError) as exc:
        segment_kwargs(p)
    assert str(exc.value).startswith(f"{src} {str(p)!r}: ") and words in str(exc.value)


def test_covariate_terms_are_resolved_at_the_given_conditions(tmp_path):
    """friction.F_c@i = 40 N/A about i_ref = 1 A, hysteresis.F_h@i = −10 N/A: at i = 2.5 A, F_c = 100 + 40·1.5 =
    160 N (a Jenkins element f = 160 N, k = 160/0.02 N/mm) and F_h = 50 − 15 = 35 N; a covariate the model does not
    use is noted; a missing one is refused naming it; a term driving a parameter out of range is refused."""
    cov = '[covariates.refs]\ni = 1.0\n[covariates.terms]\n"friction.F_c@i" = 40.0\n"hysteresis.F_h@i" = -10.0\n'
    p = _file(tmp_path, _effect("friction", F_c=100.0, x_s=0.02) + _effect("hysteresis", F_h=50.0, x_h=0.05) + cov)
    kw, notes = segment_kwargs(p, covariates={"i": 2.5, "T": 20.0})
    assert kw["hysteresis"] == ((pytest.approx(160.0 / 0.02, rel=1e-12), pytest.approx(160.0, rel=1e-12)),)
    assert kw["dahl"] == ((pytest.approx(35.0, rel=1e-12), 0.05),)
    assert "covariate(s) T given but the model has no term over them" in notes[0]
    assert "covariate terms resolved at i = 2.5 (ref 1)" in notes[1]
    with pytest.raises(ValueError, match=r"the model depends on covariate\(s\) 'i' \(friction.F_c@i, "
                                         r"hysteresis.F_h@i\); give the operating condition: --segment-covariate"):
        segment_kwargs(p)
    with pytest.raises(ValueError, match=r"effect 'hysteresis': F_h = -10.0 is out of range"):
        segment_kwargs(p, covariates={"i": 7.0})  # F_h = 50 − 60
    p = _file(tmp_path, '[covariates.refs]\np = 2.0\n[covariates.terms]\n"spring.k@p" = 3.0\n', name="k.toml")
    with pytest.raises(ValueError, match=r"covariate term\(s\) spring.k@p act on a linear spring; a chain base has "
                                         "none"):
        segment_kwargs(p, covariates={"p": 1.0})


def test_covariates_given_as_numpy_numbers_are_taken_as_floats(tmp_path):
    """An operating condition from a numpy array (np.float32, np.int64, a 0-d array) resolves F_c = 100 + 40·(2 − 1)
    = 140 N as the float 2.0 does; a bool, a string, a NaN or a sequence is refused naming the covariate."""
    import numpy as np

    cov = '[covariates.refs]\ni = 1.0\n[covariates.terms]\n"friction.F_c@i" = 40.0\n'
    p = _file(tmp_path, _effect("friction", F_c=100.0, x_s=0.02) + cov)
    want = ((pytest.approx(140.0 / 0.02, rel=1e-12), pytest.approx(140.0, rel=1e-12)),)
    for v in (2.0, np.float32(2.0), np.int64(2), np.array(2.0)):
        assert segment_kwargs(p, covariates={"i": v})[0]["hysteresis"] == want, type(v)
    for v in (True, "2", float("nan"), [2.0], np.array([2.0])):
        with pytest.raises(ValueError, match=r"covariate i = .* is invalid: valid range a finite number"):
            segment_kwargs(p, covariates={"i": v})


def test_feature_damping_is_resolved_at_the_operating_point(tmp_path):
    """damping feature c = 3, b_w = 0.01, b_A = 5, w_ref = 50 rad/s, A_ref = 0.2 mm at ω = 80 rad/s, A = 0.3 mm:
    c = 3 + 0.01·30 + 5·0.1 = 3.8 N·s/mm, with a note; without the operating point it is refused naming it."""
    p = _file(tmp_path, '[damping]\nform = "feature"\n[damping.params]\nc = 3.0\nb_w = 0.01\nb_A = 5.0\n'
                        'w_ref = 50.0\nA_ref = 0.2\n')
    kw, notes = segment_kwargs(p, omega=80.0, amplitude=0.3)
    assert kw["damping"] == pytest.approx(3.8, rel=1e-12)
    assert notes[0].startswith("damping feature law resolved at omega = 80 rad/s, A = 0.3 mm")
    with pytest.raises(ValueError, match="a law over record features c\\(ω, A\\); give its operating point: "
                                         "omega = None is invalid: valid range > 0"):
        segment_kwargs(p)


def test_cli_runs_a_hysteresis_backlash_model_with_a_note_for_its_delay(tmp_path, capsys):
    """A model written by save_model (chain base, hysteresis F_h = 60 N, x_h = 0.03 mm + backlash b = 0.02 mm,
    viscous c = 3 N·s/mm, delay 2 ms) through ``chainid dynamics --segment-model``: rc 0, the delay noted (stderr
    and JSON), the line carries the Dahl element and the play, the energy balance holds."""
    m = AugmentedModel(ChainModel(), [("hysteresis", {"F_h": 60.0, "x_h": 0.03}), ("backlash", {"b": 0.02})],
                       Damping("viscous", {"c": 3.0}), delay_s=0.002)
    path = save_model(m, tmp_path / "m.toml")
    out = tmp_path / "dyn.json"
    argv = ["dynamics", "--links", "64", "--masses", "8", "--pretension", "3000", "--drive", "sine", "--amplitude",
            "0.2", "--omega", "60", "--t-end", "0.3", "--segment-model", str(path), "--quiet"]
    assert main(argv + ["--json", str(out)]) == 0
    err = capsys.readouterr().err
    assert "note: the model's delay tau = 0.002 s is a measurement lag; the chain is simulated without it" in err
    doc = json.loads(out.read_text())
    assert doc["line"]["dahl"] == [[60.0, 0.03]] and doc["line"]["backlash_mm"] == 0.02
    assert doc["line"]["damping"] == 3.0 and doc["line"]["damping_ref_links"] == 16
    assert any("measurement lag" in n for n in doc["segment_model_notes"])
    assert doc["summary"]["energy_N_mm"]["relative_error"] < 1e-3
    assert main(argv + ["--segment-covariate", "i=2"]) == 0  # a covariate the model does not use: noted
    assert "note: covariate(s) i given but the model has no term over them: not used" in capsys.readouterr().err


@pytest.mark.parametrize("extra, words", [
    (["--segment-covariate", "i"], "expected NAME=VALUE with a finite number"),
    (["--segment-covariate", "i=nan"], "expected NAME=VALUE with a finite number"),
    (["--segment-covariate", "i=1", "--segment-covariate", "i=2"], "--segment-covariate 'i' is given twice"),
])
def test_cli_segment_covariate_checks(tmp_path, capsys, extra, words):
    m = AugmentedModel(ChainModel(), [], Damping("viscous", {"c": 1.0}))
    path = save_model(m, tmp_path / "m.toml")
    argv = ["dynamics", "--links", "32", "--masses", "2", "--t-end", "0.01", "--segment-model", str(path), "--quiet"]
    with pytest.raises(SystemExit) if "finite" in words else _nothing():
        assert main(argv + extra) == 2
    assert words in capsys.readouterr().err


def test_cli_segment_covariate_needs_a_segment_model(capsys):
    assert main(["dynamics", "--links", "32", "--masses", "2", "--t-end", "0.01", "--segment-covariate", "i=1",
                 "--quiet"]) == 2
    assert "--segment-covariate needs --segment-model" in capsys.readouterr().err


class _nothing:
    def __enter__(self):
        return self

    def __exit__(self, *a):
        return False


@pytest.mark.parametrize("pretension", [0.0, 500.0, 2e4])
def test_the_operating_elongation_is_the_chains_own_at_the_pretension(pretension):
    """x0 solves F_k(x0) = pretension on the unmodified chain (brentq on the force kernel, an independent inversion
    of the displacement form the segment uses); the tangent k_e there is the kernel's stiffness.  No pretension: the
    slack (0 mm)."""
    from scipy.optimize import brentq

    from chainid.chain.spec import default_chain
    from chainid.dynamics.segment_model import _x0_ke
    from chainid.model import kernels
    from chainid.model.base import ChainModel

    base = ChainModel(default_chain())
    x0, ke = _x0_ke(base, pretension)
    want = 0.0 if pretension == 0 else brentq(lambda x: kernels.force(x, base.chain) - pretension, 1e-9, 100.0,
                                              xtol=1e-15, rtol=1e-14)
    assert x0 == pytest.approx(want, rel=1e-12, abs=1e-15)
    assert ke == pytest.approx(float(kernels.stiffness(max(want, 1e-6), base.chain)), rel=1e-9)


def _plain(tmp_path, text, name="p.toml"):
    """The 16-link specimen (no modifiers: its link stiffness is 1/CL) with ``text`` appended."""
    p = tmp_path / name
    p.write_text(SPECIMEN + text)
    return p


def test_damping_forms_take_their_own_defaults(tmp_path):
    """A ``dahl`` damping with only F_h = 20 N gets x_h = 1 mm (the damping form's default, not the effect's
    0.05 mm); a ``coulomb`` damping with only F_c = 30 N has a rigid stick (x_s = 0): the line's Coulomb element,
    with a note giving x_s = 0 mm and the link stiffness 1/CL (Eq. 15 by hand, 4 digits).
    Bugs caught: the defaults 1.0 and 0.0 changed, the note's digits."""
    kw, notes = segment_kwargs(_plain(tmp_path, '[damping]\nform = "dahl"\n[damping.params]\nF_h = 20.0\n'))
    assert kw["dahl"] == ((20.0, 1.0),) and notes == []
    kw, notes = segment_kwargs(_plain(tmp_path, '[damping]\nform = "coulomb"\n[damping.params]\nF_c = 30.0\n'))
    assert kw["coulomb_N"] == 30.0 and kw["hysteresis"] == ()
    assert notes == [f"--segment-model {str(tmp_path / 'p.toml')!r}: damping (coulomb): stick travel x_s = 0 mm is "
                     f"stiffer than the link ({1 / CL:.4g} N/mm): Coulomb friction 30 N with the link stiffness as "
                     "stick stiffness"]


def test_a_stribeck_effect_with_only_a_static_excess_or_dF_at_F_c_is_carried(tmp_path):
    """Stribeck with F_c = 0 and dF_s = 5 N (static excess only) is an element, its stick the link stiffness 1/CL
    (Eq. 15 by hand); dF = F_c = 10 N is inside |dF| <= F_c; with F_c = dF_s = 0 there is none.
    Bugs caught: ``F_c > 0 or dF_s > 0`` → ``and``, ``abs(dF) > F_c`` → ``>=``."""
    kw, _ = segment_kwargs(_plain(tmp_path, _effect("stribeck", F_c=0.0, dF_s=5.0, v_s=1.0, dF=0.0)))
    assert kw["stribeck"] == ((0.0, 5.0, 1.0, 0.0),)
    assert kw["stribeck_stiffness"] == pytest.approx(1.0 / CL, rel=1e-9)
    kw, _ = segment_kwargs(_plain(tmp_path, _effect("stribeck", F_c=10.0, dF_s=5.0, v_s=1.0, dF=10.0)))
    assert kw["stribeck"] == ((10.0, 5.0, 1.0, 10.0),)
    kw, _ = segment_kwargs(_plain(tmp_path, _effect("stribeck", F_c=0.0, dF_s=0.0, v_s=1.0, dF=0.0)))
    assert kw["stribeck"] == () and kw["stribeck_stiffness"] is None


def test_an_operating_point_and_covariates_must_be_finite_and_positive(tmp_path):
    """A law damping needs ω > 0 and A > 0: ω = 0 and A = inf are refused naming them; a covariate value must be a
    finite number (nan refused naming it).  Bugs caught: ``v > 0`` → ``v >= 0``, the finiteness tests dropped."""
    law = '[damping]\nform = "law"\nlaw = "coulomb"\ncoefficients = [50.0]\nrule = "viscous"\n'
    p = _plain(tmp_path, law)
    with pytest.raises(ValueError, match=r"give its operating point: omega = 0.0 is invalid: valid range > 0 "):
        segment_kwargs(p, omega=0.0, amplitude=0.2)
    with pytest.raises(ValueError, match=r"give its operating point: amplitude = inf is invalid: valid range > 0 "):
        segment_kwargs(p, omega=40.0, amplitude=float("inf"))
    with pytest.raises(ValueError, match=r": covariate i = nan is invalid: valid range a finite number$"):
        segment_kwargs(p, omega=40.0, amplitude=0.2, covariates={"i": float("nan")})


def test_a_law_resolved_at_the_pretension_names_its_operating_point_and_tangent(tmp_path):
    """A Coulomb-equivalent law c_e = 50·4/(π ω A) resolved (rule viscous) at ω = 40 rad/s, A = 0.2 mm with a
    2 kN pretension: the note names the point and the specimen's tangent there, k_e = 1/(CL + ⅔·CH·F^(−1/3)) at
    F = 2000 N (Eq. 15 differentiated by hand), and the viscous c it gives, 7.95775 N·s/mm.
    Bugs caught: the tangent not taken at the pretension, the note's numbers."""
    law = '[damping]\nform = "law"\nlaw = "coulomb"\ncoefficients = [50.0]\nrule = "viscous"\n'
    kw, notes = segment_kwargs(_plain(tmp_path, law), pretension_N=2000.0, omega=40.0, amplitude=0.2)
    ke = 1.0 / (CL + (2.0 / 3.0) * CH * 2000.0 ** (-1.0 / 3.0))
    c = 50.0 * 4.0 / (math.pi * 40.0 * 0.2)
    assert kw["damping"] == pytest.approx(c, rel=1e-12)
    assert notes[0].startswith(f"damping law 'coulomb' resolved by rule 'viscous' at omega = 40 rad/s, A = 0.2 mm, "
                               f"k_e = {ke:.6g} N/mm: viscous ")


def test_a_hysteretic_rule_gives_iwan_elements_and_a_note_for_its_compensating_spring(tmp_path):
    """The same law resolved by rule hysteretic: η·k = c·ω = 50·4/(π·0.2) N/mm and x_max = A = 0.2 mm, as 32 Iwan
    elements of slip force (π/2)·η·k·x_max/32 and stick travels (i − ½)·x_max/32 (by hand; each a Jenkins element
    of stiffness F_c/x_s), and a note that the rule's compensating spring k_comp is not carried.
    Bug caught: the k_comp note's condition inverted."""
    law = '[damping]\nform = "law"\nlaw = "coulomb"\ncoefficients = [50.0]\nrule = "hysteretic"\n'
    kw, notes = segment_kwargs(_plain(tmp_path, law), pretension_N=2000.0, omega=40.0, amplitude=0.2)
    eta_k = 50.0 * 4.0 / (math.pi * 0.2)
    Fc = 0.5 * math.pi * eta_k * 0.2 / 32
    xs = (np.arange(32) + 0.5) * 0.2 / 32
    np.testing.assert_allclose(np.array(kw["hysteresis"]), np.column_stack([Fc / xs, np.full(32, Fc)]), rtol=1e-9)
    assert len(notes) == 2 and notes[1].startswith("the hysteretic rule's compensating spring k_comp = ")
    assert notes[1].endswith("N/mm is not carried by dynamics segments: the Iwan elements keep their in-phase "
                             "stiffness")
