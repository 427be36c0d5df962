"""The diagnosis on real devices nobody here built ($CHAINID_SHARED/realdata or ../shared/realdata; skipped when
absent; origins and licences in each folder's SOURCE.md), read from the raw rig files with the example readers and
diagnosed on the linear device base with the operating condition as a covariate.

The references are physical, not the code's output:

* a pneumatic seal's friction is the lip's contact pressure times a friction coefficient, so its amplitude grows
  with the supply pressure and stays positive down to the lowest pressure tested (SOURCE.md: the friction force of
  the seal under pressure);
* an MR damper's yield force grows with the coil current (the field-dependent yield stress of the fluid) and the
  device is a hysteretic damper: the force loops are rate-independent at the yield plateau.

Both sets must come out named (not ``unexplained``) by a single effect of the whole library (``--max-combo 1``
keeps the tests short; ``python benchmarks/real_devices.py`` runs the full chains), closing at least half of the
held-out gap, with what is left stated against the noise floor.
"""
from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from chainid.cli import main

REPO = Path(__file__).resolve().parents[2]
SHARED = Path(os.environ["CHAINID_SHARED"]) if os.environ.get("CHAINID_SHARED") else REPO.parent / "shared"
REAL = SHARED / "realdata"
pytestmark = [pytest.mark.slow,
              pytest.mark.skipif(not (REAL / "pneumatic-seal").is_dir() or not (REAL / "mr-damper").is_dir(),
                                 reason="shared real data not present")]
FRICTION_FAMILY = {"friction", "hysteresis", "bouc_wen", "stribeck"}


def _convert(kind: str, pattern: str, out: Path) -> Path:
    csv = out / f"{kind}.csv"
    assert main(["convert", str(REAL / pattern), "--reader", str(REPO / "examples" / "readers" / f"{kind}.toml"),
                 "--to", str(csv)]) == 0
    return csv


def _diagnose(csv: Path, cov: Path, tests: str, holdout: str, out: Path) -> dict:
    js = out / f"{csv.stem}_{tests.strip('*')}.json"
    assert main(["diagnose", str(csv), "--covariates", str(cov), "--tests", tests, "--model", "linear",
                 "--holdout", holdout, "--resamples", "0", "--max-combo", "1", "--json", str(js)]) == 0
    return json.loads(js.read_text())


@pytest.fixture(scope="module")
def seal(tmp_path_factory) -> dict:
    out = tmp_path_factory.mktemp("seal")
    csv = _convert("pneumatic_seal", "pneumatic-seal/*.csv", out)
    return _diagnose(csv, csv.with_name(csv.stem + ".covariates.csv"), "NAP310*", "NAP310_5bar", out)


@pytest.fixture(scope="module")
def mr(tmp_path_factory) -> dict:
    out = tmp_path_factory.mktemp("mr")
    csv = _convert("mr_damper", "mr-damper/*.txt", out)
    return _diagnose(csv, csv.with_name(csv.stem + ".covariates.csv"), "ME10mm2Hz*", "ME10mm2Hz_i0.5", out)


def _amplitude_law(res: dict, cov: str) -> dict:
    laws = [c for c in res["covariate_dependence"] if c["covariate"] == cov]
    assert laws, res["covariate_dependence"]
    return laws[0]


def test_a_pneumatic_seal_is_named_friction_growing_with_pressure(seal):
    steps = seal["verdict"].split("+")
    assert set(steps) <= FRICTION_FAMILY, seal["verdict"]
    assert seal["left_nrmse_holdout"] <= 0.5 * seal["baseline"]["nrmse_holdout"]
    law = _amplitude_law(seal, "p_bar")
    assert law["slope"] > 0  # N per bar
    assert law["value_at_ref"] + law["slope"] * (1.0 - law["ref"]) > 0  # still a friction force at 1 bar
    assert seal["residual"]["db_over_noise"] > 0  # what is left is stated, above the floor on a real rig


def test_an_mr_damper_is_named_hysteretic_with_yield_growing_with_current(mr):
    assert mr["verdict"] != "unexplained", mr["warnings"]
    assert set(mr["verdict"].split("+")) & FRICTION_FAMILY, mr["verdict"]
    assert mr["left_nrmse_holdout"] <= 0.5 * mr["baseline"]["nrmse_holdout"]
    law = _amplitude_law(mr, "I_A")
    assert law["slope"] > 0  # N per A


def test_every_real_verdict_states_the_fit_left_and_the_model_free_share(seal, mr):
    for res in (seal, mr):
        assert res["fit_holdout_pct"] == pytest.approx(100 * (1 - res["left_nrmse_holdout"]), abs=1e-9)
        share = res["open_world"]["predictable_share"]
        assert share is None or -1.0 <= share <= 1.0
