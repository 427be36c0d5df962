"""A damping that resolves to a negative dashpot is never silent: a run of it is refused (predict, the CLI; the
one rule of chainid.model.passivity), the diagnosis that finds it warns.

A viscous law is c_e ≡ α (its one coefficient), so the c the message must name is α itself; the ω it names is
the simulated 2π·f.  The records are a linear spring with a positive dashpot, built here in closed form.
"""
from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest

from chainid.gap.modelio import predict
from chainid.model.augmented import AugmentedModel
from chainid.model.base import LinearModel
from chainid.model.modelfile import save_model
from chainid.model.timedamping import Damping
from chainid.records.record import Record

K, XR, C = 250.0, 0.2, 4.0


def _records(freqs=(0.5, 1.0)) -> list[Record]:
    out = []
    rng = np.random.default_rng(3)
    for i, f in enumerate(freqs):
        t = np.arange(0.0, 12.0 / f, 1.0 / (200.0 * f))
        w = 2 * math.pi * f
        x = 2.0 + 0.5 * np.sin(w * t)
        F = K * (x - XR) + C * 0.5 * w * np.cos(w * t) + rng.normal(0.0, 0.5, t.size)
        out.append(Record(f"h{i}", t, x, F))
    return out


def _model(alpha: float) -> AugmentedModel:
    return AugmentedModel(LinearModel(K, XR), [], Damping("law", law="viscous", coefficients=[alpha]))


def test_predict_names_the_negative_viscous_c_and_where():
    with pytest.raises(ValueError) as e:
        predict(_model(-2.5), _records())
    msg = str(e.value)
    assert "h0, h1" in msg and "c = -2.5 N·s/mm" in msg and "is invalid: valid range >= 0 N·s/mm" in msg
    # the lowest c is the same at both tests (a constant law): the first is named, ω = 2π·0.5
    assert f"ω = {2 * math.pi * 0.5:.4g} rad/s" in msg and "A = 0.5 mm" in msg
    # negative at every record: no other test to run, so the message does not suggest --tests
    assert msg.startswith("the model: ") and msg.endswith("(a run with a negative dashpot is refused; diagnose again "
                                                          "with another --damping-law or fewer effects)")


@pytest.mark.parametrize("alpha", [0.0, C])
def test_a_dissipating_or_absent_dashpot_gives_no_warning(alpha):
    assert predict(_model(alpha), _records())["warnings"] == []


@pytest.mark.slow
def test_cli_refuses_with_and_without_strict(tmp_path):
    path = save_model(_model(-2.5), tmp_path / "m.toml")
    data = tmp_path / "d.csv"
    rows = ["test,t,x,F"] + [f"{r.test},{float(t)!r},{float(x)!r},{float(F)!r}" for r in _records() for t, x, F in zip(r.t, r.x, r.F)]
    data.write_text("\n".join(rows) + "\n")
    cmd = [sys.executable, "-c", "import sys; from chainid.cli import main; sys.exit(main())", "predict", str(path),
           str(data)]
    for extra in ([], ["--strict"]):
        p = subprocess.run(cmd + extra, capture_output=True, text=True, timeout=120)
        assert p.returncode == 2 and "Traceback" not in p.stderr, p.stderr
        assert p.stderr.startswith("chainid predict: error: the model: the damping gives a negative viscous c")
