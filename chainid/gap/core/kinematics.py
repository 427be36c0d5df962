"""Smooth kinematics x, ẋ, ẍ of a measured displacement, with the estimator chosen by the record's own spectrum.

A time-domain model force m·ẍ + c·ẋ + F_k(x) + … is only as good as the derivatives it is evaluated on.  On a
damping-dominated record the viscous force c·ẋ is many times the noise, so a 1 % error of ẋ is a residual far
above the noise floor; on a resonant device ẍ carries the inertia.  The estimator is therefore chosen per record
by the error it predicts, and the error it predicts is reported (it enters the noise floor of the diagnosis).

**The rule.**

1. *Periodic record* (the record is a whole number of periods of its excitation: the circular extension is as
   smooth across the wrap as inside, :func:`is_periodic`): spectral derivatives, ẋ = IFFT(i2πf·X(f)) with the
   spectrum cut above ``CUT_FACTOR``·f_band; ẍ cut lower where its own predicted error is less there
   (:func:`spectral_best`).  Exact for a band-limited periodic signal below the cut: the bias is the signal above
   it; the noise of x inside the kept band passes with gain (2πf)^k.
2. *Any other record*: zero-phase 4th-order Butterworth low-passes (run forward and backward, gain |H(f)|²) at
   f_cut = c·f_band for every c of :data:`CUT_CHOICES` from the one whose predicted error on the record's own
   spectrum is least (:func:`error_budget`; per derivative, :func:`adaptive`), then five-point differences
   (gain D(f) = fs·(8·sin θ − sin 2θ)/6, θ = 2πf/fs: a relative error of θ⁴/30 against the central difference's
   θ²/6).  Each estimate's noise is the white noise σ_x of x (:func:`displacement_noise`) through the filter and
   the difference, σ_c² = σ_x²·(2/fs)·∫₀^{fs/2} D(f)²·|H_c(f)|⁴ df.  Every sample takes the most smoothed estimate
   that agrees with all the less smoothed ones within ±``ICI_GAMMA`` of their noise (the intersection of
   confidence intervals, :func:`adaptive`): a smoother estimate where it is unbiased, a sharper one where the
   motion changes fast (an onset, a reversal, an edge).  The error reported per sample is that of the estimate
   it takes: its cut's stationary budget, the signal's |(2πf)^k − |H_c|²·D^k|² and the noise σ_c, the bias at most
   what the intersection tolerates (:func:`_capped`); inside broadband records it is the actual error of ẋ and ẍ
   within 20 % (tests/gap/core/test_kinematics_error_prediction.py).
3. *Edges*: the filters and the differences run on the record extended at each end by its odd reflection about
   the even part of a cubic fitted over a quarter of the band edge's period (:func:`chainid.gap.core.lowpass.
   pad_odd`: x, ẋ, ẍ and x⃛ continue unbroken, where a plain odd reflection flips ẍ and its error spreads over
   the filter's length), so a noisy first sample does not launch a transient.  The estimate there still rests on
   that extrapolation; its predicted error within the padding's reach of each end is the exact one of the linear
   estimator on the record's spectrum (:func:`chainid.gap.core.lowpass.end_profile`), over records of that
   spectrum.  The time route compares forces from half a period of the cut in (:meth:`Kinematics.edge_samples`).
4. *Rest*: where the smooth speed and acceleration both stay within ``REST_SIGMAS`` noise standard deviations of
   zero for at least half a period of f_cut, the record shows no motion and ẋ is 0 (a contact at rest is stuck);
   a reversal passes through zero speed with an acceleration and keeps its estimate.  ẍ is the derivative of the
   unzeroed ẋ.

Units: t s, x mm, ẋ mm/s, ẍ mm/s², f Hz.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import lru_cache

import numpy as np

from chainid.gap.core.lowpass import (butter_gain2, curvature_weight, derivative, end_profile, filtered,
                                     pad_lengths, stencil_gain)
from chainid.gap.core.noise import force_noise, sample_rate

__all__ = ["Kinematics", "CUT_FACTOR", "CUT_CHOICES", "REST_SIGMAS", "estimate", "is_periodic", "spectral",
           "spectral_best", "signal_power", "filtered", "error_budget", "adaptive", "displacement_noise", "derivative",
           "periodogram"]

#: the spectral x and ẋ keep this many times the band edge
CUT_FACTOR = 4.0
#: cut-off factors (× band edge) the filter estimator chooses among
CUT_CHOICES = (1.25, 1.5, 2.0, 3.0, 4.0, 6.0, 8.0, 12.0)
#: a smooth speed within this many noise standard deviations of zero, long enough, is rest (a 4σ test)
REST_SIGMAS = 4.0


@dataclass
class Kinematics:
    """Smooth x [mm], ẋ [mm/s], ẍ [mm/s²] of a record and how they were made.

    ``method`` is ``"spectral"`` or ``"butterworth"``; ``f_cut`` the cut-off [Hz]; ``sigma_x`` the noise of the
    measured x [mm]; ``err_v`` / ``err_a`` the predicted RMS error of ẋ [mm/s] and ẍ [mm/s²] (bias and noise);
    ``noise_v`` the noise part of ``err_v`` alone [mm/s] (the rest test's scale); ``err_x`` the predicted RMS
    error of the smooth x [mm].
    """

    x: np.ndarray
    xd: np.ndarray
    xdd: np.ndarray
    method: str
    f_cut: float
    sigma_x: float
    err_v: float
    err_a: float
    noise_v: float
    err_x: float = 0.0
    #: the predicted RMS error of ẋ per sample [mm/s] (None: ``err_v`` everywhere)
    err_v_t: np.ndarray | None = None
    #: the predicted RMS error of ẍ per sample [mm/s²] (None: ``err_a`` everywhere)
    err_a_t: np.ndarray | None = None
    #: ẍ's cut-off [Hz] (the filter estimator's start inside the record); NaN: not set
    f_cut_a: float = float("nan")
    #: whether x's spectrum holds signal (lines or a continuous roll-off) above ``f_cut_a``: motion ẍ cannot follow
    beyond_a: bool = False
    #: the spread under which friction's sign is taken, per sample [mm/s] (None: :meth:`v_error`)
    sign_sd_t: np.ndarray | None = None
    _spread: np.ndarray | None = None

    def v_error(self) -> np.ndarray | float:
        """The velocity's predicted RMS error [mm/s], per sample where it varies."""
        return self.err_v_t if self.err_v_t is not None else self.err_v

    def v_spread(self, t: np.ndarray) -> np.ndarray:
        """The spread per sample [mm/s] under which the sign of sliding friction is taken
        (:func:`chainid.model.effects.forms.sliding_sign`): the velocity's random error, its noise σ_c times
        √(1 + Γ²/3) for a bias the intersection keeps within ±Γσ_c (``sign_sd_t``; :meth:`v_error` broadcast where
        it is not set).  Not the predicted error with its stationary bias: a smoothing's bias shifts a reversal's
        zero crossing the same way in every record, which a Gaussian softening does not model (on noise-free
        friction records the softened sign then moved F_c between sampling rates).  A force channel samples the
        force at an instant (after its anti-alias filter), so only the estimate's own error softens the sign."""
        if self._spread is None or self._spread.size != np.size(t):
            sd = self.sign_sd_t if self.sign_sd_t is not None else self.v_error()
            self._spread = np.broadcast_to(np.asarray(sd, float), np.shape(t)).copy()
        return self._spread

    def edge_samples(self, fs: float) -> int:
        """Samples at each end of a record whose estimate rests on the padding (rule 3 of the module docstring):
        half a period of ẋ's cut, the rest rule's run, ⌈fs/(2·f_cut)⌉; none for the spectral estimator (a periodic
        record has no ends)."""
        if self.method == "spectral" or not (self.f_cut > 0):
            return 0
        return int(math.ceil(0.5 * fs / self.f_cut))

    def trimmed(self, a: int, b: int) -> "Kinematics":
        """The same estimate on samples a … b − 1 (every per-sample array sliced; ``err_v`` and ``err_a`` the RMS of
        the per-sample errors over the samples kept, where they vary; ``err_x`` and ``noise_v`` stay the record's)."""
        ev_t = None if self.err_v_t is None else self.err_v_t[a:b]
        ea_t = None if self.err_a_t is None else self.err_a_t[a:b]
        rms = (lambda e, whole: whole if e is None or not e.size else float(np.sqrt(np.mean(e ** 2))))
        return replace(self, x=self.x[a:b], xd=self.xd[a:b], xdd=self.xdd[a:b], err_v_t=ev_t, err_a_t=ea_t,
                       err_v=rms(ev_t, self.err_v), err_a=rms(ea_t, self.err_a), _spread=None,
                       sign_sd_t=None if self.sign_sd_t is None else self.sign_sd_t[a:b])

    def info(self) -> dict[str, float | str]:
        """The estimator and its predicted errors, for a report."""
        return {"method": self.method, "f_cut_Hz": self.f_cut, "sigma_x_mm": self.sigma_x, "err_x_mm": self.err_x,
                "err_v_mm_s": self.err_v, "err_a_mm_s2": self.err_a}


def _detrended(x: np.ndarray) -> np.ndarray:
    n = np.arange(x.size)
    return x - np.polyval(np.polyfit(n, x, 1), n)


def is_periodic(x: np.ndarray, sigma_x: float) -> bool:
    """Whether the record is (close to) a whole number of periods of its own excitation.

    A local cubic through the last 8 and the first 8 samples (the wrap-around) must fit as well as local cubics
    inside the record: its residual RMS at most 3× the median of 16 interior windows' and within 4 σ_x of them.
    Needs >= 256 samples.
    """
    x = np.asarray(x, float)
    n = x.size
    if n < 256:
        return False
    u = np.arange(16.0)

    def cubic_rms(seg: np.ndarray) -> float:
        return float(np.sqrt(np.mean((seg - np.polyval(np.polyfit(u, seg, 3), u)) ** 2)))

    wrap = cubic_rms(np.concatenate([x[-8:], x[:8]]))
    starts = np.linspace(8, n - 24, 16).astype(int)
    inner = float(np.median([cubic_rms(x[s:s + 16]) for s in starts]))
    return wrap <= 3.0 * inner + 4.0 * sigma_x


def periodogram(x: np.ndarray, fs: float, window: bool) -> tuple[np.ndarray, np.ndarray, float]:
    """One-sided power spectrum of a record x [mm] sampled at fs [Hz].

    ``window``: detrended and Hann-windowed (a record that is not periodic); else the mean removed.  Returns the
    frequencies f [Hz], the power P [mm² per bin, summing to the variance] and the white noise floor [mm² per bin]
    (the median of the upper half)."""
    y = _detrended(np.asarray(x, float)) if window else np.asarray(x, float) - float(np.mean(x))
    n = y.size
    wv = np.hanning(n) if window else np.ones(n)
    X = np.fft.rfft(y * wv)
    P = (np.abs(X) ** 2) * 2.0 / (n * float(np.sum(wv ** 2)))
    P[0] *= 0.5
    if n % 2 == 0:
        P[-1] *= 0.5
    f = np.fft.rfftfreq(n, 1.0 / fs)
    floor = float(np.median(P[P.size // 2:])) if P.size >= 8 else 0.0
    return f, P, floor


#: bins of the running mean that finds a continuous spectrum below the single-bin detection level
SMOOTH_BINS = 32


def signal_power(P: np.ndarray, floor: float, windowed: bool = False, continuous: bool = True) -> np.ndarray:
    """The signal's power per bin [mm²] in a periodogram ``P`` whose white-noise bins have median ``floor``.

    Two detections, the larger taken per bin:

    * *lines*: a bin above the largest a white-noise periodogram reaches (exponential with mean floor/ln 2: P above
      floor/ln2·ln(20·N) happens by chance with probability 1/20 over the N bins), counted as P − floor/ln 2;
    * *a continuous spectrum* (filtered noise, a response's roll-off): the running mean over
      :data:`SMOOTH_BINS` = K bins, under noise alone a Gamma variable of mean floor/ln 2 and shape K (K/2 for a
      Hann-``windowed`` periodogram, whose neighbouring bins are correlated), counted as the mean less
      floor/ln 2 over the first run of bins above its 95 % quantile that holds a bin above its 1 − 0.05/N
      quantile (two levels, as an edge detector's hysteresis: the seed is a Bonferroni bound over every window
      position, so at most 1 white-noise record in 20 shows any; the run then follows the roll-off down to where
      it is no longer told from noise).  A roll-off continues the excitation's own spectrum; a detection apart
      from it is the noise's.

    The second (``continuous``) finds the roll-off of a band-limited random excitation, which no single bin shows
    but whose sum above a cut is the bias of a derivative cut there (weighed by (2πf)^2k, it decides ẍ's cut on a
    periodic record).
    """
    from scipy.stats import gamma

    P = np.asarray(P, float)
    mean_noise = floor / math.log(2.0)
    lines = np.where(P > mean_noise * math.log(20.0 * max(P.size, 1)), P - mean_noise, 0.0)
    if not continuous or P.size < 4 * SMOOTH_BINS or mean_noise <= 0.0:
        return lines
    shape = SMOOTH_BINS / 2.0 if windowed else float(SMOOTH_BINS)
    seed_level = float(gamma.ppf(1.0 - 0.05 / P.size, shape)) / shape
    run_level = float(gamma.ppf(0.95, shape)) / shape
    smooth = np.convolve(P, np.ones(SMOOTH_BINS) / SMOOTH_BINS, mode="same")
    cont = np.zeros_like(P)
    above = smooth > mean_noise * run_level
    edges = np.flatnonzero(np.diff(np.concatenate([[0], above.view(np.int8), [0]])))
    for a, b in zip(edges[::2], edges[1::2]):
        if np.any(smooth[a:b] > mean_noise * seed_level):
            cont[a:b] = smooth[a:b] - mean_noise
            break
    return np.maximum(lines, cont)


def spectral(x: np.ndarray, fs: float, f_cut: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Spectral x, ẋ, ẍ of a periodic record [mm, mm/s, mm/s²], the spectrum cut above f_cut [Hz]."""
    x = np.asarray(x, float)
    n = x.size
    X = np.fft.rfft(x)
    f = np.fft.rfftfreq(n, 1.0 / fs)
    X[f > f_cut] = 0.0
    w = 2j * np.pi * f
    if n % 2 == 0:  # the Nyquist bin has no derivative of its own
        w[-1] = 0.0
    return np.fft.irfft(X, n), np.fft.irfft(w * X, n), np.fft.irfft(w * w * X, n)


def error_budget(f: np.ndarray, S: np.ndarray, fs: float, f_cut: float, sigma_x: float, order: int = 1,
                 spectral_cut: bool = False) -> tuple[float, float]:
    """Predicted RMS error of the ``order``-th derivative (0: x [mm], 1: ẋ [mm/s], 2: ẍ [mm/s²]): (bias + noise,
    noise alone).

    ``S`` is the signal's one-sided power per bin [mm²] at frequencies ``f`` [Hz] (the periodogram with the noise
    floor removed), σ_x the white noise of x [mm].  ``spectral_cut``: the spectral estimator cut at f_cut [Hz]
    (bias: the signal above the cut); else a 4th-order Butterworth at f_cut run forward and backward, then central
    differences (bias: |w^k − |H|²·D^k|² on the signal, D the five-point difference's gain, :func:`derivative`).
    """
    if order not in (0, 1, 2):
        raise ValueError(f"order = {order!r} is out of range; valid: 0, 1 or 2")
    w = 2.0 * np.pi * np.asarray(f, float)
    noise = sigma_x ** 2 * _noise_gain(float(fs), float(f_cut), int(order), bool(spectral_cut))
    if spectral_cut:
        keep = w <= 2.0 * np.pi * f_cut
        bias = float(np.sum(S[~keep] * w[~keep] ** (2 * order)))
        return math.sqrt(bias + noise), math.sqrt(noise)
    H2 = butter_gain2(w / (2 * np.pi), f_cut, fs)
    D = stencil_gain(w, fs) ** order
    bias = float(np.sum(np.abs(w ** order - H2 * D) ** 2 * S))
    return math.sqrt(bias + noise), math.sqrt(noise)


@lru_cache(maxsize=512)
def _noise_gain(fs: float, f_cut: float, order: int, spectral_cut: bool) -> float:
    """The white noise of x's power gain into the ``order``-th derivative of an estimator (per mm² of σ_x²):
    (2/fs)·∫₀^{fs/2} (2πf)^2k df below the spectral cut, or (2/fs)·∫ D(f)^2k·|H(f)|⁴ df for the filter."""
    ff = np.linspace(0.0, 0.5 * fs, 4097)
    ww = 2.0 * np.pi * ff
    if spectral_cut:
        kk = ww <= 2.0 * np.pi * f_cut
        return (2.0 / fs) * float(np.trapezoid(ww[kk] ** (2 * order), ff[kk])) if kk.sum() > 1 else 0.0
    return (2.0 / fs) * float(np.trapezoid(stencil_gain(ww, fs) ** (2 * order) * butter_gain2(ff, f_cut, fs) ** 2, ff))


def _rest_zero(xd: np.ndarray, xdd: np.ndarray, v_noise: float | np.ndarray, a_noise: float | np.ndarray,
               min_run: int) -> np.ndarray:
    """ẋ with runs of at least ``min_run`` samples at rest set to 0: |ẋ| <= REST_SIGMAS·v_noise and
    |ẍ| <= REST_SIGMAS·a_noise (a reversal passes through zero speed with an acceleration; a rest has none); the
    noise sds may vary per sample."""
    if not np.any(np.asarray(v_noise) > 0.0):
        return xd
    low = (np.abs(xd) <= REST_SIGMAS * np.asarray(v_noise)) & (np.abs(xdd) <= REST_SIGMAS * np.maximum(a_noise, 0.0))
    if not low.any():
        return xd
    edges = np.flatnonzero(np.diff(np.concatenate([[0], low.view(np.int8), [0]])))
    out = xd.copy()
    for a, b in zip(edges[::2], edges[1::2]):
        if b - a >= min_run:
            out[a:b] = 0.0
    return out


def displacement_noise(x: np.ndarray, fs: float, f_band: float) -> float:
    """The white noise σ_x [mm] of a measured displacement.

    Where the excitation band ends below fs/4, the upper half of the spectrum holds noise only: σ_x from its median
    power (the periodogram of white noise of variance σ² is exponential with mean 2σ²/n per bin, median ln 2 of
    that).  Otherwise the robust scale of the second difference (:func:`chainid.gap.core.noise.force_noise`), which a
    signal smooth on the sample scale does not reach.
    """
    x = np.asarray(x, float)
    if x.size < 16:
        return force_noise(x) if x.size >= 5 else 0.0
    if f_band < 0.25 * fs:
        _, _, floor = periodogram(x, fs, window=True)
        return math.sqrt(max(floor, 0.0) / math.log(2.0) * x.size / 2.0)
    return force_noise(x)


def estimate(t: np.ndarray, x: np.ndarray, f_band: float) -> Kinematics:
    """Smooth kinematics of a record by the rule of the module docstring.

    Parameters
    ----------
    t : ndarray
        Time stamps [s], strictly increasing (uniform within a few per cent).
    x : ndarray
        Measured displacement [mm].
    f_band : float
        Upper edge of the excitation band [Hz] (:func:`chainid.gap.core.noise.excitation_band`).
    """
    t = np.asarray(t, float)
    x = np.asarray(x, float)
    fs = sample_rate(t)
    sigma_x = displacement_noise(x, fs, f_band)
    periodic = is_periodic(x, sigma_x)
    f, P, floor = periodogram(x, fs, window=not periodic)
    S_all = signal_power(P, floor, windowed=not periodic)
    if periodic:
        kin = spectral_best(x, fs, f_band, sigma_x, f, signal_power(P, floor, continuous=False), S_all)
    else:
        kin = adaptive(t, x, f_band, sigma_x, f, signal_power(P, floor, windowed=True, continuous=False))
    kin.beyond_a = bool(np.any(S_all[f > kin.f_cut_a] > 0.0))
    return kin


def _cuts(f_band: float, top: float) -> list[float]:
    """The cut-offs [Hz] the estimators choose among: :data:`CUT_CHOICES` × the band edge below ``top`` [Hz]."""
    return [c * f_band for c in CUT_CHOICES if c * f_band < top] or [top]


def _best_cut(f: np.ndarray, S: np.ndarray, fs: float, cuts: list[float], sigma_x: float, order: int,
              spectral_cut: bool) -> int:
    """Index of the cut whose predicted error of the ``order``-th derivative is least (:func:`error_budget`)."""
    return int(np.argmin([error_budget(f, S, fs, fc, sigma_x, order, spectral_cut)[0] for fc in cuts]))


def spectral_best(x: np.ndarray, fs: float, f_band: float, sigma_x: float, f: np.ndarray, S: np.ndarray,
                  S_roll: np.ndarray | None = None) -> Kinematics:
    """Spectral kinematics of a periodic record: x and ẋ cut at ``CUT_FACTOR``·f_band, ẍ where its own predicted
    error is least.

    ẍ weighs the noise of x by (2πf)⁴, so its best cut lies lower: the c·f_band of :data:`CUT_CHOICES` up to
    ``CUT_FACTOR`` whose :func:`error_budget` for ẍ (the signal above the cut, as bias, plus the noise of the kept
    band) is least, on the spectrum's lines and continuous roll-off ``S_roll`` (:func:`signal_power`; default
    ``S``).  x's and ẋ's predicted errors are taken on the lines ``S``.  On a force-driven resonant device the
    inertia force m·ẍ of a cut at the band edge carries a noise many times smaller than at 4× the band.
    """
    S_roll = S if S_roll is None else S_roll
    fc = min(CUT_FACTOR * f_band, 0.5 * fs)
    cuts = [c for c in _cuts(f_band, 0.5 * fs + 1e-9) if c <= fc] or [fc]
    fa = cuts[_best_cut(f, S_roll, fs, cuts, sigma_x, 2, True)]
    xs, xd, _ = spectral(x, fs, fc)
    xdd = spectral(x, fs, fa)[2]
    ex, _ = error_budget(f, S, fs, fc, sigma_x, 0, spectral_cut=True)
    ev, nv = error_budget(f, S, fs, fc, sigma_x, 1, spectral_cut=True)
    ea, na = error_budget(f, S_roll, fs, fa, sigma_x, 2, spectral_cut=True)
    xd = _rest_zero(xd, xdd, nv, na, max(3, int(math.ceil(0.5 * fs / fc))))
    return Kinematics(xs, xd, xdd, "spectral", fc, sigma_x, ev, ea, nv, ex, f_cut_a=fa)


def adaptive(t: np.ndarray, x: np.ndarray, f_band: float, sigma_x: float, f: np.ndarray, S: np.ndarray
             ) -> Kinematics:
    """The filter estimator with a cut-off chosen per sample by the intersection of confidence intervals (ICI).

    The record is filtered at every cut of :data:`CUT_CHOICES` up to 0.45·fs.  x and ẋ start from the cut whose
    predicted error of ẋ on the record's own spectrum ``S`` (its lines, :func:`signal_power`) is least
    (:func:`error_budget`); ẍ from ẍ's own best cut, and inside the record (beyond three periods of that cut from
    either end) up to ``ACC_SPAN`` times it (the ICI tolerates a bias up to Γ times the noise of the sharper
    estimates, large for ẍ, so a smoother start would let a pass-band droop through; a rare empty intersection
    must not hand a sample to an estimate hundreds of times noisier; the ends need the sharp ones).  Each estimate
    of ẋ has a known noise sd σ_k (the white noise σ_x of x through that filter and the difference).  At every
    sample, going from the least smoothed estimate to the most smoothed, the intervals ẋ_k ± ``ICI_GAMMA``·σ_k are
    intersected; the sample takes the most smoothed estimate whose interval still meets all the less smoothed
    ones' (a smoother estimate that disagrees is biased there: an onset, a reversal, an edge).  x and ẍ are chosen
    the same way on their own intervals.  The error reported per sample is the chosen cut's predicted error, its
    stationary budget (bias and noise) inside the record and its end profile near either end
    (:func:`_at_the_ends`); their RMS is ``err_v`` and ``err_a``; ``f_cut`` is the cut most samples take.
    """
    fs = sample_rate(t)
    cuts = _cuts(f_band, 0.45 * fs)
    # x and ẋ never smoother than ẋ's best fixed cut, ẍ than its own: ICI tolerates a bias up to Γ times the noise
    # of the sharper estimates, which for ẍ is large, so a start below ẍ's best lets the pass-band droop through
    i_v = _best_cut(f, S, fs, cuts, sigma_x, 1, False)
    first = [i_v, i_v, _best_cut(f, S, fs, cuts, sigma_x, 2, False)]
    lo = min(first)
    cuts = cuts[lo:]
    rho = curvature_weight(f, S, fs, pad_lengths(x.size, fs, cuts[0], f_band)[1], sigma_x)
    est = [filtered(t, x, fc, f_band, rho) for fc in cuts]
    # (total, noise) of every cut for x, ẋ, ẍ, computed once: the intervals' noise and the predicted errors
    budgets = [np.array([error_budget(f, S, fs, fc, sigma_x, k) for fc in cuts]) for k in (0, 1, 2)]
    nx, nv, na = (b[:, 1] for b in budgets)
    kx, kv, ka = (_ici(np.array([e[j] for e in est])[first[j] - lo:], sd[first[j] - lo:]) + first[j] - lo
                  for j, sd in enumerate((nx, nv, na)))
    # inside the record ẍ's candidates end at ACC_SPAN times its start: a rare empty intersection would otherwise
    # hand a sample to an estimate whose noise is hundreds of times the start's, and those few samples rule ẍ's RMS
    # error; within the start filter's reach of an end (3 periods of its cut) every candidate stays open
    a0 = first[2] - lo
    span = 1 + max(i for i, c in enumerate(cuts) if c <= ACC_SPAN * cuts[a0])
    inner = _ici(np.array([e[2] for e in est])[a0:span], na[a0:span]) + a0
    reach = int(min(x.size // 2, math.ceil(3.0 * fs / cuts[a0])))
    ka[reach:x.size - reach] = inner[reach:x.size - reach]
    ex_t, ev_t, ea_t = _at_the_ends(f, S, fs, cuts, f_band, sigma_x, x.size, [i - lo for i in first], [kx, kv, ka],
                                    rho, budgets)
    rows = np.arange(x.size)
    xs = np.array([e[0] for e in est])[kx, rows]
    xd = np.array([e[1] for e in est])[kv, rows]
    xdd = np.array([e[2] for e in est])[ka, rows]
    fc = cuts[int(np.bincount(kv, minlength=len(cuts)).argmax())]
    ex = float(np.sqrt(np.mean(ex_t ** 2)))
    xd = _rest_zero(xd, xdd, nv[kv], na[ka], max(3, int(math.ceil(0.5 * fs / fc))))
    kin = Kinematics(xs, xd, xdd, "butterworth-ici", fc, sigma_x, float(np.sqrt(np.mean(ev_t**2))),
                     float(np.sqrt(np.mean(ea_t**2))), float(np.sqrt(np.mean(nv[kv] ** 2))), ex)
    kin.err_v_t, kin.err_a_t = ev_t, ea_t
    kin.sign_sd_t = nv[kv] * math.sqrt(1.0 + ICI_GAMMA ** 2 / 3.0)
    kin.f_cut_a = cuts[a0]
    return kin


def _capped(tot: np.ndarray, noise: np.ndarray) -> np.ndarray:
    """Per cut, from its stationary budget (:func:`error_budget`: ``tot``, ``noise``): the predicted error
    inside the record, the noise σ_c and the bias b_c with b_c² ≤ Γ²σ'²/3, σ' the noise of the next sharper cut
    (the intersection keeps an estimate whose bias stays within the sharper estimates' ±Γσ'; taken uniform
    there; the sharpest cut's bias uncapped).  A noise bin that passes for a line far above the band (one record
    in twenty) would otherwise count its (2πf)^2k-weighted power as bias of every cut: the bound keeps that
    record's prediction within a few times its error."""
    sharper = np.append(noise[1:], np.inf)  # no sharper estimate bounds the sharpest cut's bias
    return np.sqrt(noise ** 2 + np.minimum(tot ** 2 - noise ** 2, ICI_GAMMA ** 2 * sharper ** 2 / 3.0))


def _at_the_ends(f: np.ndarray, S: np.ndarray, fs: float, cuts: list[float], f_band: float, sigma_x: float,
                 n: int, first: list[int], picks: list[np.ndarray], rho: float, budgets: list[np.ndarray]
                 ) -> list[np.ndarray]:
    """Per-sample predicted errors of x, ẋ, ẍ [mm, mm/s, mm/s²], with the ends' cuts chosen by them.

    ``budgets[k]`` holds every cut's (total, noise) :func:`error_budget` of order k.  Inside the record each
    sample keeps the intersection's cut (``picks``, indices into ``cuts``, rewritten at the ends) and the cut's
    :func:`_capped` error.  Within three periods of the smoothest cut of either end the intersection cannot see the
    padding's bias (its intervals hold noise only: at a 12-20 Hz record's first samples it took estimates twice as
    wrong as their own prediction), so there every sample takes, from order k's first candidate on, the cut whose
    predicted error at that distance from the end is least: the cut's end profile (:func:`chainid.gap.core.lowpass.
    end_profile`) in excess of its stationary budget, added to its :func:`_capped` error.  The choice depends on the
    spectrum, not on the record's values at the ends, so the prediction holds over records of that spectrum."""
    reach = int(min(n // 2, math.ceil(3.0 * fs / cuts[0])))
    profiles = [end_profile(f, S, fs, fc, f_band, sigma_x, n, rho) for fc in cuts]
    out = []
    for order, k_t in enumerate(picks):
        tot = budgets[order][:, 0]
        capped = _capped(tot, budgets[order][:, 1])
        e_t = capped[k_t]
        for side, idx in enumerate((np.arange(reach), n - 1 - np.arange(reach))):
            E = np.tile(capped[:, None], (1, reach))
            for c, prof in enumerate(profiles):
                R = min(prof.shape[2], reach)
                E[c, :R] = np.sqrt(capped[c] ** 2 + np.maximum(prof[side, order, :R] ** 2 - tot[c] ** 2, 0.0))
            E[:first[order]] = np.inf
            best = np.argmin(E, axis=0)
            k_t[idx] = best
            e_t[idx] = E[best, np.arange(reach)]
        out.append(e_t)
    return out


#: half-width of the ICI confidence intervals, in noise standard deviations
ICI_GAMMA = 2.5
#: ẍ's ICI candidates span its best fixed cut to this many times it
ACC_SPAN = 2.0


def _ici(V: np.ndarray, sd: np.ndarray) -> np.ndarray:
    """Per sample, the index of the most smoothed estimate (row 0 most smoothed, rows in order of cut) whose
    interval V_k ± ICI_GAMMA·sd_k meets those of every less smoothed estimate."""
    K, n = V.shape
    lo = np.full(n, -np.inf)
    hi = np.full(n, np.inf)
    choice = np.full(n, K - 1)
    alive = np.ones(n, bool)
    for k in range(K - 1, -1, -1):
        lo = np.maximum(lo, V[k] - ICI_GAMMA * sd[k])
        hi = np.minimum(hi, V[k] + ICI_GAMMA * sd[k])
        alive &= lo <= hi
        choice = np.where(alive, k, choice)
    return choice
