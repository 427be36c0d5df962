"""The user guide's 'Your own data' (docs/guide/reading-records.md): the three layouts built here, the documented
command lines run as written."""
from __future__ import annotations

import json
import math
import re
import shlex
from pathlib import Path

import numpy as np
import pytest

from chainid.records import read_records
from chainid.records.record import Record
from repo_paths import REPO

GUIDE = REPO / "docs" / "guide" / "reading-records.md"
KIP_N = 4448.2216152605
FS = 10240.0
C_E = 5.0  # N.s/mm, viscous damping of the MTS fixtures


def _section() -> str:
    text = GUIDE.read_text(encoding="utf-8")
    start = text.index("## Your own data")
    return text[start:text.index("\n## ", start + 1)]


def _blocks(sec: str) -> list[str]:
    return re.findall(r"```\n(.*?)```", sec, flags=re.S)


def _ref(test: str, f: float) -> Record:
    t = np.arange(2048) / FS
    x = 1.9 + 0.3 * np.sin(2 * math.pi * f * t)
    return Record(test, t, x, 11117.0 + 7000.0 * (x - 1.9))


def _chain_ref(test: str, f: float) -> Record:
    """A chain test (DIN 22252 14x50 near Eq. 26's F0): x0 = 1.906 mm, A = 0.3 mm at f Hz for 2 s,
    F = F_k(x) + c_e x' + m x'' (Eq. 1, viscous)."""
    from chainid.chain.spec import load_chain
    from chainid.model import kernels

    chain = load_chain("din22252:14x50")  # the guide's --chain

    t = np.arange(int(2.0 * FS)) / FS
    w = 2 * math.pi * f
    x = 1.906 + 0.3 * np.sin(w * t)
    m = chain.mass_kg
    F = (np.asarray(kernels.force(x, chain, "paper"), dtype=float) + C_E * 0.3 * w * np.cos(w * t)
         - m * 0.3 * w * w * np.sin(w * t) * 1e-3)
    return Record(test, t, x, F)


def _check(out: Path, refs: list[Record]) -> None:
    recs = read_records(out, validate=False)
    assert [r.test for r in recs] == [r.test for r in refs]
    for r, e in zip(recs, refs):
        np.testing.assert_allclose(r.t, e.t, rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(r.x, e.x, rtol=1e-12)
        np.testing.assert_allclose(r.F, e.F, rtol=1e-12)


@pytest.mark.slow
def test_readme_layouts_and_commands(tmp_path, monkeypatch, capsys):
    from chainid.cli import main

    sec = _section()
    cmds = [ln for b in _blocks(sec) for ln in b.splitlines() if ln.startswith("chainid ")]
    assert len(cmds) == 4 and sum(c.startswith("chainid convert") for c in cmds) == 3, cmds
    profile = next(b for b in _blocks(sec) if b.startswith("skip_rows"))
    monkeypatch.chdir(tmp_path)
    # 1. JSON in inches and kips, one file per test
    (tmp_path / "brfd").mkdir()
    brfd = [_ref("0.5Hz_1in", 0.5 * 20), _ref("1Hz_1in", 20.0)]
    for r in brfd:
        (tmp_path / "brfd" / f"{r.test}.json").write_text(json.dumps(
            {"time": r.t.tolist(), "disp": (r.x / 25.4).tolist(), "force": (r.F / KIP_N).tolist()}))
    # 2. headerless TSV force, displacement at 10 240 Hz
    (tmp_path / "wri").mkdir()
    wri = [_ref("07", 12.0), _ref("08", 15.0)]
    for r in wri:
        np.savetxt(tmp_path / "wri" / f"run_{r.test}.tsv", np.column_stack([r.F, r.x]), delimiter="\t", fmt="%.17g")
    # 3. MTS exports with the guide's header block: six chain tests (a damping law needs six)
    (tmp_path / "mts").mkdir()
    mts = [_chain_ref(f"specimen{k}", f) for k, f in enumerate((4.0, 5.0, 6.0, 7.0, 8.0, 9.0), start=1)]
    head = ["MTS TestSuite export", "Station: Frame 1", "Specimen: 3", "Rate: 10240 Hz", "",
            "Time (ms);Axial Displacement;Axial Force"]
    for r in mts:
        rows = [";".join(repr(float(v)).replace(".", ",") for v in (a * 1000, -b, c))
                for a, b, c in zip(r.t, r.x, r.F)]
        (tmp_path / "mts" / f"{r.test}.csv").write_text("\n".join(head + rows) + "\n")
    (tmp_path / "mts.toml").write_text(profile)
    for cmd in cmds:
        argv = shlex.split(cmd)[1:]
        assert main(argv) == 0, (cmd, capsys.readouterr().err)
        if argv[0] == "identify":
            out = capsys.readouterr().out
            assert all(r.test in out for r in mts)
            # the same with --json: c_e of every test is the 5 N.s/mm it was built with (ms -> s, x sign flipped)
            assert main(argv + ["--json", "id.json", "--quiet"]) == 0
            doc = json.loads((tmp_path / "id.json").read_text())
            assert sorted(t["test"] for t in doc["tests"]) == [r.test for r in mts]
            for t in doc["tests"]:
                assert t["c_e"] == pytest.approx(C_E, rel=0.02), t
    _check(tmp_path / "brfd.csv", brfd)
    _check(tmp_path / "wri.csv", wri)
    _check(tmp_path / "mts.csv", mts)
