"""``chainid identify`` judges the chain's load limits on the largest force of all its records (never a smaller
record's): one test of a set loaded to about 1.3·10⁵ N, the others near 11 kN, gives the working-load warning,
on stderr and in the JSON.  The limit is that of the built-in 14×50 DIN 22252 grade C chain by hand: half the
proof force, 640 N/mm² on two legs of π·14²/4 mm² = 98 520 N.
"""
from __future__ import annotations

import json
import math

import pytest

from chainid.cli import main
from chainid.model.base import ChainModel
from chainid.records.files import write_records
from chainid.records.simulate import TestSpec, paper_plan, simulate

WORK_N = 640.0 * 2 * math.pi * 14.0**2 / 4 / 2


@pytest.mark.parametrize("big_first", [True, False])
def test_the_largest_record_force_is_judged(tmp_path, capsys, big_first):
    plan = list(paper_plan())
    big = TestSpec("big", 20.0, 14.0, 0.5)  # x0 = 14 mm: F about 1.3e5 N
    plan = [big] + plan if big_first else plan + [big]
    recs = simulate(plan, ChainModel(), 2834.4, n_cycles=4, samples_per_cycle=64)
    F_max = max(float(r.F.max()) for r in recs)
    assert F_max > WORK_N > max(float(r.F.max()) for r in recs if r.test != "big")
    p = tmp_path / "d.csv"
    write_records(p, recs)
    main(["identify", str(p), "--quiet", "--json", "-"])
    cap = capsys.readouterr()
    doc = json.loads(cap.out)
    want = f"F_max = {F_max:.6g} N exceeds the working load (half the proof force) {WORK_N:.4g} N"
    assert any(w.startswith(want) for w in doc.get("warnings", [])), (want, doc.get("warnings"))
    assert f"chainid identify: warning: {want}" in cap.err
