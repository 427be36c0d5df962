"""``chainid verify``: an equation agrees only when the printed form is equal to the derivation both symbolically
and numerically.  A pair equal to 1e-12 at every random point but symbolically different differs; a pair equal
symbolically but written differently agrees; a pair 1e-3 apart differs.
"""
from __future__ import annotations

import pytest

sp = pytest.importorskip("sympy")

from chainid.derive import verify  # noqa: E402
from chainid.derive.symbols import E, R, d  # noqa: E402


def test_numerically_equal_but_symbolically_different_differs():
    derived = E * d**2 / R
    printed = derived * (1 + sp.Rational(1, 10**12))  # 1e-12 relative everywhere: below the numeric tolerance
    c = verify._compare("X", derived, printed, "test pair")
    assert c.numbers["max_rel_diff_random_points"] == pytest.approx(1e-12, rel=1e-3)
    assert c.status == "differs"


def test_symbolically_equal_in_another_form_agrees():
    c = verify._compare("X", (d + R) ** 2 * E, E * d**2 + 2 * E * d * R + E * R**2, "test pair")
    assert c.status == "agrees" and c.numbers["max_rel_diff_random_points"] < 1e-14


def test_numerically_different_differs():
    c = verify._compare("X", E * d**2 / R, E * d**2 / R * sp.Rational(1001, 1000), "test pair")
    assert c.status == "differs"
    assert c.numbers["max_rel_diff_random_points"] == pytest.approx(1e-3 / 1.001, rel=1e-6)
