"""Small blind benchmark (issues 4 and 10): single, mismatch, compound, control; rates by hand from the rows."""

from __future__ import annotations

import json

from chainid.gap.benchmark.grid import canon, grid, run_benchmark


def test_small_benchmark(capsys, tmp_path):
    out = tmp_path / "b.json"
    s = run_benchmark(small=True, scheduler="processes", n_workers=2, progress=False, json_path=str(out),
                      excitations=("harmonic",))  # the non-harmonic families: tests/test_gap_benchmark_time.py
    text = capsys.readouterr().out
    assert "compound cases, both causes named" in text and "control gives none" in text
    rows = s["rows"]
    assert len(rows) == len(grid(small=True, excitations=("harmonic",))) == s["n_cases"]
    # every family is present and each rate agrees with a count from the rows
    fams = {r["family"] for r in rows}
    assert fams == {"single", "control", "mismatch", "mismatch+", "pair"}
    comp = [r for r in rows if r["family"] in ("mismatch+", "pair") and r["snr"] >= 3]
    both = sum(set(canon(r["truth"])) <= canon(r["verdict"]) for r in comp) / len(comp)
    assert s["compound_both_named_rate"] == both
    assert both >= 0.75  # 4 compound cases: at most one miss
    assert s["control_none_rate"] == 1.0
    single = [r for r in rows if r["family"] == "single" and r["snr"] >= 3]
    assert sum(canon(r["verdict"]) == canon(r["truth"]) for r in single) == len(single)
    assert s["median_shrinkage_when_right"] >= 0.7
    doc = json.loads(out.read_text())
    assert doc["n_cases"] == len(rows)


def test_canonical_names():
    assert canon("machine_compliance+friction") == {"stiffness_level", "friction"}
    assert canon("none") == set() and canon("unexplained") == set()
    assert canon(["machine_compliance"]) == {"stiffness_level"}


def test_compound_rates_by_hand():
    from chainid.gap.benchmark.report import summarise

    def row(truth, verdict, confounded=(), family="mismatch+"):
        return {"family": family, "truth": truth, "verdict": verdict, "snr": 10.0, "shrinkage": 0.9, "seconds": 1.0,
                "confounded": [list(c) for c in confounded], "chain": "c", "plan": "p", "noise": 0.01, "levels": []}

    rows = [row(["stiffness_level", "slack"], "contact_law", [("contact_law", "stiffness_level+slack")]),
            row(["stiffness_level", "friction"], "stiffness_level+friction"),
            row(["friction", "sensor_delay"], "friction", family="pair"),
            row(["machine_compliance", "backlash"], "stiffness_level+backlash+slack")]
    s = summarise(rows)
    assert s["compound_both_named_rate"] == 2 / 4  # rows 2 and 4 (machine_compliance reads as stiffness_level)
    assert s["compound_exact_rate"] == 1 / 4  # only row 2 names exactly the true pair
    assert s["compound_named_or_confounded_rate"] == 3 / 4  # row 1's verdict comes with the true pair as confound
