"""The two shared raw sets (../shared/realdata, or $CHAINID_SHARED/realdata; skipped when absent) read by the
README's one command each with the example reader profiles, checked against this file's own parse of the raw text
(plain Python: split lines and fields, the physics of SOURCE.md): the number of tests, their ids, the covariates
and every sample of t, x, F."""
from __future__ import annotations

import csv
import math
import os
import re
import shlex
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]
_ROOT = Path(os.environ["CHAINID_SHARED"]) if os.environ.get("CHAINID_SHARED") else REPO.parent / "shared"
REAL = _ROOT / "realdata"
pytestmark = pytest.mark.skipif(not (REAL / "mr-damper").is_dir() or not (REAL / "pneumatic-seal").is_dir(),
                                reason="shared real data not present")


def _readme_commands() -> list[str]:
    text = (REPO / "README.md").read_text(encoding="utf-8")
    start = text.index("## Rig files as they really are")
    sec = text[start:text.index("\n## ", start + 1)]
    blocks = re.findall(r"```\n(.*?)```", sec, flags=re.S)
    return [ln for b in blocks for ln in b.splitlines() if ln.startswith("chainid ")]


def _run_readme(kind: str, tmp_path: Path) -> tuple[Path, Path]:
    from chainid.cli import main

    (cmd,) = [c for c in _readme_commands() if kind in c]
    argv = shlex.split(cmd)[1:]
    argv = [a.replace("../shared/realdata", str(REAL)) for a in argv]
    argv = [str(REPO / a) if a.startswith("examples/") else a for a in argv]
    k = argv.index("--to")
    argv[k + 1] = str(tmp_path / argv[k + 1])
    assert main(argv) == 0
    out = Path(argv[k + 1])
    return out, out.with_name(out.stem + ".covariates.csv")


def _read_csv(path: Path) -> dict[str, dict[str, list[float]]]:
    out: dict[str, dict[str, list[float]]] = {}
    with path.open(newline="") as fh:
        for row in csv.DictReader(fh):
            d = out.setdefault(row["test"], {"t": [], "x": [], "F": []})
            for c in ("t", "x", "F"):
                d[c].append(float(row[c]))
    return out


def _read_cov(path: Path) -> dict[str, dict[str, float]]:
    out: dict[str, dict[str, float]] = {}
    with path.open(newline="") as fh:
        for row in csv.DictReader(fh):
            out.setdefault(row["test"], {})[row["name"]] = float(row["value"])
    return out


def test_the_pneumatic_seal_command_against_a_hand_parse(tmp_path):
    out, cov = _run_readme("pneumatic-seal", tmp_path)
    got, covs = _read_csv(out), _read_cov(cov)
    files = sorted((REAL / "pneumatic-seal").glob("*.csv"))
    assert list(got) == [f.stem for f in files] and len(files) == 12
    for f in files:
        rows = [[float(v) for v in ln.split()] for ln in f.read_text().splitlines() if ln.strip()]
        bore = 25.0 if f.name.startswith("NAP310") else 25.7
        area = math.pi * (bore / 2) ** 2  # mm^2; p [bar] * 0.1 = N/mm^2
        g = got[f.stem]
        assert len(g["t"]) == len(rows)
        np.testing.assert_allclose(g["t"], [r[0] / 1000.0 for r in rows], rtol=1e-12, atol=0)
        np.testing.assert_array_equal(g["x"], [r[4] for r in rows])
        np.testing.assert_allclose(g["F"], [r[6] - r[5] * 0.1 * area for r in rows], rtol=0, atol=1e-6)
        set_p = float(f.stem.rsplit("_", 1)[1].removesuffix("bar"))
        assert covs[f.stem]["p_bar"] == set_p
        assert covs[f.stem]["p_mean_bar"] == pytest.approx(sum(r[5] for r in rows) / len(rows), rel=1e-12)
        assert abs(covs[f.stem]["p_mean_bar"] - set_p) < 0.05 * set_p  # the rig held its set pressure


def _hand_mr(path: Path) -> list[tuple[str, dict[str, list[float]], float]]:
    """Segments of one DAQ file: (test id, t x F, current), by the SOURCE.md rules."""
    lines = path.read_text().splitlines()
    interval = float(lines[2].split(":")[1])
    assert lines[6].startswith("Sample Number")
    rows = [[c.strip() for c in ln.split(",")] for ln in lines[7:] if ln.strip()]
    segs, cur = [], []
    for r in rows:
        cur.append(r)
        if len(r) == 5 and r[4] == "DAQ Pause":
            segs.append(cur)
            cur = []
    assert not cur and len(segs) == 5
    x_col = 2 if interval == 0.001 else 3  # 1 ms files: CHANNEL0 is the displacement
    out = []
    for seg, amps in zip(segs, ("0", "0.25", "0.5", "0.75", "1")):
        v = [float(r[x_col]) for r in seg]
        rest = sum(v[:100]) / 100
        first = int(seg[0][0])
        out.append((f"{path.stem}_i{amps}", {"t": [(int(r[0]) - first) * interval for r in seg],
                                             "x": [10.0 * (a - rest) for a in v],
                                             "F": [980.665 * float(r[5 - x_col]) for r in seg]}, float(amps)))
    return out


def test_the_mr_damper_command_against_a_hand_parse(tmp_path):
    out, cov = _run_readme("mr-damper", tmp_path)
    got, covs = _read_csv(out), _read_cov(cov)
    files = sorted((REAL / "mr-damper").glob("*.txt"))
    want = [seg for f in files for seg in _hand_mr(f)]
    assert list(got) == [w[0] for w in want] and len(want) == 15
    for test, ref, amps in want:
        g = got[test]
        assert len(g["t"]) == len(ref["t"])
        np.testing.assert_allclose(g["t"], ref["t"], rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(g["x"], ref["x"], rtol=0, atol=1e-9)
        np.testing.assert_allclose(g["F"], ref["F"], rtol=1e-12, atol=0)
        assert covs[test] == {"I_A": amps}
    peak = {t: max(abs(v) for v in got[t]["F"]) for t in got}  # the force rises with the current (SOURCE.md)
    for f in files:
        p = [peak[f"{f.stem}_i{a}"] for a in ("0", "0.25", "0.5", "0.75", "1")]
        assert p == sorted(p), (f.name, p)
