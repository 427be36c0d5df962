"""``chainid simulate --effect``: records with an unmodelled effect, found blind by ``chainid diagnose``."""

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
    assert main(["diagnose", str(tmp_path / "fric.csv"), "--holdout", "3,7", "--json", str(out)]) == 0
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
