"""Small blind benchmark (issue 4)."""

from __future__ import annotations

from chainid.gap.benchmark import run_benchmark


def test_small_benchmark(capsys):
    s = run_benchmark(small=True, processes=2)
    out = capsys.readouterr().out
    assert "confusion matrix" in out
    assert s["control_none_rate"] == 1.0
    assert s["right_rate_snr3"] >= 0.9
    assert s["median_shrinkage_when_right"] >= 0.7
    # the out-of-library drift is never given a library name
    assert set(s["drift_verdicts"]) <= {"none", "unexplained"}
