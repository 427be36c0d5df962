"""Textbook spectral forms typed from their standard statements, for the tests of the excitation generators."""
from __future__ import annotations

import numpy as np


def kt_cp_displacement(f, f_g=2.0, zeta_g=0.5, f_c=0.2):
    """Displacement amplitude of the textbook Kanai–Tajimi ground acceleration filtered by the Clough–Penzien
    high-pass (ζ_c = 0.7): sqrt(|H_KT|²·|H_CP|²)/ω², typed from the standard forms."""
    w, wg, wc = 2 * np.pi * f, 2 * np.pi * f_g, 2 * np.pi * f_c
    hkt = (wg**4 + 4 * zeta_g**2 * wg**2 * w**2) / ((wg**2 - w**2) ** 2 + 4 * zeta_g**2 * wg**2 * w**2)
    hcp = w**4 / ((wc**2 - w**2) ** 2 + 4 * 0.7**2 * wc**2 * w**2)
    return np.sqrt(hkt * hcp) / w**2
