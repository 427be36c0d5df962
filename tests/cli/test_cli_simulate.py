"""``chainid simulate``: the paper's default laws, a model file with its memory limit, records with an unmodelled
effect found blind by ``chainid diagnose``."""
from __future__ import annotations

import json

import numpy as np
import pytest

from chainid.cli import main
from chainid.records.files import read_records


def _sim(path, *extra):
    args = ["simulate", str(path), "--noise-F", "20", "--cycles", "6", *extra]
    assert main(args) == 0
    return {r.test: r for r in read_records(path)}


@pytest.mark.slow
def test_friction_effect_adds_coulomb_force_and_is_diagnosed(tmp_path, capsys):
    base = _sim(tmp_path / "base.csv")
    fric = _sim(tmp_path / "fric.csv", "--effect", "friction:F_c=150")
    # Same seed, same noise: the difference is the effect alone, +-F_c with the sign of the velocity.
    for tid in ("2", "3", "9"):
        b, f = base[tid], fric[tid]
        assert np.array_equal(b.t, f.t) and np.array_equal(b.x, f.x)
        v = np.gradient(b.x, b.t)
        moving = np.abs(v) > 0.2 * np.max(np.abs(v))  # away from the reversals (elastic stick)
        dF = (f.F - b.F)[moving]
        assert np.median(np.abs(dF)) == pytest.approx(150.0, rel=0.01)
        assert np.mean(np.sign(dF) == np.sign(v[moving])) > 0.99
    capsys.readouterr()
    out = tmp_path / "d.json"
    assert main(["diagnose", "--resamples", "0", str(tmp_path / "fric.csv"), "--holdout", "3,7", "--json", str(out)]) == 0
    doc = json.loads(out.read_text())
    assert doc["verdict"] == "friction"
    best = next(r for r in doc["ranking"] if r["effect"] == "friction")  # (stribeck, which nests it, may rank level)
    assert best["params"]["friction.F_c"] == pytest.approx(150.0, rel=0.05)
    assert best["shrinkage"] >= 0.7


def test_bad_effect_is_a_clear_error(tmp_path, capsys):
    assert main(["simulate", str(tmp_path / "a.csv"), "--effect", "frict:F_c=1"]) == 2
    assert "unknown" in capsys.readouterr().err
    assert main(["simulate", str(tmp_path / "b.csv"), "--effect", "friction:F_c=-1"]) == 2
    err = capsys.readouterr().err
    assert "F_c" in err and "-1" in err and ">= 0" in err
    assert not (tmp_path / "a.csv").exists() and not (tmp_path / "b.csv").exists()


def test_cli_simulate_from_a_model_file(tmp_path, capsys):
    """simulate --model M.toml (a linear base, no effects) writes the paper's plan within the default memory limit
    (1 GiB) and names 'no effects'.  Bugs caught: the model-file option not registered, GiB mis-scaled (1024-3
    bytes), the 'no effects' fallback lost."""
    from chainid.model.augmented import AugmentedModel
    from chainid.model.modelfile import save_model
    from chainid.model.timedamping import Damping

    mf = tmp_path / "m.toml"
    save_model(AugmentedModel(LinearModel_(), [], Damping("viscous", {"c": 1.0}), 0.0, 0.0), mf)
    out = tmp_path / "r.csv"
    assert main(["simulate", str(out), "--model", str(mf), "--cycles", "3", "--samples-per-cycle", "32"]) == 0
    text = capsys.readouterr().out
    assert "no effects" in text and out.is_file()


def LinearModel_():
    from chainid.model.base import LinearModel

    return LinearModel(1e4, 0.0)


def test_simulate_default_laws_are_the_papers_eq28_and_eq27(tmp_path, capsys):
    """``chainid simulate`` without --params: the viscous law's c = 2834.4 N·s/mm (Eq. 27, test 3; the option's
    help) and the polynomial law's α = Eq. 28 as printed in the paper, (28.02, −651.57, −8386.50, 7394.84, 4378.89),
    whose c_e at each test of the paper plan the table states (Eq. 21 by hand with ω the plan's rad/s)."""
    from chainid.cli import main
    from chainid.records.simulate import paper_plan

    eq28 = (28.02, -651.57, -8386.50, 7394.84, 4378.89)
    assert main(["simulate", str(tmp_path / "v.csv"), "--cycles", "3"]) == 0
    assert "(law viscous [2834.4]," in capsys.readouterr().out
    assert main(["simulate", str(tmp_path / "p.csv"), "--law", "polynomial", "--cycles", "3"]) == 0
    out = capsys.readouterr().out
    assert f"(law polynomial {list(eq28)}," in out
    rows = [ln.split() for ln in out.splitlines()[2:11]]
    for s, row in zip(paper_plan(), rows):
        c = eq28[0] * s.omega ** 2 + eq28[1] * s.omega + eq28[2] * s.A ** 2 + eq28[3] * s.A + eq28[4]
        assert row[0] == s.test and float(row[4]) == pytest.approx(c, rel=1e-4)  # printed to 5 digits


class _Reached(Exception):
    """Raised by a stand-in once the command has handed over its arguments."""


def test_simulate_model_file_hands_max_memory_in_bytes(tmp_path, monkeypatch):
    """``simulate --model M.toml --max-memory 0.5``: the limit reaches ``simulate_model`` as 0.5·2^30 bytes
    (GiB, the option's unit).  Bug caught: 1024³ → 1023³ on the model-file path."""
    import chainid.records.simulate as sim
    from chainid.model.augmented import AugmentedModel
    from chainid.model.base import LinearModel
    from chainid.model.modelfile import save_model
    from chainid.model.timedamping import Damping

    mf = tmp_path / "m.toml"
    save_model(AugmentedModel(LinearModel(1e4, 0.0), [], Damping("viscous", {"c": 1.0}), 0.0, 0.0), mf)
    seen = {}

    def stand_in(plan, model, **kw):  # noqa: ANN001
        seen.update(kw)
        raise _Reached

    monkeypatch.setattr(sim, "simulate_model", stand_in)
    with pytest.raises(_Reached):
        main(["simulate", str(tmp_path / "r.csv"), "--model", str(mf), "--max-memory", "0.5"])
    assert seen["max_memory"] == 0.5 * 2**30
