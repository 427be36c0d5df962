"""One rule for records no analysis can work on: a force that does not vary (F ≡ 0: a dead force channel) or a
displacement that does not vary (x ≡ const: no motion; a damping "fitted" to it is F/0) is the same one-line
error in identify, audit --data, diagnose and predict (rc 2), naming the test, the column and the value."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.chain.spec import PAPER_CHAIN
from chainid.cli import main
from chainid.model.augmented import AugmentedModel
from chainid.model.base import ChainModel
from chainid.model.modelfile import save_model
from chainid.model.timedamping import Damping
from chainid.records.files import write_records
from chainid.records.record import Record


def _records(dead: str) -> list[Record]:
    out = []
    for i, w in enumerate((2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0), 1):
        t = np.arange(0.0, 8 * 2 * math.pi / w, 2 * math.pi / w / 64)
        x = 2.2 + 0.25 * np.sin(w * t)
        F = 11000.0 + 2000.0 * np.sin(w * t) + 300.0 * np.cos(w * t)
        if dead == "F":
            F = np.zeros_like(t)
        else:
            x = np.full_like(t, 2.2)
        out.append(Record(str(i), t, x, F))
    return out


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("dead")
    paths = {}
    for dead in ("F", "x"):
        paths[dead] = tmp / f"dead_{dead}.csv"
        write_records(paths[dead], _records(dead))
    paths["model"] = save_model(AugmentedModel(ChainModel(PAPER_CHAIN), [], Damping("viscous", {"c": 2.0})),
                                tmp / "m.toml")
    return {k: str(v) for k, v in paths.items()}


EXPECTED = {
    "F": "test '1': the force F is constant (0 N in all {n} samples): a dead channel, nothing to diagnose; valid "
         "records have a varying F",
    "x": "test '1': the displacement x is constant (2.2 mm in all {n} samples): no motion, nothing to identify (a "
         "dead displacement channel); valid records have a varying x",
}


@pytest.mark.parametrize("dead", ["F", "x"])
@pytest.mark.parametrize("command", ["identify", "audit", "diagnose", "predict"])
def test_a_dead_channel_is_the_same_error_everywhere(command, dead, files, capsys):
    data = files[dead]
    argv = {"identify": ["identify", data, "--quiet"], "audit": ["audit", "--data", data],
            "diagnose": ["diagnose", "--resamples", "0", data, "--holdout", "7"], "predict": ["predict", files["model"], data]}[command]
    assert main(argv) == 2
    err = [ln for ln in capsys.readouterr().err.splitlines() if ln.strip()]
    n = _records(dead)[0].t.size
    assert err == [f"chainid {command}: error: " + EXPECTED[dead].format(n=n)]
