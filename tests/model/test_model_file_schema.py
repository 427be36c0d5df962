"""The model file's typed schema, checked on every load: each probe of a hand-edited file (a wrong type, a value
outside its physical range, an unknown key, a deep nesting) is one error naming the key path, the value and the
valid range; a valid but implausible value is a warning naming the key.  The expected paths and ranges are
written here from the schema's table (chainid/model/ranges.py docstring): F_c >= 0 N and <= 1e9 N, mass 0 to
1e9 kg, delay -10 to 10 s, n_bins a whole number 8 to 4096, ...
"""
from __future__ import annotations

import copy
import math
import warnings

import pytest

from chainid.chain.spec import PAPER_CHAIN
from chainid.model.augmented import NOT_FORCE, AugmentedModel
from chainid.model.base import ChainModel, LinearModel
from chainid.model.effects import DEFAULTS, EFFECT_NAMES, make_effect
from chainid.model.modelfile import load_model, model_from_dict, model_to_dict, save_model
from chainid.model.ranges import DAMPING_RANGES, EFFECT_RANGES, MODIFIER_OF
from chainid.model.schema import ModelFileWarning
from chainid.model.timedamping import FORMS, Damping


def _model() -> AugmentedModel:
    m = AugmentedModel(ChainModel(PAPER_CHAIN), [("friction", {"F_c": 150.0, "x_s": 0.01}),
                                                 ("hysteresis", {"F_h": 50.0})],
                       Damping("law", law="viscous", coefficients=[3.0], per_test={"a": 3.1}), 0.001, 3.2)
    m.baseline = AugmentedModel(ChainModel(PAPER_CHAIN), [], Damping("viscous", {"c": 2.0}))
    m.info = {"evaluation": {"n_bins": 64, "allow_compression": True, "steady_tol": 0.05},
              "provenance": {"command": "chainid diagnose d.csv"}}
    return m


GOOD = model_to_dict(_model())


def _load(edit) -> tuple[AugmentedModel, list[str]]:
    d = copy.deepcopy(GOOD)
    edit(d)
    with warnings.catch_warnings(record=True) as got:
        warnings.simplefilter("always")
        m = model_from_dict(d, "M")
    return m, [str(w.message) for w in got if issubclass(w.category, ModelFileWarning)]


# -- one table of effect ranges ----------------------------------------------------------------------------

@pytest.mark.parametrize("name", EFFECT_NAMES)
def test_every_effect_parameter_has_a_range(name):
    """Fails when an effect of the library gets a parameter that the ranges table does not cover."""
    params = set(make_effect(name).param_names) | set(DEFAULTS[name])
    if name == "damping_law":  # its time-domain form has its own parameters (slopes over record features)
        from chainid.model.effects.library import TIME_DAMPING_LAW

        params |= {p.name for p in TIME_DAMPING_LAW.params}
    assert params == set(EFFECT_RANGES[name]), (name, params, set(EFFECT_RANGES.get(name, {})))


def test_every_damping_parameter_and_kernel_modifier_has_a_range():
    for form, params in FORMS.items():
        assert set(params) <= set(DAMPING_RANGES.get(form, {})), form
    for mod, (eff, p) in MODIFIER_OF.items():
        assert p in EFFECT_RANGES[eff] and hasattr(ChainModel(PAPER_CHAIN), mod)


# -- errors: path, value, valid range ----------------------------------------------------------------------

def _set(*path, value):
    def edit(d):
        node = d
        for k in path[:-1]:
            node = node[k]
        node[path[-1]] = value
    return edit


PROBES = [
    # (edit, expected text in the error)
    (_set("mass_kg", value=[1, 2]), "mass_kg = [1, 2] is invalid (an array): valid values are numbers, >= 0 and "
                                    "<= 1e+09 kg"),
    (_set("effects", value=3), "effects = 3 is invalid (a number): valid values are an array of tables"),
    (_set("base", value=1), "base = 1 is invalid (a number): valid values are a table"),
    (_set("damping", value=1), "damping = 1 is invalid (a number): valid values are a table"),
    (_set("effects", 0, "params", "F_c", value=[1.0]), "effects[0].params.F_c = [1.0] is invalid (an array)"),
    (_set("evaluation", "steady_tol", value="0.1"), "evaluation.steady_tol = '0.1' is invalid (a string): valid "
                                                     "values are numbers, > 0 and < 1"),
    (_set("effects", 0, "params", "F_c", value=-150.0), "effects[0].params.F_c = -150.0 is out of range: valid "
                                                         "range >= 0 and <= 1e+09 N"),
    (_set("effects", 0, "params", "F_c", value=1e12), "effects[0].params.F_c = 1000000000000.0 is out of range"),
    (_set("effects", 0, "params", "x_s", value=-0.1), "effects[0].params.x_s = -0.1 is out of range: valid range "
                                                       ">= 0 and <= 10000 mm"),
    (_set("effects", 1, "params", "x_h", value=0.0), "effects[1].params.x_h = 0.0 is out of range: valid range > 0"),
    (_set("mass_kg", value=1e300), "mass_kg = 1e+300 is out of range: valid range >= 0 and <= 1e+09 kg"),
    (_set("damping", "coefficients", value=[1e300]), "damping.coefficients[0] = 1e+300 is out of range"),
    (_set("damping", "coefficients", value=[1.0, 2.0]), "damping.coefficients has 2 number(s): valid: 1 for law "
                                                        "'viscous'"),
    (_set("delay_s", value=1e9), "delay_s = 1000000000.0 is out of range: valid range >= -10 and <= 10 s"),
    (_set("delay_s", value=True), "delay_s = True is invalid (true/false)"),
    (_set("evaluation", "n_bins", value=0), "evaluation.n_bins = 0 is out of range: valid range a whole number >= 8 "
                                            "and <= 4096"),
    (_set("evaluation", "n_bins", value=-5), "evaluation.n_bins = -5 is out of range"),
    (_set("evaluation", "n_bins", value=1e9), "evaluation.n_bins = 1000000000.0 is out of range"),
    (_set("evaluation", "n_bins", value=64.5), "evaluation.n_bins = 64.5 is out of range: valid range a whole number"),
    (_set("evaluation", "allow_compression", value="no"), "evaluation.allow_compression = 'no' is invalid (a "
                                                          "string): valid values are true or false"),
    (_set("damping", "k_e", value=math.nan), "damping.k_e = nan is out of range"),  # unused by a viscous law
    (_set("damping", "per_test", "a", value=math.nan), "damping.per_test.a = nan is out of range"),
    (_set("baseline", "damping", "params", "c", value=math.inf), "baseline.damping.params.c = inf is out of range"),
    (_set("baseline", "mass_kg", value=-1.0), "baseline.mass_kg = -1.0 is out of range"),
    (_set("base", "hertz_scale", value=0.0), "base.hertz_scale = 0.0 is out of range: valid range >= 0.001 and "
                                             "<= 1000"),
    (_set("base", "chain", value=1), "base.chain = 1 is invalid (a number)"),
    (_set("base", "chain", "d", value="14"), "base.chain: ChainSpec.d = '14' is invalid"),
    (_set("base", "variant", value=7), "base.variant = 7 is invalid (a number)"),
    (_set("mass", value=3.0), "unknown key mass (format_version 1)"),
    (_set("effects", 0, "params", "F_C", value=3.0), "unknown parameter effects[0].params.F_C of effect 'friction'; "
                                                     "valid parameters: F_c, mu, x_s"),
    (_set("damping", "colour", value=1), "unknown key damping.colour"),
    (_set("format_version", value=2), "format_version = 2 is not supported (written by a newer chainid"),
    (_set("format_version", value="1"), "format_version = '1' is invalid (a string)"),
    (_set("format_version", value=True), "format_version = True is invalid (true/false)"),
    (_set("effects", 0, "name", value="sensor_delay"), "effects[0].name = 'sensor_delay' is invalid"),
    (_set("units", "length", value="m"), "units.length = 'm' is invalid: valid values are mm"),
    (_set("provenance", "data_sha256", value="abc"), "provenance.data_sha256 = 'abc' is invalid"),
    (_set("provenance", "command", value=5), "provenance.command = 5 is invalid (a number)"),
    (_set("base", value={"model": "linear"}), "base.k is missing"),
    (_set("base", value={"model": "linear", "k": 100.0, "mass": math.nan}), "base.mass = nan is out of range"),
]


@pytest.mark.parametrize("edit, text", PROBES, ids=[p[1][:40] for p in PROBES])
def test_a_bad_key_is_one_error_naming_path_value_and_range(edit, text):
    with pytest.raises(ValueError) as e:
        _load(edit)
    assert str(e.value).startswith("M: ") and text in str(e.value), str(e.value)


def test_a_chain_only_effect_on_a_linear_base_is_refused():
    def edit(d):
        d["base"] = {"model": "linear", "k": 100.0}
        d["effects"] = [{"name": "contact_law", "params": {}}]
    with pytest.raises(ValueError, match=r"^M: effects: effect 'contact_law' needs a chain base"):
        _load(edit)


# -- warnings: valid but implausible ------------------------------------------------------------------------

@pytest.mark.parametrize("edit, path", [
    (_set("effects", 0, "params", "F_c", value=5e7), "effects[0].params.F_c = 50000000.0 N is implausible "
                                                     "(plausible: <= 1e+07 N)"),
    (_set("mass_kg", value=2e5), "mass_kg = 200000.0 kg is implausible (plausible: <= 100000 kg)"),
    (_set("delay_s", value=2.0), "delay_s = 2.0 s is implausible (plausible: -1 to 1 s)"),
])
def test_an_implausible_value_loads_with_a_warning_naming_it(edit, path):
    m, got = _load(edit)
    assert got == [f"M: {path}; it is used as given"]
    assert m.info["warnings"] == got


def test_the_written_model_loads_back_without_a_warning(tmp_path):
    p = save_model(_model(), tmp_path / "m.toml")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # any warning fails
        m = load_model(p)
    assert m.effects[0] == ("friction", {"F_c": 150.0, "mu": 0.0, "x_s": 0.01})
    assert m.mass == 3.2 and m.delay_s == 0.001 and m.damping.coefficients == [3.0]


@pytest.mark.parametrize("suffix, text", [(".json", "[" * 100000 + "]" * 100000),
                                          (".toml", "a = " + "[" * 100000 + "]" * 100000)])
def test_a_deep_nesting_is_one_error(tmp_path, suffix, text):
    p = tmp_path / f"deep{suffix}"
    p.write_text(text)
    with pytest.raises(ValueError, match="is nested too deeply to be a chainid model file"):
        load_model(p)


def test_the_augmented_model_checks_the_same_table():
    with pytest.raises(ValueError, match=r"effect 'friction': F_c = -150.0 is out of range: valid range >= 0"):
        AugmentedModel(LinearModel(100.0, 0.0), [("friction", {"F_c": -150.0})])
    with pytest.raises(ValueError, match=r"delay_s = 1000000000.0 is out of range"):
        AugmentedModel(LinearModel(100.0, 0.0), [], delay_s=1e9)
    assert {n for n in EFFECT_NAMES if n not in NOT_FORCE} <= set(EFFECT_RANGES)


def test_the_readme_states_the_ranges_table():
    from pathlib import Path

    from chainid.model.ranges import range_table

    readme = (Path(__file__).resolve().parents[2] / "README.md").read_text(encoding="utf-8")
    assert range_table() in readme
