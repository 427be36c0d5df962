"""The damping law choice (chainid.gap.harmonic.law_choice): leave-one-out errors against brute-force refits, ties."""
from __future__ import annotations

import numpy as np
import pytest

from chainid.gap.harmonic import law_choice


def test_fit_loo_against_brute_force_refits():
    """Leave-one-out predictions by the leverage formula equal the refits without each test (another method)."""
    rng = np.random.default_rng(8)
    X = np.column_stack([np.ones(9), rng.uniform(1, 4, 9), rng.uniform(0.1, 0.5, 9)])
    c = X @ [1.0, 2.0, 3.0] + 0.1 * rng.normal(size=9)
    p, loo = law_choice.fit_loo(X, c)
    np.testing.assert_allclose(p, np.linalg.lstsq(X, c, rcond=None)[0], rtol=1e-12)
    for i in range(9):
        keep = np.arange(9) != i
        pi = np.linalg.lstsq(X[keep], c[keep], rcond=None)[0]
        assert loo[i] == pytest.approx(X[i] @ pi, rel=1e-9)
    assert law_choice.allowed(4) == [k for k in law_choice.allowed(99) if k != "polynomial"]
    assert law_choice.allowed(2) == ["viscous", "coulomb", "hysteretic"]  # 1 coefficient <= 2 − 1


def test_law_choice_leave_one_out_errors_and_ties_by_hand():
    """c_e = 0.5 + noise-free scatter d_i: the viscous law's LOO prediction of test i is the mean of the others,
    so its error is n/(n − 1)·(c_i − c̄) and its LOO RMS n/(n − 1)·std(c).  A Coulomb-exact set
    c = 4·F_f/(π·ω·A) is fitted with zero error by coulomb and by viscous+coulomb: the tie goes to the law with
    fewer coefficients."""
    from chainid.gap.harmonic.law_choice import choose

    w = np.array([1.0, 2.0, 4.0, 1.0, 2.0, 4.0, 3.0])
    A = np.array([0.1, 0.1, 0.1, 0.3, 0.3, 0.3, 0.2])
    ke = np.full(7, 5000.0)
    c = 0.5 + np.array([0.01, -0.02, 0.03, 0.0, -0.01, 0.02, -0.03])
    best, errs = choose(w, A, ke, c, ["viscous"])
    assert best == "viscous" and errs["viscous"] == pytest.approx(7 / 6 * np.std(c), rel=1e-9)
    cc = 4 * 20.0 / (np.pi * w * A)
    best, errs = choose(w, A, ke, cc, ["viscous+coulomb", "viscous", "coulomb", "hysteretic"])
    assert best == "coulomb" and errs["coulomb"] < 1e-9 and errs["viscous+coulomb"] < 1e-9
    assert errs["viscous"] > 10 and errs["hysteretic"] > 1  # c spans 21 … 255 N·s/mm
    ch = 0.02 * ke / w  # structural, eta = 0.02
    assert choose(w, A, ke, ch, ["viscous", "coulomb", "hysteretic", "viscous+hysteretic"])[0] == "hysteretic"
    with pytest.raises(ValueError, match="no damping law has fewer coefficients than the training tests"):
        choose(w, A, ke, c, [])
