"""Stationarity of the residual (chainid.gap.core.stationarity): trends against time with the shaker's mean and
amplitude as covariates, their noise floors and the four-standard-error threshold.  Units N, s."""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from chainid.gap.core import stationarity


# ---------------------------------------------------------------- stationarity
def _cycles(n=12):
    t = np.arange(n, dtype=float)  # one cycle per second
    xm = 0.02 * t + 0.05 * np.sin(1.3 * t)  # the shaker's mean wanders (not collinear with t)
    xa = 2.0 + 0.01 * t + 0.04 * np.cos(0.7 * t)  # and so does its amplitude
    return t, xm, xa


def test_trend_follows_the_shakers_mean_and_amplitude_not_time():
    """A force that only follows the shaker's mean (F = 100 + 30·x_m) and amplitude (a = 50·x_a) has no trend.
    Bugs caught: the covariate column dropped, or x_m / x_a swapped between the mean and the harmonics."""
    t, xm, xa = _cycles()
    cy = {"t": t, "mean": 100.0 + 30.0 * xm, "a": 50.0 * xa, "b": 3.0 + 0.0 * t, "xm": xm, "xa": xa,
          "n": np.full(t.size, 64.0)}
    res = stationarity.check([SimpleNamespace(test="T1", sigma=0.01, cycles=cy)])
    row = res["tests"][0]
    for q in ("mean", "a", "b"):
        assert abs(row[q]["slope_N_per_s"]) < 1e-9, q
    assert res["stationary"] is True
    # the same force against time alone has the slope of 30·x_m's line in t: clearly a trend without the covariate
    sl, se, _ = stationarity.trend(t, cy["mean"])
    assert abs(sl) > 0.3 and abs(sl) / se > stationarity.Z_TREND


def test_trend_noise_floor_closed_form():
    """An exact line has zero scatter: its standard error is the floor σ_c/sqrt(Σ(t−t̄)²) (closed form), its change
    |slope|·span.  Bugs caught: the floor ignored (se → 1e-300), floor not squared, span from the wrong end."""
    t = np.arange(10, dtype=float)  # Σ(t − 4.5)² = 82.5
    sl, se, chg = stationarity.trend(t, 0.1 * t, sd_floor=0.5)
    assert sl == pytest.approx(0.1, rel=1e-12)
    assert se == pytest.approx(0.5 / math.sqrt(82.5), rel=1e-9)
    assert chg == pytest.approx(0.9, rel=1e-12)


def test_check_floor_per_quantity():
    """The per-cycle floor is σ·sqrt(1/n) for the mean and σ·sqrt(2/n) for a harmonic amplitude (white noise), so
    exact lines of slope s give z = s·sqrt(82.5)/floor.  Bug caught: 1 and 2 swapped or the same for both."""
    t = np.arange(10, dtype=float)
    x0 = np.zeros(10)
    cy = {"t": t, "mean": 0.2 * t, "a": 0.2 * t, "b": 0.0 * t, "xm": x0, "xa": x0, "n": np.full(10, 50.0)}
    row = stationarity.check([SimpleNamespace(test="T", sigma=1.0, cycles=cy)])["tests"][0]
    assert row["mean"]["z"] == pytest.approx(0.2 * math.sqrt(82.5) / math.sqrt(1 / 50), rel=1e-9)
    assert row["a"]["z"] == pytest.approx(0.2 * math.sqrt(82.5) / math.sqrt(2 / 50), rel=1e-9)


def test_too_few_cycles_not_checked():
    t = np.arange(stationarity.MIN_CYCLES - 1, dtype=float)
    cy = {"t": t, "mean": t, "a": t, "b": t, "xm": t, "xa": t, "n": np.ones_like(t)}
    assert stationarity.check([SimpleNamespace(test="T", sigma=1.0, cycles=cy)])["stationary"] is None
    t4 = np.arange(stationarity.MIN_CYCLES, dtype=float)
    cy4 = {k: np.arange(stationarity.MIN_CYCLES, dtype=float) for k in ("t", "mean", "a", "b", "xm", "xa")}
    assert stationarity.check([SimpleNamespace(test="T", sigma=1.0, cycles=cy4)])["stationary"] is not None
    assert t4.size == stationarity.MIN_CYCLES


def test_trend_standard_error_from_the_scatter_by_textbook_formulas():
    """``trend`` without a covariate is the straight-line fit: slope b = Sxy/Sxx, s² = RSS/(n − 2), SE = √(s²/Sxx)
    (textbook OLS); the floor only counts when larger than the scatter (floor 0.01 here: it does not)."""
    from chainid.gap.core.stationarity import trend

    t = np.arange(10, dtype=float)
    y = 3.0 + 0.1 * t + 2.0 * (-1.0) ** np.arange(10)
    sxx = float(np.sum((t - t.mean()) ** 2))
    b = float(np.sum((t - t.mean()) * (y - y.mean()))) / sxx
    rss = float(np.sum((y - y.mean() - b * (t - t.mean())) ** 2))
    sl, se, chg = trend(t, y, sd_floor=0.01)
    assert sl == pytest.approx(b, rel=1e-12) and se == pytest.approx(math.sqrt(rss / 8 / sxx), rel=1e-12)
    assert chg == pytest.approx(abs(b) * 9, rel=1e-12)
    assert trend(t, y, sd_floor=10.0)[1] == pytest.approx(10.0 / math.sqrt(sxx), rel=1e-12)  # the floor wins


def _cycle_table(slope: float, n: int = 10) -> dict[str, np.ndarray]:
    t = np.arange(n, dtype=float)  # one cycle a second
    return {"t": t, "mean": slope * t, "a": np.zeros(n), "b": np.zeros(n), "xm": np.full(n, 2.0),
            "xa": np.full(n, 0.1)}


def _tests(slopes):
    return [SimpleNamespace(test=f"T{i}", sigma=1.0, cycles=_cycle_table(s)) for i, s in enumerate(slopes)]


def test_stationarity_a_trend_in_a_quarter_of_the_tests_by_hand():
    """Noise-free lines: the scatter is 0, so the standard error is the floor σ·sqrt(1/n) = 1 N (no cycle counts
    given: n = 1) over sqrt(Σ(t − t̄)²) = sqrt(82.5) for t = 0 … 9 s; slope 5 N/s: z = 5·sqrt(82.5) = 45.4,
    change 5·9 = 45 N.  One trending test in 4 is a quarter (non-stationary), one in 5 is not."""
    from chainid.gap.core import stationarity

    z = 5.0 * math.sqrt(82.5)
    res = stationarity.check(_tests([5.0, 0.0, 0.0, 0.0]))
    assert res["stationary"] is False
    assert res["z"] == pytest.approx(z, rel=1e-9)
    q = res["by_quantity"]["mean"]
    assert q["n_tests"] == 1 and q["max_z"] == pytest.approx(z, rel=1e-9)
    assert q["change_N"] == pytest.approx(math.sqrt(45.0 ** 2 / 4), rel=1e-9)  # RMS over the 4 tests: 22.5 N
    assert res["trend_change_N"] == pytest.approx(22.5, rel=1e-9)  # a and b flat: only the mean counts
    assert res["by_quantity"]["a"] == {"max_z": 0.0, "change_N": 0.0, "n_tests": 0}
    assert res["finding"].startswith(
        "non-stationary: the mean force trends over the cycles in 1 of 4 tests (change over the window 22.5 N "
        "RMS over tests, up to 45.4 standard errors)")
    assert [r["n_cycles"] for r in res["tests"]] == [10] * 4
    res5 = stationarity.check(_tests([5.0, 0.0, 0.0, 0.0, 0.0]))
    assert res5["stationary"] is True and res5["finding"].startswith("the force is stationary")
    assert res5["by_quantity"]["mean"]["change_N"] == pytest.approx(45.0 / math.sqrt(5), rel=1e-9)
    # two in 5 (ceil(0.25 · 5) = 2) is enough again
    assert stationarity.check(_tests([5.0, -5.0, 0.0, 0.0, 0.0]))["stationary"] is False


@pytest.mark.parametrize("z,stationary", [(3.9, True), (4.1, False)])
def test_stationarity_threshold_is_four_standard_errors(z, stationary):
    from chainid.gap.core import stationarity

    res = stationarity.check(_tests([z / math.sqrt(82.5)]))
    assert res["z"] == pytest.approx(z, rel=1e-9)
    assert res["stationary"] is stationary
    assert res["trend_change_N"] == pytest.approx(0.0 if stationary else 9 * z / math.sqrt(82.5), rel=1e-9)


def test_stationarity_floor_of_a_harmonic_amplitude_uses_the_cycle_counts():
    """A harmonic amplitude's floor is σ·sqrt(2/n) with n the mean samples per cycle: σ = 2 N, n = 50 →
    0.4 N; a slope 0.1 N/s of b over t = 0 … 9: z = 0.1·sqrt(82.5)/0.4."""
    from chainid.gap.core import stationarity

    cy = _cycle_table(0.0) | {"b": 0.1 * np.arange(10.0), "n": np.full(10, 50.0)}
    res = stationarity.check([SimpleNamespace(test="T", sigma=2.0, cycles=cy)])
    assert res["tests"][0]["b"]["z"] == pytest.approx(0.1 * math.sqrt(82.5) / 0.4, rel=1e-9)
    assert res["tests"][0]["b"]["change_N"] == pytest.approx(0.9, rel=1e-9)


def test_trend_uses_the_covariate_from_six_cycles_on():
    """y = 3·t + 10·cov exactly: with ≥ 6 cycles the covariate is fitted and the slope is 3 N/s exactly; with 5
    it is not (too few cycles for three coefficients and a scatter), and the slope is the plain line's."""
    from chainid.gap.core import stationarity

    cov = np.array([0.3, -0.1, 0.7, 0.2, -0.4, 0.5])
    for n in (5, 6):
        t, c = np.arange(n, dtype=float), cov[:n]
        y = 3.0 * t + 10.0 * c
        sl, se, chg = stationarity.trend(t, y, c)
        plain = float(np.polyfit(t, y, 1)[0])
        assert sl == pytest.approx(3.0 if n == 6 else plain, rel=1e-9, abs=1e-12)
        assert chg == pytest.approx(abs(sl) * (n - 1), rel=1e-12)
        if n == 5:
            assert plain != pytest.approx(3.0, rel=1e-3)  # the two readings differ
    assert stationarity.trend(np.arange(2.0), np.arange(2.0)) == (0.0, math.inf, 0.0)  # fewer than 3 cycles
    assert stationarity.trend(np.zeros(4), np.arange(4.0)) == (0.0, math.inf, 0.0)  # no time span
    none = stationarity.check(_tests([]) + [SimpleNamespace(test="S", sigma=1.0, cycles=_cycle_table(1.0, n=3))])
    assert none["stationary"] is None
    assert none["finding"] == "stationarity not checked: no test has >= 4 whole steady cycles"
