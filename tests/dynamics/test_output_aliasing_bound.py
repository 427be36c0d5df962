"""The output-aliasing warning of a dynamics run is at fewer than 2 stored samples per drive period (the Nyquist
rate), not at fewer than 1: a sine of period 0.03 s stored every 0.02 s (500 outputs over 10 s) is 1.5 samples
per period and warns; stored every 0.01 s (1000 outputs) it is 3 per period and does not.  Periods by hand."""
from __future__ import annotations

import math
import warnings

from chainid.dynamics import ChainLine, Drive, simulate

LINE = ChainLine(n_links=100, n_masses=10, pretension_N=5000.0)
T = 0.03  # s
DRIVE = Drive("sine", A=0.01, omega=2 * math.pi / T)


def _alias_warnings(n_out: int) -> list[str]:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        res = simulate(LINE, DRIVE, 10.0, n_out=n_out)
    assert res.dt < T / 20  # the step resolves the drive: only the outputs can alias it
    return [m for m in res.warnings if "by the outputs" in m]


def test_one_and_a_half_samples_per_period_warn():
    (msg,) = _alias_warnings(500)
    assert "(1.5 per period; valid >= 2)" in msg


def test_three_samples_per_period_do_not():
    assert _alias_warnings(1000) == []
