"""Why a set of records takes the time-domain route, said once on stderr by ``diagnose`` (chainid.gap.diagnose):
held-out blocks asked for, or operating conditions that differ; a set of steady sines at one condition says nothing
and takes the phase-bin route.  (A record that is not a sine: tests/gap/harmonic/test_not_a_sine.py.)"""
from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from chainid.gap.diagnose import diagnose
from chainid.records.record import Record

T = np.arange(4000) / 400.0  # 10 cycles of 1 Hz, 400 samples each


def _sines(covariates=None) -> list[Record]:
    """Four sine tests of a linear spring F = 50 + 100·x N with 0.5 N of noise, amplitudes 1, 2, 1.5, 2.5 mm."""
    rng = np.random.default_rng(8)
    recs = []
    for i, amp in enumerate((1.0, 2.0, 1.5, 2.5)):
        x = 3.0 + amp * np.sin(2 * math.pi * T)
        recs.append(Record(f"r{i}", T, x, 50.0 + 100.0 * x + 0.5 * rng.normal(size=T.size),
                           covariates=(covariates or [{}] * 4)[i]))
    return recs


def _said(capsys, recs, **kw) -> tuple[dict, list[str]]:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = diagnose(recs, kw.pop("holdout", ["r1"]), None, effects=["friction"], max_combo=1, uncertainty=False,
                       **kw)
    return res, [ln for ln in capsys.readouterr().err.splitlines() if "every record takes" in ln]


@pytest.mark.parametrize("kw, reason", [
    ({"holdout_blocks": 4, "holdout": []}, "--holdout-blocks 4"),
    ({"covariates": [{"I": 0.0}, {"I": 0.5}, {"I": 1.0}, {"I": 0.5}]},
     "the records' operating conditions (covariates) differ"),
])
def test_the_time_route_says_why_once(capsys, kw, reason):
    kw = dict(kw)
    recs = _sines(kw.pop("covariates", None))
    res, said = _said(capsys, recs, **kw)
    assert res["route"] == "time"
    assert said == [f"chainid diagnose: every record takes the time-domain route: {reason}"]


def test_steady_sines_at_one_condition_take_the_phase_bin_route_silently(capsys):
    res, said = _said(capsys, _sines())
    assert res["route"] == "harmonic" and said == []
