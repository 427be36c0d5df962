"""The diagnosis' final model saved to a model file and read back (:func:`chainid.model.modelfile.save_model`,
``load_model``) predicts the held-out record (:func:`chainid.gap.modelio.predict`) with the NRMSE the diagnosis
reports for it (``tests[].nrmse_after``; its baseline: ``nrmse_before``), to 1e-6 relative — on a linear base with
per-test offsets and a covariate term (friction following a coil current), and on the chain (a fixture mass),
time route and harmonic route; data simulated independently (:mod:`recovery_cases`).
"""
from __future__ import annotations

import pytest

import recovery_cases as rc
from chainid.gap.modelio import predict
from chainid.model.modelfile import load_model, save_model

pytestmark = pytest.mark.slow


def _chain_sines():
    from chainid.model import ChainModel

    m = ChainModel()
    pairs = ((2.0, 0.3), (5.0, 0.2), (10.0, 0.3), (10.0, 0.15), (20.0, 0.2), (20.0, 0.1))

    def force(mo, t, f, A):
        x, xd, xdd = mo(t)
        return m.force(x) + (m.mass_kg + 20.0) * xdd * 1e-3 + rc.C_CHAIN * xd

    return rc.harmonic_set(force, pairs=pairs, x0=rc.X0_CHAIN, sigma_x=rc.SX_CHAIN, sigma_F=rc.SF_CHAIN), ["h3"], m


CASES = [("covariate", rc.covariate_set, "friction"),
         ("rand_fixture_mass", rc.fixture_mass_set, "fixture_mass"),
         ("harm_fixture_mass", _chain_sines, "fixture_mass")]


@pytest.mark.parametrize("suffix", [".toml", ".json"])
@pytest.mark.parametrize("key,build,effect", CASES, ids=[c[0] for c in CASES])
def test_saved_model_predicts_the_held_out_record_as_diagnosed(key, build, effect, suffix, tmp_path):
    res, recs, _ = rc.diagnosed(key, build)
    assert res["verdict"] == effect, res["chain_text"]
    hold = res["holdout"]
    assert len(hold) == 1
    reported = next(t for t in res["tests"] if t["test"] == hold[0])
    path = save_model(res["_models"][-1], tmp_path / f"final{suffix}")
    model = load_model(path)
    if key == "covariate":
        assert model.offsets and model.covariate_terms, "offsets and a covariate term go into the file"
    out = predict(model, [r for r in recs if r.test == hold[0]])
    row = out["tests"][0]
    assert row["nrmse_model"] == pytest.approx(reported["nrmse_after"], rel=1e-6), (row, reported)
    assert row["nrmse_baseline"] == pytest.approx(reported["nrmse_before"], rel=1e-6), (row, reported)
