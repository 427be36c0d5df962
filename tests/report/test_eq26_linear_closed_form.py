"""The Eq. 26 reading of the paper's record (chainid.report.eq26.eq26_analysis) on a linear spring, where every
number has a closed form: F = F0 + F_A sin(ψ + φ) against F_k = k(x − x_ref) + m·ẍ·1e-3, x = x0 + A sin ψ.
Units mm, N, s, kg."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.damping import audit
from chainid.report.eq26 import eq26_analysis

K, X_REF, M = 20_000.0, 1.0, 3.2


class Linear:
    name, mass_kg = "linear", M

    def force(self, x):
        return K * (np.asarray(x, float) - X_REF)

    def stiffness(self, x):
        return np.full(np.shape(x), K)


def test_the_eq26_numbers_of_a_linear_spring_are_their_closed_forms():
    """By hand, with the paper's F0, F_A, φ (Eq. 26) and x0, A, ω (Eq. 27): the model's first-harmonic stiffness is
    k; the record's in-phase stiffness F_A cos φ/A over the dynamic k − mω²·1e-3; the damping the record implies
    F_A sin φ/(ωA); the residual F − F_k − m·ẍ·1e-3 has mean F0 − k(x0 − x_ref), sin ψ part F_A cos φ − kA +
    mω²A·1e-3, cos ψ part F_A sin φ, and no higher harmonics."""
    E26, E27 = audit.EQ26, audit.EQ27
    x0, A, w = E27["x0"], E27["A"], E27["omega"]
    F0, FA, phi = E26["F0"], E26["FA"], E26["phi"]
    d = eq26_analysis(Linear())
    k_in = FA * math.cos(phi) / A
    assert d["in_phase"]["k_model_first_harmonic_N_per_mm"] == pytest.approx(K, rel=1e-12)
    assert d["in_phase"]["k_e_range_N_per_mm"] == pytest.approx([K, K], rel=1e-12)
    assert d["in_phase"]["ratio_in_phase_over_model_dynamic"] == pytest.approx(k_in / (K - M * w * w * 1e-3),
                                                                               rel=1e-12)
    assert d["quadrature"]["c_e_implied_by_record_N_s_per_mm"] == pytest.approx(FA * math.sin(phi) / (w * A),
                                                                                 rel=1e-12)
    h = d["residual_harmonics"]
    assert h["mean"] == pytest.approx(F0 - K * (x0 - X_REF), rel=1e-12)
    assert h["h1_x"] == pytest.approx(FA * math.cos(phi) - K * A + M * w * w * A * 1e-3, rel=1e-10)
    assert h["h1_xdot"] == pytest.approx(FA * math.sin(phi), rel=1e-10)
    assert max(h["h2"], h["h3"], h["h4"], h["h5"]) < 1e-9 * h["h1"]


def test_residual_panel_labels_give_its_harmonics_in_kN(tmp_path, monkeypatch):
    """The residual panel's legend reads the harmonics in kN to one decimal: 2449 N in phase with x is "+2.4 kN"
    (a value where dividing by anything but 1000 shows), −14 471.66 N in phase with ẋ "−14.5 kN"."""
    import matplotlib.figure

    from chainid.report.eq26 import plot_eq26

    d = eq26_analysis(Linear())
    d["residual_harmonics"] = dict(d["residual_harmonics"], h1_x=2449.0, h1_xdot=-14471.66)
    seen = []
    monkeypatch.setattr(matplotlib.figure.Figure, "savefig",
                        lambda fig, *a, **k: seen.extend(t.get_text() for ax in fig.axes if ax.get_legend()
                                                         for t in ax.get_legend().get_texts()))
    plot_eq26(tmp_path / "eq26.png", Linear(), d)
    assert "in phase with x: +2.4 kN (stiffness)" in seen
    assert "in phase with ẋ: -14.5 kN (damping)" in seen
