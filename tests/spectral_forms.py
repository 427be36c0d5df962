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


def earthquake_band_ratio(fs: float, T: float, seeds, f_hi: float, num: tuple[float, float],
                          den: tuple[float, float]) -> float:
    """The displacement power of ``chainid.records.excitation.earthquake`` in band ``num`` [Hz] over that in band
    ``den`` (records of T s at fs Hz, one per seed, each spectrum normalised to unit power and summed), divided by
    the same ratio of :func:`kt_cp_displacement` (f_g = 2 Hz, ζ = 0.5, f_c = 0.2 Hz: the generator's defaults).
    1 when the generated spectrum has the textbook shape."""
    from chainid.records.excitation import earthquake

    n = int(fs * T)
    f = np.fft.rfftfreq(n, 1 / fs)
    P = np.zeros(f.size)
    for seed in seeds:
        X = np.abs(np.fft.rfft(earthquake(n, fs, 10.0, 0.0, np.random.default_rng(seed), f_hi=f_hi).x)) ** 2
        P += X / X.sum()
    b1, b2 = (f >= num[0]) & (f <= num[1]), (f >= den[0]) & (f <= den[1])
    ref = (kt_cp_displacement(f[b1]) ** 2).sum() / (kt_cp_displacement(f[b2]) ** 2).sum()
    return float(P[b1].sum() / P[b2].sum() / ref)
