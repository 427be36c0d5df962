"""The leave-one-test-out jack-knife of the harmonic route (chainid.gap.harmonic.route): its SD by hand."""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from chainid.gap.harmonic.problem import Candidate
from chainid.gap.harmonic.route import jackknife as _jackknife


# ---------------------------------------------------------------- jack-knife
def test_jackknife_of_a_mean_is_the_standard_error():
    """Leave-one-out refits of a mean: the jack-knife SD sqrt((n−1)/n·Σ(θ_i − θ̄)²) equals s/sqrt(n) exactly
    (s the sample SD, ddof 1).  Bugs caught: factor (n−1)/n replaced by 1/n, n/(n−1) or dropped."""
    vals = np.array([1.0, 2.0, 4.0, 8.0, 16.0])
    tr = [SimpleNamespace(v=v) for v in vals]

    def fit(names, train_only, start, polish_only):
        return SimpleNamespace(params={"p": float(np.mean([d.v for d in train_only])), "law.0": 99.0})

    prob = SimpleNamespace(train=tr, fit=fit)
    cand = Candidate(name="x", params={"p": 0.0, "law.0": 1.0}, n_params=1)
    sd = _jackknife(prob, cand)
    assert set(sd) == {"p"}  # the damping-law coefficients are not jack-knifed
    assert sd["p"] == pytest.approx(np.std(vals, ddof=1) / math.sqrt(vals.size), rel=1e-12)


def test_jackknife_sd_by_hand():
    """Leave-one-test-out refits give 1, 2, 4: sd = sqrt((n − 1)/n · Σ(v − v̄)²) = sqrt(2/3 · 42/9); a law
    coefficient (``law.*``) is not jack-knifed."""
    from chainid.gap.harmonic.route import jackknife as _jackknife

    vals = iter([1.0, 2.0, 4.0])
    seen = []

    def fit(names, train_only, start, polish_only):  # noqa: ANN001
        seen.append(([d.test for d in train_only], polish_only, dict(start)))
        return SimpleNamespace(params={"friction.F_c": next(vals)})

    prob = SimpleNamespace(train=[SimpleNamespace(test=s) for s in "ABC"], fit=fit)
    cand = SimpleNamespace(names=["friction"], params={"friction.F_c": 2.5, "law.0": 9.0})
    sd = _jackknife(prob, cand)
    assert sd == {"friction.F_c": pytest.approx(math.sqrt(2 / 3 * 42 / 9), rel=1e-12)}
    assert [s[0] for s in seen] == [["B", "C"], ["A", "C"], ["A", "B"]] and all(s[1] for s in seen)


def test_jackknife_sd_of_an_unmoved_parameter_is_not_resolved():
    """Leave-one-out values all 1.4e-05 (or within 1e-9 of it relatively): NaN, "not resolved", not 0; a column
    that moves keeps its sd; a column all at 0 (on a bound) is NaN too."""
    from chainid.gap.core.candidate import jackknife_sd

    v = np.array([[1.4e-05, 1.0, 0.0], [1.4e-05 * (1 + 1e-12), 2.0, 0.0], [1.4e-05, 4.0, 0.0]])
    sd = jackknife_sd(v)
    assert math.isnan(sd[0]) and math.isnan(sd[2])
    assert sd[1] == pytest.approx(math.sqrt(2 / 3 * 42 / 9), rel=1e-12)
