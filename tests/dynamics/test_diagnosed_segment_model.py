"""A diagnosed model in a chain drive, end to end: diagnose --save-model → dynamics --segment-model."""
import json

import pytest

from chainid.cli import main
from chainid.gap.benchmark.grid import grid3x3_plan
from chainid.model import ChainModel, PolynomialLaw, parse_effect
from chainid.records import write_records
from chainid.records.simulate import simulate


@pytest.mark.slow
def test_diagnosed_friction_model_drives_the_segments(tmp_path, capsys):
    model = ChainModel()
    recs = simulate(grid3x3_plan(prefix=""), model, PolynomialLaw([0.5, 1.0, 100.0, 20.0, 50.0]), n_cycles=8,
                    samples_per_cycle=128, noise_F=20.0, seed=1, force_fn=parse_effect("friction:F_c=150", model))
    data, m, out = tmp_path / "d.csv", tmp_path / "m.toml", tmp_path / "dyn.json"
    write_records(data, recs)
    assert main(["diagnose", "--resamples", "0", str(data), "--holdout", "3,7,11", "--max-combo", "1", "--save-model", str(m)]) == 0
    capsys.readouterr()
    w, A = 10.0, 0.2
    assert main(["dynamics", "--links", "400", "--masses", "25", "--pretension", "2000", "--drive", "polygon",
                 "--teeth", "10", "--speed", "1000", "--t-ramp", "0.5", "--t-end", "1", "--segment-model", str(m),
                 "--segment-omega", str(w), "--segment-amplitude", str(A), "--quiet", "--json", str(out)]) == 0
    assert "resolved by rule 'viscous'" in capsys.readouterr().err
    doc = json.loads(out.read_text())
    import tomllib
    saved = tomllib.loads(m.read_text())
    a = saved["damping"]["coefficients"]  # Eq. 21 by hand: α1ω² + α2ω + α3A² + α4A + α5 (16-link specimen)
    assert doc["line"]["damping"] == pytest.approx(a[0] * w * w + a[1] * w + a[2] * A * A + a[3] * A + a[4], rel=1e-12)
    fr = saved["effects"][0]["params"]
    assert doc["line"]["coulomb_N"] == pytest.approx(fr["F_c"] + fr["mu"] * 2000.0, rel=1e-12)
    assert abs(doc["line"]["coulomb_N"] - 150.0) < 10.0  # the simulated friction, found by the diagnosis
    eb = doc["summary"]["energy_N_mm"]
    assert eb["relative_error"] < 1e-3 and eb["dissipated"] > 0
