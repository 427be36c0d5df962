"""The verdict's chain is the explanation chain up to its held-out minimum: later steps are over-fitting and cut;
an earlier step that raised the held-out error alone is kept when the steps after it take the error below every
shorter chain's (the held-out data support the effects together), and a note says so."""
from __future__ import annotations

import math
from types import SimpleNamespace

from chainid.gap.core.verdict import joint_notes, overfit_warning, trusted_path


def _path(*h: float) -> list[SimpleNamespace]:
    names = ["baseline", "a", "b", "c", "d"]
    return [SimpleNamespace(nrmse_holdout=v, names=names[1:i + 1] or ["baseline"]) for i, v in enumerate(h)]


def test_a_monotone_chain_is_kept_whole():
    p = _path(0.5, 0.3, 0.2)
    ok, bad = trusted_path(p)
    assert (len(ok), bad, joint_notes(ok)) == (3, None, [])


def test_steps_after_the_held_out_minimum_are_cut():
    p = _path(0.5, 0.3, 0.35, 0.4)
    ok, bad = trusted_path(p)
    assert (len(ok), bad) == (2, 2)
    assert overfit_warning(p, bad).startswith("over-fitted: step 2 (b) raised the held-out NRMSE from 0.3 to 0.35")


def test_a_rise_recovered_below_every_shorter_chain_is_kept_with_a_note():
    p = _path(0.2421, 0.3208, 0.09289)  # a real seal set: hysteresis alone rises, with the damping law it falls
    ok, bad = trusted_path(p)
    assert (len(ok), bad) == (3, None)
    (note,) = joint_notes(ok)
    assert note.startswith("step 1 (a) alone raised the held-out NRMSE from 0.2421 to 0.3208")
    assert "reaches 0.09289" in note


def test_a_rise_not_recovered_below_the_best_shorter_chain_is_cut_at_the_best():
    p = _path(0.5, 0.3, 0.4, 0.31)  # step 3 recovers, but not below step 1
    ok, bad = trusted_path(p)
    assert (len(ok), bad) == (2, 2)


def test_equal_held_out_errors_keep_the_longer_chain():
    ok, bad = trusted_path(_path(0.5, 0.3, 0.3))
    assert (len(ok), bad) == (3, None)


def test_a_non_finite_held_out_score_cuts_at_the_first_rise():
    ok, bad = trusted_path(_path(0.5, 0.3, math.nan, 0.1))
    assert (len(ok), bad) == (2, 2)
