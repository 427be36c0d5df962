"""``predict --plots``: test ids that a file name cannot hold as they are ("T 1", "T/1") get portable names with a
hash of the id, so ids that sanitise alike ("T 1", "T_1", "T/1") give three figures, none over another.  The
expected names are computed here: ``predict_`` + the id with every character outside A-Z a-z 0-9 _ . - replaced
by ``_`` + (if that changed it) ``-`` and the first 8 hex digits of SHA-256 of the id + ``.png``."""
from __future__ import annotations

import hashlib
import math

import numpy as np

from chainid.chain.spec import PAPER_CHAIN
from chainid.cli import main
from chainid.model.augmented import AugmentedModel
from chainid.model.base import ChainModel
from chainid.model.modelfile import save_model
from chainid.model.timedamping import Damping
from chainid.records.files import write_records
from chainid.records.record import Record

IDS = ["T 1", "T_1", "T/1"]


def _name(test: str) -> str:
    slug = "".join(c if c.isalnum() and c.isascii() or c in "_.-" else "_" for c in test)
    if slug != test:
        slug += "-" + hashlib.sha256(test.encode()).hexdigest()[:8]
    return f"predict_{slug}.png"


def test_ids_that_sanitise_alike_get_distinct_figures(tmp_path, capsys):
    recs = []
    for i, test in enumerate(IDS):
        w = 2.0 + i
        t = np.arange(0.0, 8 * 2 * math.pi / w, 2 * math.pi / w / 64)
        x = 2.2 + 0.25 * np.sin(w * t)
        recs.append(Record(test, t, x, 11000.0 + 2000.0 * np.sin(w * t) + 300.0 * np.cos(w * t)))
    data = tmp_path / "d.csv"
    write_records(data, recs)
    model = save_model(AugmentedModel(ChainModel(PAPER_CHAIN), [], Damping("viscous", {"c": 2.0})), tmp_path / "m.toml")
    plots = tmp_path / "plots"
    assert main(["predict", str(model), str(data), "--plots", str(plots)]) == 0
    expected = sorted(_name(t) for t in IDS)
    assert len(set(expected)) == 3 and "predict_T_1.png" in expected
    assert sorted(p.name for p in plots.iterdir()) == expected
    # a second run without --force is refused before any work, naming an existing figure
    capsys.readouterr()
    assert main(["predict", str(model), str(data), "--plots", str(plots)]) == 2
    assert "already exists" in capsys.readouterr().err
