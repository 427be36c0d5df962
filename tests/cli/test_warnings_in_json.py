"""Every warning a command prints on stderr is in its JSON ``warnings`` too (plausibility warnings of the records,
load limits, the model file), for every command that writes JSON; printed once, as ``chainid CMD: warning: ...``.

The records are simulated tests whose time column is multiplied by 1000 (t in ms read as s): the plausibility
check names their implausibly slow main frequency.
"""
from __future__ import annotations

import json

import pytest

from chainid.chain.spec import PAPER_CHAIN
from chainid.cli import main
from chainid.infra import runlog
from chainid.model.augmented import AugmentedModel
from chainid.model.base import ChainModel
from chainid.model.modelfile import save_model
from chainid.model.timedamping import Damping
from chainid.records.files import write_records
from chainid.records.record import Record
from chainid.records.simulate import paper_plan, simulate


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("w")
    recs = simulate(paper_plan(), ChainModel(), 2834.4, n_cycles=4, samples_per_cycle=64)
    slow = tmp / "slow.csv"
    write_records(slow, [Record(r.test, r.t * 1000.0, r.x, r.F) for r in recs])
    model = save_model(AugmentedModel(ChainModel(PAPER_CHAIN), [], Damping("viscous", {"c": 2.0})), tmp / "m.toml")
    return str(slow), str(model)


COMMANDS = {
    "identify": lambda d, m: ["identify", d, "--quiet"],
    "audit": lambda d, m: ["audit", "--data", d],
    "diagnose": lambda d, m: ["diagnose", "--resamples", "0", d, "--holdout", "9", "--max-combo", "1"],
    "predict": lambda d, m: ["predict", m, d],
    "stiffness": lambda d, m: ["stiffness", "--F", "150000"],
    "dynamics": lambda d, m: ["dynamics", "--links", "100", "--masses", "10", "--t-end", "0.05", "--pretension",
                              "150000"],
}


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_every_printed_warning_is_in_the_json(command, files, capsys):
    argv = COMMANDS[command](*files) + ["--json", "-"]
    assert main(argv) == 0
    cap = capsys.readouterr()
    head = f"chainid {command}: warning: "
    printed = [ln[len(head):] for ln in cap.err.splitlines() if ln.startswith(head)]
    assert printed, cap.err  # the probe does warn
    assert len(printed) == len(set(printed))  # each once
    assert not [ln for ln in cap.err.splitlines() if "Warning:" in ln]  # no Python-style warning lines
    doc = json.loads(cap.out)
    missing = [w for w in printed if w not in doc["warnings"]]
    assert not missing, missing
    if command in ("identify", "audit", "diagnose", "predict"):
        assert any("implausibly slow" in w for w in printed)


def test_the_merge_keeps_the_document_and_adds_only_new_messages(capsys):
    with runlog.collecting("x"):
        runlog.warn("one")
        runlog.warn("two")
        runlog.warn("one")  # printed once
        doc = runlog.merge_warnings({"a": 1, "warnings": ["two", "zero"]})
    assert doc == {"a": 1, "warnings": ["two", "zero", "one"]}
    assert capsys.readouterr().err.splitlines() == ["chainid x: warning: one", "chainid x: warning: two"]
    assert runlog.merge_warnings({"a": 1}) == {"a": 1}  # outside a run: unchanged


def test_python_warnings_of_a_run_are_collected(capsys):
    import warnings

    with runlog.collecting("y") as got:
        warnings.warn("from the library", UserWarning)
        warnings.warn("from the library", UserWarning)
    assert got == ["from the library"]
    assert capsys.readouterr().err == "chainid y: warning: from the library\n"
