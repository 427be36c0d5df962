"""Noise floor, excitation band and smooth kinematics of a record that is not a steady harmonic test.

A harmonic test gets its noise from the cycle-to-cycle scatter of the phase bins
(:mod:`chainid.gap.harmonic.prepare`).  A transient, random or seismic record has no repeated
cycle, so the noise is estimated from the record itself:

* **Force noise σ [N]** — the robust scale of the second difference of the force,
  σ = 1.4826·MAD(Δ²F)/√6.  White noise of standard deviation σ has
  var(Δ²F) = 6σ²; a force that is smooth on the sample scale (a band far below
  the Nyquist frequency) adds only (2π f/fs)⁴ of its own variance, and the few
  jumps of a friction force at reversals do not move a median.  This is the
  residual of a local quadratic fit over three samples.  The estimator is
  biased low when the force channel is low-pass filtered close to its own
  sampling rate (correlated noise); then the spectrum of the force above the
  excitation band (:func:`hf_floor`) is reported beside it.
  A **quantised** force channel (an ADC: every value a whole multiple of a step q,
  :func:`force_quantum`) has a lattice-valued Δ²F whose plain median is a whole number
  of steps (biased low or high by up to a step); there the MAD is the median of the
  grouped data (each lattice value spread over ±q/2), and σ includes the
  quantisation error (q²/12 of variance), which is part of the channel's noise.
* **Excitation band [Hz]** — the frequency below which ``BAND_FRACTION`` of the
  displacement's variance (linear trend removed, the flat noise floor of the
  spectrum's upper half subtracted) lies.
* **Plain smooth kinematics** (:func:`kinematics`) — x, ẋ, ẍ from a zero-phase low-pass (Butterworth,
  run forward and backward) of the measured x at ``CUT_FACTOR`` times the band, then central differences:
  the excitation passes unchanged, the displacement noise above it is removed
  before it can switch a memory operator (a false reversal) or be amplified by
  differentiation.  The diagnosis itself uses the estimator chosen by the record's own spectrum
  (:mod:`chainid.gap.core.kinematics`: spectral derivatives on a periodic record, the least-error low-pass
  otherwise, each with its predicted error); this one is the plain reference it is checked against.

Units: t s, x mm, F N, f Hz.
"""

from __future__ import annotations

import math

import numpy as np

#: the excitation band holds this fraction of the displacement's variance (above its noise floor)
BAND_FRACTION = 0.999
#: the kinematics low-pass sits this many times above the band edge (a 4th-order filter run twice is
#: down by < 1e-4 at the band edge)
CUT_FACTOR = 4.0


def force_noise(F: np.ndarray) -> float:
    """Force noise σ [N] of one record: 1.4826·MAD(Δ²F)/√6 (see the module docstring).

    Parameters
    ----------
    F : ndarray
        Force samples [N] (uniform sampling, >= 5 samples).
    """
    F = np.asarray(F, float)
    if F.size < 5:
        raise ValueError(f"force_noise needs >= 5 samples; got {F.size}")
    d2 = np.diff(F, 2)
    q = force_quantum(F)
    if q > 0:
        return 1.4826 * _grouped_mad(np.round(d2 / q).astype(np.int64)) * q / math.sqrt(6.0)
    mad = float(np.median(np.abs(d2 - np.median(d2))))
    return 1.4826 * mad / math.sqrt(6.0)


def force_quantum(F: np.ndarray) -> float:
    """The force channel's quantisation step q [N] (every sample a whole multiple of q plus one offset), or 0.

    Detected when the record has fewer distinct values than half its samples and the gaps between
    neighbouring distinct values up to 20 steps are whole multiples of the step within 0.1 of it (the values
    may be printed with a rounding of their own, e.g. a step of 3.5625 N written to 0.01 N).  q is the mean
    of the gaps within 1.5× the smallest.
    """
    u = np.unique(np.asarray(F, float))
    if u.size < 3 or u.size > 0.5 * np.asarray(F).size:
        return 0.0
    g = np.diff(u)
    if not g.min() > 0:
        return 0.0
    q = float(np.mean(g[g < 1.5 * g.min()]))
    r = g[g < 20 * q] / q
    return q if r.size >= 2 and bool(np.all(np.abs(r - np.round(r)) < 0.1)) else 0.0


def _grouped_mad(k: np.ndarray) -> float:
    """MAD [steps] of integer lattice data, each value spread uniformly over ±½ step (grouped-data median)."""
    med = _grouped_median(k)
    a = np.abs(k - med)  # half-integer or integer distances; group a covers [a − ½, a + ½] clipped at 0
    vals, cnt = np.unique(np.round(2 * a).astype(np.int64), return_counts=True)
    lo = np.maximum(vals / 2.0 - 0.5, 0.0)
    hi = vals / 2.0 + 0.5
    order = np.argsort(lo)
    lo, hi, cnt = lo[order], hi[order], cnt[order].astype(float)
    half = 0.5 * cnt.sum()
    c = np.cumsum(cnt)
    j = int(np.searchsorted(c, half))
    below = c[j] - cnt[j]
    return float(lo[j] + (half - below) / cnt[j] * (hi[j] - lo[j]))


def _grouped_median(k: np.ndarray) -> float:
    vals, cnt = np.unique(k, return_counts=True)
    c = np.cumsum(cnt).astype(float)
    half = 0.5 * c[-1]
    j = int(np.searchsorted(c, half))
    below = c[j] - cnt[j]
    return float(vals[j] - 0.5 + (half - below) / cnt[j])


def sample_rate(t: np.ndarray) -> float:
    """Sampling rate [Hz] from the median time step (t in s, increasing)."""
    dt = float(np.median(np.diff(np.asarray(t, float))))
    if not dt > 0:
        raise ValueError(f"t must be increasing; median time step {dt!r} s")
    return 1.0 / dt


def psd(y: np.ndarray, fs: float) -> tuple[np.ndarray, np.ndarray]:
    """Frequencies [Hz] and Hann-windowed periodogram (unnormalised power, the signal's unit squared) of ``y``
    sampled at ``fs`` [Hz], its linear trend removed (a shifted mean or a drift is not a band)."""
    y = np.asarray(y, float)
    n = y.size
    tt = np.arange(n)
    y = y - np.polyval(np.polyfit(tt, y, 1), tt)  # linear trend removed (a shifted mean is not a band)
    w = np.hanning(n)
    P = np.abs(np.fft.rfft(y * w)) ** 2
    f = np.fft.rfftfreq(n, 1.0 / fs)
    return f, P


def excitation_band(t: np.ndarray, x: np.ndarray) -> float:
    """Upper edge [Hz] of the displacement's band: ``BAND_FRACTION`` of its variance above the noise floor.

    The floor is the median power of the spectrum's upper half (a displacement excitation has no content
    there); a record whose spectrum is flat (no band) returns the Nyquist frequency.
    """
    fs = sample_rate(t)
    f, P = psd(x, fs)
    if f.size < 8:
        return 0.5 * fs
    floor = float(np.median(P[f.size // 2:]))
    Pc = np.maximum(P - floor, 0.0)
    Pc[0] = 0.0
    tot = float(Pc.sum())
    if tot <= 0:
        return 0.5 * fs
    k = int(np.searchsorted(np.cumsum(Pc) / tot, BAND_FRACTION))
    return float(min(max(f[min(k, f.size - 1)], f[1]), 0.5 * fs))


def hf_floor(t: np.ndarray, F: np.ndarray, f_band: float) -> float:
    """RMS [N] per unit bandwidth-equivalent σ of the force spectrum above ``CUT_FACTOR``·f_band: the white
    noise level σ that would give the median power there (an independent check of :func:`force_noise`;
    equal to it for white noise, larger when the force has broadband content, e.g. chatter)."""
    fs = sample_rate(t)
    f, P = psd(F, fs)
    m = f > CUT_FACTOR * f_band
    if m.sum() < 8:
        return float("nan")
    n = np.asarray(F).size
    w2 = float(np.sum(np.hanning(n) ** 2))
    # E|rfft(w·e)|² = σ²·Σw² for white e; the median of a χ²₂/2 variable is ln 2 of its mean
    return math.sqrt(float(np.median(P[m])) / (w2 * math.log(2.0)))


def lowpass_sos(fs: float, f_cut: float, n: int) -> np.ndarray | None:
    """Second-order sections of the 4th-order Butterworth low-pass at f_cut [Hz] for n samples at fs [Hz];
    None where a record is not smoothed (cut at or above 0.45·fs, or fewer than 30 samples)."""
    from scipy.signal import butter

    if f_cut >= 0.45 * fs or n < 30:
        return None
    return butter(4, f_cut / (0.5 * fs), output="sos")


def lowpass(y: np.ndarray, fs: float, f_cut: float) -> np.ndarray:
    """Zero-phase 4th-order Butterworth low-pass at f_cut [Hz] (forward-backward); identity at/above Nyquist."""
    from scipy.signal import sosfiltfilt

    y = np.asarray(y, float)
    sos = lowpass_sos(fs, f_cut, y.size)
    return y.copy() if sos is None else sosfiltfilt(sos, y)


def _noise_share(f: np.ndarray, g: np.ndarray, fs: float) -> float:
    """(2/fs)·∫₀^{fs/2} g df by trapezoids: the share of a white noise's variance passed by a power gain g(f)."""
    return 2.0 / fs * float(np.sum(0.5 * (g[1:] + g[:-1]) * np.diff(f)))


def _smoothing_gain(fs: float, f_cut: float, n: int) -> tuple[np.ndarray, np.ndarray] | None:
    """Frequencies [Hz] and power gain |H|² of the zero-phase low-pass :func:`lowpass` (None: no smoothing)."""
    from scipy.signal import sosfreqz

    sos = lowpass_sos(fs, f_cut, n)
    if sos is None:
        return None
    f, h = sosfreqz(sos, worN=8192, fs=fs)
    return f, np.abs(h) ** 2


def displacement_noise(x: np.ndarray, xs: np.ndarray, fs: float, f_cut: float) -> float:
    """Standard deviation σ_x [mm] of the white displacement noise of a record, from what the low-pass removed.

    x − xs = (1 − |H|²)·x (:func:`lowpass`, cut ``f_cut`` [Hz]) holds the noise above the band; its robust scale
    1.4826·MAD (an edge of the motion does not count) over the square root of the noise variance's share that
    passes 1 − |H|², (2/fs)·∫₀^{fs/2} (1 − |H(f)|²)² df, is σ_x.  0 when the record is not smoothed (cut at or
    above 0.45·fs) or has no displacement noise."""
    gain = _smoothing_gain(fs, f_cut, np.asarray(x).size)
    return 0.0 if gain is None else _sigma_x(x, xs, fs, *gain)


def _sigma_x(x: np.ndarray, xs: np.ndarray, fs: float, f: np.ndarray, h2: np.ndarray) -> float:
    """:func:`displacement_noise` with the low-pass's power gain ``h2`` at ``f`` [Hz] given."""
    r = np.asarray(x, float) - np.asarray(xs, float)
    return 1.4826 * float(np.median(np.abs(r - np.median(r)))) / math.sqrt(_noise_share(f, (1.0 - h2) ** 2, fs))


def velocity_noise(x: np.ndarray, xs: np.ndarray, fs: float, f_cut: float) -> float:
    """Standard deviation [mm/s] of the noise the displacement noise leaves in the smooth velocity.

    The displacement noise σ_x (white, :func:`displacement_noise`) passes, in band, the zero-phase Butterworth
    (gain |H|², :func:`lowpass`) and the central difference (gain fs·sin(2πf/fs)), so
    σ_v² = σ_x²·(2/fs)·∫₀^{fs/2} fs²·sin²(2πf/fs)·|H(f)|⁴ df.
    0 when the record is not smoothed (cut at or above 0.45·fs) or has no displacement noise.
    """
    gain = _smoothing_gain(fs, f_cut, np.asarray(x).size)
    if gain is None:
        return 0.0
    f, h2 = gain
    sig_x = _sigma_x(x, xs, fs, f, h2)
    return sig_x * math.sqrt(_noise_share(f, (fs * np.sin(2 * np.pi * f / fs)) ** 2 * h2 ** 2, fs))


#: a smooth speed within this many noise standard deviations of zero is no resolvable motion (a 4σ test)
REST_SIGMAS = 4.0


def kinematics(t: np.ndarray, x: np.ndarray, f_band: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Smooth x [mm], ẋ [mm/s], ẍ [mm/s²]: zero-phase low-pass at ``CUT_FACTOR``·f_band, then central
    differences on the record's own time stamps.

    Where the smooth speed is within ``REST_SIGMAS`` noise standard deviations of zero
    (:func:`velocity_noise`) the record shows no motion and ẋ is 0: a contact at rest (a record's lead-in, a
    stop) is stuck, so its Coulomb friction is not switched by the noise's sign (each false switch costs
    2·F_c) and no dashpot force is made of noise.  ẍ is the difference of the unzeroed ẋ.
    """
    fs = sample_rate(t)
    f_cut = CUT_FACTOR * f_band
    xs = lowpass(x, fs, f_cut)
    xd = np.gradient(xs, t)
    xdd = np.gradient(xd, t)
    v_n = velocity_noise(x, xs, fs, f_cut)
    if v_n > 0.0:
        xd = np.where(np.abs(xd) <= REST_SIGMAS * v_n, 0.0, xd)
    return xs, xd, xdd


def record_kinematics(t: np.ndarray, x: np.ndarray) -> tuple[float, np.ndarray, np.ndarray, np.ndarray]:
    """The excitation band [Hz] of a record and its smooth x, ẋ, ẍ (:func:`excitation_band`,
    :func:`kinematics`): what the time-domain route and ``predict`` evaluate a model on."""
    fb = excitation_band(t, x)
    return (fb, *kinematics(t, x, fb))


#: a steady harmonic test holds at least this share of its displacement variance within ± ``LINE_WIDTH`` of its
#: spectral peak (one sine, even with a taper or jitter); a record below it is not a harmonic test
LINE_SHARE = 0.2
LINE_WIDTH = 0.1


def is_broadband(t: np.ndarray, x: np.ndarray) -> bool:
    """Whether the displacement is clearly not one sine: less than ``LINE_SHARE`` of its variance (linear trend
    removed) within ± ``LINE_WIDTH`` (relative) of the spectral peak.  Such a record skips the harmonic
    estimate (it has no steady cycles to find) and goes straight to the time-domain route."""
    f, P = psd(x, sample_rate(t))
    if f.size < 8:
        return False
    P[0] = 0.0
    k = int(np.argmax(P))
    m = np.abs(f - f[k]) <= LINE_WIDTH * f[k] + (f[1] - f[0])
    return float(P[m].sum()) < LINE_SHARE * float(P.sum())
