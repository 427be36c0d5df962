"""Model files (chainid.model.modelfile): round trip, refusals naming the field, infinities kept with their sign."""
from __future__ import annotations

import math

import pytest

from chainid.cli import main
from chainid.model import ChainModel
from chainid.model.augmented import AugmentedModel
from chainid.model.base import LinearModel
from chainid.model.modelfile import load_model, model_from_dict, model_to_dict, save_model
from chainid.model.timedamping import Damping


MODEL = ChainModel()


def test_model_file_round_trip_and_errors(tmp_path):
    m = AugmentedModel(MODEL, [("slack", {"s": 0.01}), ("friction", {"F_c": 10.0})],
                       Damping("law", law="viscous", coefficients=[2.0], per_test={"1": 2.5}), 0.002, 3.0)
    for name in ("m.toml", "m.json"):
        p = save_model(m, tmp_path / name)
        assert model_to_dict(load_model(p)) == model_to_dict(m)
        with pytest.raises(ValueError, match="exists"):
            save_model(m, p)
    d = model_to_dict(m)
    with pytest.raises(ValueError, match="format_version = 2"):
        model_from_dict(d | {"format_version": 2})
    with pytest.raises(ValueError, match="unknown key.*colour"):
        model_from_dict(d | {"colour": 1})
    with pytest.raises(ValueError, match="wobble"):
        model_from_dict(d | {"effects": [{"name": "wobble", "params": {}}]})
    with pytest.raises(ValueError, match="unknown parameter.*Q"):
        model_from_dict(d | {"effects": [{"name": "friction", "params": {"Q": 1.0}}]})
    with pytest.raises(ValueError, match="mass_kg"):
        model_from_dict(d | {"mass_kg": -1.0})
    bad = tmp_path / "bad.toml"
    bad.write_text("format_version = 1\n[base\n")
    with pytest.raises(ValueError, match="not valid TOML"):
        load_model(bad)
    with pytest.raises(ValueError, match="does not exist"):
        load_model(tmp_path / "none.toml")
    assert main(["predict", str(tmp_path / "none.toml"), str(bad)]) == 2


def test_model_file_keeps_infinities_with_their_sign(tmp_path):
    """±inf is written as TOML inf / -inf and parses back with its sign; a model file holding them in keys the
    schema does not know (and n_bins = 3, below its range of 8 to 4096) is refused on load, naming the keys."""
    import tomllib

    from chainid.model.modelfile import load_model, save_model, to_toml

    ev = {"upper": math.inf, "lower": -math.inf, "n_bins": 3}
    text = to_toml({"evaluation": ev})
    assert "upper = inf" in text and "lower = -inf" in text
    back = tomllib.loads(text)["evaluation"]
    assert back["upper"] == math.inf and back["lower"] == -math.inf and back["n_bins"] == 3
    p = save_model(AugmentedModel(LinearModel(100.0, 0.0), info={"evaluation": ev}), tmp_path / "m.toml")
    with pytest.raises(ValueError, match=r"unknown keys evaluation\.upper, evaluation\.lower"):
        load_model(p)


def _model_dict():
    m = AugmentedModel(LinearModel(100.0, 0.0), [], Damping("viscous", {"c": 1.0}), 0.0, 0.0)
    return model_to_dict(m)


@pytest.mark.parametrize("kind", ["a-other-model", "zz-other-model"])
def test_model_file_refuses_any_other_kind(kind):
    """kind must equal 'chainid-augmented-model' (one sorting before, one after it are both refused).
    Bug caught: the equality test made an ordering."""
    d = _model_dict()
    d["kind"] = kind
    with pytest.raises(ValueError, match="kind = "):
        model_from_dict(d)


def test_model_file_linear_base_needs_k():
    d = _model_dict()
    assert model_from_dict(d).base.k == 100.0
    del d["base"]["k"]
    with pytest.raises(ValueError, match="a linear base needs k"):
        model_from_dict(d)
