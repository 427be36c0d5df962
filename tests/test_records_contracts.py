"""records contracts (issue 20 §5, mutation survivors of records): the earthquake generator's spectrum is the
Kanai–Tajimi × Clough–Penzien form its docstring names, a record of 1.5 cycles is reported as 1.5 periods, and a
duplicated column is named with its 1-based positions."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.records.excitation import earthquake
from chainid.records.files import read_records
from chainid.records.record import Record
from chainid.records.validate import validate_record


def _kt_cp_displacement(f, f_g=2.0, zeta_g=0.5, f_c=0.2):
    """Displacement amplitude of the textbook Kanai–Tajimi ground acceleration filtered by the Clough–Penzien
    high-pass (ζ_c = 0.7): sqrt(|H_KT|²·|H_CP|²)/ω², typed from the standard forms."""
    w, wg, wc = 2 * np.pi * f, 2 * np.pi * f_g, 2 * np.pi * f_c
    hkt = (wg**4 + 4 * zeta_g**2 * wg**2 * w**2) / ((wg**2 - w**2) ** 2 + 4 * zeta_g**2 * wg**2 * w**2)
    hcp = w**4 / ((wc**2 - w**2) ** 2 + 4 * 0.7**2 * wc**2 * w**2)
    return np.sqrt(hkt * hcp) / w**2


def test_earthquake_spectrum_slope_is_kanai_tajimi_clough_penzien():
    """Between f_c = 0.2 Hz and f_g = 2 Hz the Clough–Penzien |H|² is about 1 and the displacement (acceleration
    over ω²) falls as about f⁻², raised a little by the Kanai–Tajimi peak at f_g: the log-log slope of the
    generated displacement's amplitude spectrum over 0.3–2 Hz matches that of the closed form within 0.25
    (a high-pass of another order tilts it by a whole unit). Measured over seeds 5–12: within 0.13."""
    band = (0.3, 2.0)
    fs, T = 8.0, 960.0  # a long record: the envelope smears the random-phase spectrum over fewer bins
    n = int(fs * T)
    rng = np.random.default_rng(6)
    m = earthquake(n, fs, 10.0, 0.0, rng, f_hi=3.0)
    X = np.abs(np.fft.rfft(m.x))
    f = np.fft.rfftfreq(n, 1 / fs)
    sel = (f >= band[0]) & (f <= band[1])
    slope = np.polyfit(np.log(f[sel]), np.log(X[sel]), 1)[0]
    ref = np.polyfit(np.log(f[sel]), np.log(_kt_cp_displacement(f[sel])), 1)[0]
    assert slope == pytest.approx(ref, abs=0.25)
    assert float(np.max(np.abs(m.x))) == pytest.approx(10.0, rel=1e-9)  # scaled to the peak


def test_one_and_a_half_cycles_are_reported_as_such():
    """A steady sine of period 2π s over 1.5 periods: fewer than the 2 whole cycles needed; the message says the
    record spans 1.5 periods of 6.283 s."""
    t = np.linspace(0.0, 3 * math.pi, 1500, endpoint=False)
    x = 2.0 + 0.3 * np.sin(t)
    rec = Record("a", t, x, 1000.0 * x)
    with pytest.raises(ValueError, match=r"test 'a': fewer than 2 full cycles .* spans 1\.5 periods of 6\.283 s"):
        validate_record(rec)


def test_duplicate_column_is_named_with_its_positions(tmp_path):
    p = tmp_path / "d.csv"
    p.write_text("test,t,x,F,x\n1,0,1,2,3\n1,0.1,1,2,3\n")
    with pytest.raises(ValueError, match=r"column\(s\) \['x'\] appear more than once .*at positions \[3, 5\]"):
        read_records(p)
