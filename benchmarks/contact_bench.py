"""The free-exponent contact kernel's inverse F_k(x) (``generated/contact_power.py``) against two baselines.

``force_array`` starts each sample's Newton in s = ln F at the last sample's root (under the upper bound) and
computes F^β as e^(βs); it stops at a step of a few ulp of s.  Baselines, measured in the same run: ``cold``, the same kernel started at the upper bound
for every sample (``log_force`` with no guess); ``before``, the kernel as it was generated before (cold starts,
F^β as a power, an absolute stop at 1e-15 in s).  Two inputs of 10^5 elongations [mm]: a record (a 1 Hz sine
around 0.5 mm at 400 Hz with 1 % noise, the gap diagnosis' case) and log-uniform samples in random order
(1e-9 to 1e3 mm, no neighbour close: the warm start's worst case).  Medians of 15 repetitions, single thread.

Usage (from the repository root)::

    python benchmarks/contact_bench.py
"""
from __future__ import annotations

import math
import statistics
import sys
import time
from pathlib import Path

import numpy as np
from numba import njit

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from chainid.model.base import ChainModel  # noqa: E402
from chainid.model.kernels import power_module  # noqa: E402

_mod = power_module()
_log_force = _mod.log_force


@njit
def cold_array(x: np.ndarray, c_lin: float, c_hertz: float, beta: float) -> np.ndarray:
    """Every sample's Newton from the upper bound (the baseline)."""
    out = np.empty(x.shape[0])
    for i in range(x.shape[0]):
        out[i] = math.exp(_log_force(x[i], c_lin, c_hertz, beta, math.nan))
    return out


@njit
def before_array(x: np.ndarray, c_lin: float, c_hertz: float, beta: float) -> np.ndarray:
    """The earlier kernel: Newton from the upper bound, F**beta a power (the generated code before the change)."""
    out = np.empty(x.shape[0])
    for i in range(x.shape[0]):
        if x[i] <= 0.0:
            out[i] = 0.0
            continue
        s = min(math.log(x[i] / c_lin), math.log(x[i] / c_hertz) / beta)
        for _ in range(200):
            F = math.exp(s)
            step = (F * c_lin + F**beta * c_hertz - x[i]) / (F * c_lin + F**beta * beta * c_hertz)
            s -= step
            if abs(step) <= 1e-15:
                break
        out[i] = math.exp(s)
    return out


@njit
def newton_steps(x: np.ndarray, c_lin: float, c_hertz: float, beta: float, warm: bool) -> float:
    """Mean Newton steps per positive sample of the kernel's iteration (its stopping rule), from the last root
    (``warm``) or cold."""
    total, count, s_last = 0, 0, math.nan
    for i in range(x.shape[0]):
        if not x[i] > 0.0:
            continue
        s_hi = min(math.log(x[i] / c_lin), math.log(x[i] / c_hertz) / beta)
        s = s_last if warm and s_last < s_hi else s_hi
        tol, last = 8.9e-16 * (abs(s_hi) + 2.0 / beta), math.inf
        for _ in range(200):
            step = ((math.exp(s) * c_lin + math.exp(beta * s) * c_hertz - x[i])
                    / (math.exp(s) * c_lin + math.exp(beta * s) * beta * c_hertz))
            s = min(s - step, s_hi)
            total += 1
            if abs(step) <= tol or (abs(step) >= last and abs(step) <= 1e3 * tol):
                break
            last = abs(step)
        s_last, count = s, count + 1
    return total / max(count, 1)


def median_time(fn, *args, repeat: int = 15) -> float:
    """Median wall time [s] of ``fn(*args)`` after one warm-up call."""
    fn(*args)
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn(*args)
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main() -> int:
    coef = ChainModel(contact_exponent=0.8).coefficients
    rng = np.random.default_rng(0)
    t = np.arange(100_000) / 400.0
    inputs = {"record (sine + noise)": 0.5 + 0.3 * np.sin(2 * np.pi * t) + 0.003 * rng.standard_normal(t.size),
              "log-uniform, random order": 10.0 ** rng.uniform(-9, 3, 100_000)}
    print("contact_power.force_array, beta = 0.8, 10^5 samples, median of 15")
    for name, x in inputs.items():
        warm, cold = median_time(_mod.force_array, x, *coef), median_time(cold_array, x, *coef)
        before = median_time(before_array, x, *coef)
        same = np.max(np.abs(_mod.force_array(x, *coef) / before_array(x, *coef) - 1.0))
        print(f"  {name:<27} now {warm * 1e3:6.2f} ms  cold/now {cold / warm:5.2f}  before/now {before / warm:5.2f}"
              f"  max rel. difference from before {same:.1e}")
        print(f"  {'':<27} Newton steps per sample: {newton_steps(x, *coef, False):.2f} cold, "
              f"{newton_steps(x, *coef, True):.2f} from the last root")
    return 0


if __name__ == "__main__":
    sys.exit(main())
