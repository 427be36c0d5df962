"""A warning the library issues while a command runs (not one the command adds to its document itself) reaches
the JSON ``warnings`` as well as stderr: the one rule of :mod:`chainid.infra.runlog` (``write_json`` merges the
run's warnings into every document it writes).

The probe is a model file whose mass and delay are implausible but valid, 2·10⁵ kg and 2 s (the model-file schema
warns above 10⁵ kg and outside ±1 s, docs/reference/contracts.md); ``predict`` loads it and its result document
names neither itself.
"""
from __future__ import annotations

import json
import re

import pytest

from chainid.chain.spec import PAPER_CHAIN
from chainid.cli import main
from chainid.model.augmented import AugmentedModel
from chainid.model.base import ChainModel
from chainid.model.modelfile import save_model
from chainid.model.timedamping import Damping
from chainid.records.files import write_records
from chainid.records.simulate import paper_plan, simulate


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("run")
    recs = simulate(paper_plan(), ChainModel(), 2834.4, n_cycles=4, samples_per_cycle=64)[:2]
    data = tmp / "d.csv"
    write_records(data, recs)
    model = save_model(AugmentedModel(ChainModel(PAPER_CHAIN), [], Damping("viscous", {"c": 2.0})), tmp / "m.toml")
    text = model.read_text()
    assert text.count("\nmass_kg = ") == 1 and text.count("\ndelay_s = ") == 1
    heavy = tmp / "heavy.toml"
    text = re.sub(r"\nmass_kg = [^\n]*", "\nmass_kg = 200000.0", text)
    heavy.write_text(re.sub(r"\ndelay_s = [^\n]*", "\ndelay_s = 2.0", text))
    return str(data), str(heavy)


@pytest.mark.parametrize("want", ["mass_kg = 200000.0 kg is implausible (plausible: <= 100000 kg); it is used as given",
                                  "delay_s = 2.0 s is implausible (plausible: -1 to 1 s); it is used as given"])
def test_model_file_warnings_of_predict_are_in_its_json(files, capsys, want):
    data, heavy = files
    assert main(["predict", heavy, data, "--json", "-"]) == 0
    cap = capsys.readouterr()
    head = "chainid predict: warning: "
    printed = [ln[len(head):] for ln in cap.err.splitlines() if ln.startswith(head) and want in ln]
    assert len(printed) == 1, cap.err
    doc = json.loads(cap.out)
    assert [w for w in doc["warnings"] if want in w] == printed
