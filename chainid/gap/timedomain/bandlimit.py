"""The band in which a record's force is compared with the model: a state-variable filter for a band-limited force.

The model force m·ẍ + c·ẋ + F_k(x) + … is evaluated on kinematics cut at a few times the band edge
(:mod:`chainid.gap.core.kinematics`).  On a force-driven device (a shaker, an analog mass–spring–damper) the
measured force is the drive: band-limited, with nothing above the band but noise.  Its nonlinear parts (a stick,
a friction corner) put content above the cut into the true ẍ that cancels theirs in the force; the estimated ẍ has
lost it, so the model force keeps a high-frequency residual that no effect can fit, and it ranks a smooth
hysteresis above the true sharp friction.  Where the force has no content above ẍ's cut the comparison loses
nothing by being made below it: the force and every model column pass the same zero-phase low-pass (the
state-variable filter of continuous-time identification), and the residual is what the model misses in the band
its kinematics resolve.  Where the force has content above the cut (a displacement-driven device whose friction
switches), that content is information and the record is compared over the whole band, as before.

**The rule** (:func:`residual_cut`): a record is compared below f_a, ẍ's cut, when

* the motion has content above f_a (its spectrum's lines or continuous roll-off, detected as the kinematics detect
  them): fast motion that ẍ does not follow, made inside the device since the force has none; and
* the force's power above f_a is that of its white noise σ_F (the robust second-difference estimate of the
  record's force noise), within 4.4 standard deviations (:func:`residual_cut`); and f_a < 0.45·fs.

A displacement-driven record whose motion ends below the cut, one whose force switches (friction: content above the
cut), and a linear device driven by force (whose motion above the cut is the force's, divided by m·ω²: below the
displacement noise) are compared over the whole band.  A displacement drive whose roll-off runs past the cut while
its force there is only noise (a smooth device under broadband motion) is compared below it: where the force has
nothing above the cut, the comparison loses nothing there but noise.

The filter is the 4th-order zero-phase Butterworth of the kinematics (:func:`chainid.gap.core.noise.lowpass_sos`);
white noise through it keeps the share ρ = (2/fs)·∫|H(f)|⁴ df of its power (:func:`noise_share`), and the filtered
residual's samples are correlated, ρ·n of them independent: the noise floor and the χ² tests of the diagnosis use
both (:meth:`chainid.gap.timedomain.problem.TimeProblem.noise_floor`, ``n_cells``).

Units: Hz, s; arrays in the caller's units.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from chainid.gap.core.noise import lowpass_sos, psd

__all__ = ["residual_cut", "noise_share", "difference_share", "runs", "band_limited"]


def residual_cut(F: np.ndarray, fs: float, f_a: float, sigma: float, beyond_a: bool) -> float:
    """The cut [Hz] below which a record's force is compared with the model: ``f_a`` when the motion has content
    above it (``beyond_a``, :attr:`chainid.gap.core.kinematics.Kinematics.beyond_a`) and the force holds nothing but
    its white noise σ [N] there, else NaN (the whole band).

    Above f_a the Hann-windowed periodogram of F (:func:`chainid.gap.core.noise.psd`, its linear trend removed), each
    bin over its white-noise mean σ²·Σw², has a mean R; under noise alone R is 1 with a standard deviation
    √(35/18/N) over N bins (a Hann bin correlates with its first and second neighbours with |ρ|² = 4/9 and 1/36:
    1 + 2·(4/9 + 1/36) = 35/18).  The force is band-limited when R < 1 + 5·√(1.5/N): a one-sided test at 4.4 of
    those standard deviations."""
    F = np.asarray(F, float)
    n = F.size
    if not beyond_a or not (math.isfinite(f_a) and 0.0 < f_a < 0.45 * fs) or n < 256 or not sigma > 0.0:
        return float("nan")
    f, P = psd(F, fs)
    P = P / (sigma**2 * float(np.sum(np.hanning(n) ** 2)))
    above = f > f_a
    N = int(above.sum())
    if N < 64:
        return float("nan")
    return float(f_a) if float(np.mean(P[above])) < 1.0 + 5.0 * math.sqrt(1.5 / N) else float("nan")


@functools.lru_cache(maxsize=256)
def _sos(fs: float, f_cut: float) -> np.ndarray | None:
    """The filter's second-order sections (designed once per rate and cut)."""
    return lowpass_sos(fs, f_cut, 1 << 12)


@functools.lru_cache(maxsize=256)
def _steady_state(fs: float, f_cut: float) -> np.ndarray:
    """The filter's unit-step steady state, ``scipy.signal.sosfilt_zi`` of :func:`_sos` (computed once)."""
    from scipy.signal import sosfilt_zi

    return sosfilt_zi(_sos(fs, f_cut))


def noise_share(fs: float, f_cut: float) -> float:
    """ρ: the share of a white noise's power that the zero-phase filter at ``f_cut`` [Hz] keeps (1 when none)."""
    sos = _sos(float(fs), float(f_cut)) if math.isfinite(f_cut) else None
    if sos is None:
        return 1.0
    from scipy.signal import sosfreqz

    _, h = sosfreqz(sos, worN=8192, fs=fs)
    return float(np.mean(np.abs(h) ** 4))


def difference_share(fs: float, f_cut: float) -> float:
    """The share of a white noise's second-difference power that the zero-phase filter at ``f_cut`` keeps.

    mean(|H|⁴·(2 sin πf/fs)⁴) / 6 over 0 … fs/2, the second difference's own gain (2 sin πf/fs)⁴ averaging 6 there.
    A record compared below the cut has a residual whose second difference holds this share of the noise's
    (:mod:`.noisecheck`).

    Parameters
    ----------
    fs : float
        Sampling rate [Hz].
    f_cut : float
        The comparison's cut [Hz] (NaN, or one the filter cannot make: no filter).

    Returns
    -------
    float
        The share, in (0, 1]; 1 without a filter.
    """
    sos = _sos(float(fs), float(f_cut)) if math.isfinite(f_cut) else None
    if sos is None:
        return 1.0
    from scipy.signal import sosfreqz

    f, h = sosfreqz(sos, worN=8192, fs=fs)
    return float(np.mean(np.abs(h) ** 4 * (2.0 * np.sin(np.pi * f / fs)) ** 4) / 6.0)


def _pad(sos: np.ndarray) -> int:
    """``scipy.signal.sosfiltfilt``'s default padding of ``sos``: 3 × its taps, 2·sections + 1 less the trailing
    zero coefficients its sections share (none for this Butterworth low-pass)."""
    ntaps = 2 * sos.shape[0] + 1 - min(int((sos[:, 2] == 0).sum()), int((sos[:, 5] == 0).sum()))
    return 3 * ntaps


def _filtfilt(sos: np.ndarray, zi: np.ndarray, x: np.ndarray) -> np.ndarray:
    """``scipy.signal.sosfiltfilt(sos, x, axis=0)`` with its default padding, the same operations in the same
    order (odd extension by :func:`_pad` samples, forward pass from the steady state at the first sample,
    backward pass from the one at the last), with the steady state ``zi`` given instead of solved for on every
    call: bit-identical, at a quarter of the time on a 4 000-sample run (``benchmarks/bandlimit_bench.py``)."""
    from scipy.signal import sosfilt

    edge = _pad(sos)
    ext = np.concatenate((2 * x[:1] - x[edge:0:-1], x, 2 * x[-1:] - x[-2 : -(edge + 2) : -1]), axis=0)
    z = zi.reshape((sos.shape[0], 2) + (1,) * (x.ndim - 1))
    y, _ = sosfilt(sos, ext, axis=0, zi=z * ext[:1])
    y, _ = sosfilt(sos, y[::-1], axis=0, zi=z * y[-1:])
    return y[::-1][edge:-edge]


def runs(n: int, idx: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Start and end (exclusive) positions of the runs of consecutive sample indices in ``idx`` (a view of windows
    of a record; None: one run of ``n`` samples)."""
    if idx is None:
        return np.array([0]), np.array([n])
    cut = np.flatnonzero(np.diff(idx) != 1) + 1
    return np.concatenate([[0], cut]), np.concatenate([cut, [idx.size]])


def band_limited(a: np.ndarray, fs: float, f_cut: float, idx: np.ndarray | None = None) -> np.ndarray:
    """``a`` (samples along axis 0) through the zero-phase filter at ``f_cut`` [Hz], each run of consecutive
    sample indices ``idx`` (a view of windows of a record; None: one run) filtered on its own; ``a`` unchanged
    when ``f_cut`` is NaN.  A run too short for the filter's padding (a view of every q-th sample, q > 1, is all
    runs of one: a decimated series has no band to cut at the record's rate) passes as it is.  Each run's result
    is the one ``scipy.signal.sosfiltfilt`` gives it (:func:`_filtfilt`, with the filter's steady state solved once
    per rate and cut)."""
    if not math.isfinite(f_cut):
        return a
    sos = _sos(float(fs), float(f_cut))
    if sos is None:
        return a
    zi = _steady_state(float(fs), float(f_cut))
    a = np.asarray(a, float)
    starts, ends = runs(a.shape[0], idx)
    pad = _pad(sos)  # sosfiltfilt's default padding needs a run longer than it
    long = np.flatnonzero(ends - starts > pad)
    if long.size == 0:
        return a
    out = a.copy()
    for i, j in zip(starts[long], ends[long]):
        out[i:j] = _filtfilt(sos, zi, a[i:j])
    return out
