"""The stability of a clear step on harmonic tests: friction F_c = 150 N on the paper's chain (9 simulated tests,
3 and 7 held out: 7 training tests, the damping law chosen by the diagnosis) is chosen in nearly every resample.
Draws with fewer distinct tests than the law's coefficients used to score nothing, so 'no chain' won 85 % of the
resamples of this very case (the probability of >= 6 distinct tests among 7 draws of 7 is 0.135)."""
from __future__ import annotations

import warnings

import pytest

from chainid.cli import main
from chainid.gap.diagnose import diagnose
from chainid.model import ChainModel
from chainid.records.files import read_records

pytestmark = pytest.mark.slow


def test_a_clear_friction_step_is_stable_over_resamples(tmp_path):
    csv = tmp_path / "d.csv"
    assert main(["simulate", str(csv), "--effect", "friction:F_c=150", "--noise-F", "20", "--seed", "0"]) == 0
    recs = read_records(csv)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = diagnose(recs, ["3", "7"], ChainModel(), effects=["friction"], max_combo=1, resamples=40, seed=1,
                       quiet=True)
    assert res["verdict"] == "friction"
    assert res["steps"][1]["stability"] >= 0.9, res["stability"]
