"""One record prepared for the time-domain route: band, smooth kinematics, noise, features, blocks, fit subset.

The model force is evaluated on the record's own samples with *causal* memory operators (run forward from a
stated initial state at the first sample), so any excitation can be analysed: start-ups, load steps, sweeps,
band-limited random and seismic displacement, resonant devices driven by a force.  The kinematics come from
:mod:`chainid.gap.core.kinematics` (the estimator chosen by the record's own spectrum, its error predicted).

Each record is cut into contiguous time blocks (never random samples): the units of leave-one-block-out scoring,
of resampling, and, with ``--holdout-blocks K``, of the held-out set (the last of K blocks of each record).

Record features (the damping law's variables): the band centre ω_c [rad/s] (the variance-weighted mean angular
frequency of the displacement, :func:`chainid.model.timedamping.record_features`; the frequency of a harmonic
test) and the amplitude A [mm] (half the range of the smooth x; the amplitude of a harmonic test).  A record's
covariates (operating conditions: coil current, pressure, ...) come with it.  A record whose motion has content
above ẍ's cut while its force has none is compared with the model below that cut (``f_res``, ``rho``:
:mod:`chainid.gap.timedomain.bandlimit`).

Units: t s, x mm, ẋ mm/s, ẍ mm/s², F N, f Hz.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Sequence

import numpy as np

from chainid.gap.core import noise as nz
from chainid.gap.core.kinematics import Kinematics, estimate
from chainid.gap.timedomain.bandlimit import noise_share, residual_cut
from chainid.model.timedamping import record_features

__all__ = ["MIN_SAMPLES", "TimeData", "prepare_time", "low_edge", "reversals",
           "travel_since_reversal", "split_blocks", "fit_subsets", "windows", "FIT_TOTAL"]

#: fewest samples of a time-domain record
MIN_SAMPLES = 64
#: samples per period of the band edge kept by the fit subset (the score uses every sample)
FIT_SAMPLES_PER_PERIOD = 40
#: most samples per record in the fit subset, unless the band needs more (``FIT_SAMPLES_PER_PERIOD``)
FIT_MAX = 4000
#: most samples of the fit subsets of all training records together (:func:`fit_subsets`)
FIT_TOTAL = 131_072
#: a thinned fit subset keeps whole windows of this many periods of the record's low band edge ...
FIT_WINDOW_PERIODS = 4
#: ... but at least this many windows per record (and one per block)
FIT_MIN_WINDOWS = 4


@dataclass
class TimeData:
    """One record prepared for the time-domain diagnosis (units mm, N, s, Hz): every per-sample array holds the
    record's interior (:func:`interior`: the ends, where the kinematics rest on the filters' padding, left out)."""

    __test__ = False
    test: str
    t: np.ndarray
    x: np.ndarray
    xd: np.ndarray
    xdd: np.ndarray
    F: np.ndarray
    x_meas: np.ndarray
    sigma: float
    f_band: float
    fs: float
    sigma_hf: float = float("nan")
    #: block index of every sample (0 … n_blocks − 1), contiguous in time
    block: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
    n_blocks: int = 1
    #: samples of the fit subset (every q-th sample)
    fit_idx: np.ndarray = field(default_factory=lambda: np.zeros(0, np.int64))
    kind: str = "time"
    kin: Kinematics | None = None
    covariates: dict[str, float] = field(default_factory=dict)
    omega_c: float = float("nan")
    #: the whole record's half range [mm] (a dashpot law's amplitude feature, read as ``predict`` reads it)
    A_c: float = float("nan")
    f_low: float = float("nan")
    #: the force is compared with the model below this cut [Hz] (NaN: the whole band; :mod:`.bandlimit`)
    f_res: float = float("nan")
    #: the share of the force noise's power the comparison keeps (1: the whole band)
    rho: float = 1.0
    #: σ [N] as read from the record's force alone, before a fitted chain's residual capped it (:mod:`.noisecheck`)
    sigma_read: float = float("nan")

    @property
    def omega(self) -> float:
        """Dominant angular frequency [rad/s] (peak of the displacement spectrum)."""
        f, P = nz.psd(self.x, self.fs)
        P[0] = 0.0
        return 2 * math.pi * float(f[int(np.argmax(P))])

    @property
    def A(self) -> float:
        """Half the displacement range [mm]."""
        return 0.5 * float(np.ptp(self.x))

    @property
    def x0(self) -> float:
        """Mean displacement [mm]."""
        return float(np.mean(self.x))

    @property
    def window(self) -> str:
        return f"time domain, {self.t.size} samples, band {self.f_band:.3g} Hz, {self.n_blocks} blocks"


def low_edge(t: np.ndarray, x: np.ndarray, fraction: float = 0.01) -> float:
    """The lower edge [Hz] of a displacement's band: the frequency below which ``fraction`` of its variance lies
    (the longest useful period is 1/low_edge)."""
    fs = nz.sample_rate(t)
    f, P = nz.psd(x, fs)
    if f.size < 8:
        return float(f[1]) if f.size > 1 else 0.0
    floor = float(np.median(P[f.size // 2:]))
    Pc = np.maximum(P - floor, 0.0)
    Pc[0] = 0.0
    tot = float(Pc.sum())
    if tot <= 0:
        return float(f[1])
    k = int(np.searchsorted(np.cumsum(Pc) / tot, fraction))
    return float(max(f[min(k, f.size - 1)], f[1]))


def interior(kin: Any, fs: float, n: int) -> tuple[int, int]:
    """The samples a … b − 1 of a record that are compared: all but :meth:`~chainid.gap.core.kinematics.Kinematics.
    edge_samples` at each end, where ẋ̂ rests on the filters' padding.  A sign taken there can be wrong for a
    sample or three where the motion leaves rest, each an error of up to 2·F_c in a friction force: on a noise-free
    start-up record those few samples had pulled F_c 1.15 % low.  At most the samples beyond :data:`MIN_SAMPLES`
    are left out."""
    e = min(kin.edge_samples(fs), max((n - MIN_SAMPLES) // 2, 0))
    return e, n - e


def prepare_time(rec: Any, n_blocks: int = 4, sigma_cap: float | None = None) -> TimeData:
    """Prepare one record for the time domain: band, smooth kinematics, force noise, features, blocks, fit subset.

    Parameters
    ----------
    rec : Record
        t [s] (increasing), x [mm], F [N]; its ``covariates`` (name → value) when it has them.
    n_blocks : int
        Contiguous time blocks of the record (>= 1).
    sigma_cap : float, optional
        An upper bound on the force noise σ [N]: the noise a fitted chain's residual leaves room for
        (:mod:`.noisecheck`); the σ read from the force is kept where it is smaller.

    Raises
    ------
    ValueError
        Too few samples, non-finite values or t not increasing (names the test and the value).
    """
    t = np.asarray(rec.t, float)
    if t.size < MIN_SAMPLES:
        raise ValueError(f"test {rec.test!r}: {t.size} samples; the time-domain route needs >= {MIN_SAMPLES}")
    if not (np.all(np.isfinite(rec.x)) and np.all(np.isfinite(rec.F)) and np.all(np.isfinite(t))):
        raise ValueError(f"test {rec.test!r}: non-finite t, x or F")
    if np.any(np.diff(t) <= 0):
        raise ValueError(f"test {rec.test!r}: t must be strictly increasing")
    n_blocks = int(n_blocks)
    if n_blocks < 1 or n_blocks > t.size // 16:
        raise ValueError(f"blocks per record = {n_blocks!r} is out of range for test {rec.test!r}; "
                         f"valid range 1 to {t.size // 16}")
    fs = nz.sample_rate(t)
    fb = nz.excitation_band(t, rec.x)
    kin = estimate(t, rec.x, fb)
    F = np.asarray(rec.F, float)
    sigma_hf = nz.hf_floor(t, F, fb)
    # two estimates of the force noise, each an upper bound where the other fails: the robust second difference
    # takes in a force curved on the sample scale (a record sampled a few times its band), the spectrum above the
    # band takes in broadband force content (friction switching); the smaller is the noise
    sigma = nz.force_noise(F)
    if math.isfinite(sigma_hf) and sigma_hf > 0:
        sigma = min(sigma, sigma_hf)
    sigma = sigma_read = max(sigma, 1e-6 * float(np.std(F)) + 1e-9)
    if sigma_cap is not None and math.isfinite(sigma_cap) and 0.0 < sigma_cap < sigma:
        sigma = float(sigma_cap)
    # the ends, where the kinematics rest on the padding, are estimated but not compared (:func:`interior`); the
    # record's features are the whole record's
    omega_c, A_c = record_features(t, kin.x)
    a, b = interior(kin, fs, t.size)
    kin = kin.trimmed(a, b)
    t, F, x_meas = t[a:b], F[a:b], np.asarray(rec.x, float)[a:b]
    xs, xd, xdd = kin.x, kin.xd, kin.xdd
    block = np.minimum((np.arange(t.size) * n_blocks) // t.size, n_blocks - 1).astype(np.int64)
    q = max(1, min(int(fs / (FIT_SAMPLES_PER_PERIOD * fb)), int(math.ceil(t.size / FIT_MAX))))
    cov = {str(k): float(v) for k, v in dict(getattr(rec, "covariates", None) or {}).items()}
    f_res = residual_cut(F, fs, kin.f_cut_a, sigma, kin.beyond_a)
    return TimeData(rec.test, t, xs, xd, xdd, F, x_meas, sigma, fb, fs,
                    sigma_hf, block, n_blocks, np.arange(0, t.size, q, dtype=np.int64), kin=kin,
                    covariates=cov, omega_c=omega_c, A_c=A_c, f_low=low_edge(t, xs), f_res=f_res,
                    rho=noise_share(fs, f_res), sigma_read=sigma_read)


def fit_subsets(data: Sequence[TimeData], train: dict[str, np.ndarray], total: int = FIT_TOTAL
                ) -> dict[str, tuple[np.ndarray, np.ndarray | None]]:
    """Each record's samples for the shape search, bounded so that the search's cost does not grow with the data.

    Parameters
    ----------
    data : the records
    train : per test, the boolean mask of its training samples
    total : the most samples of the training records' subsets together

    Returns
    -------
    dict
        Per test ``(idx, lead)``: the sample indices of the search's view, in order, and None or a boolean mask
        over them of lead-in samples, which the search weighs 0.

    A record with no training sample (held out whole) is weighed 0 in the search: its view is its first
    ``MIN_SAMPLES`` samples (nothing changes numerically).  When the training records' subsets
    (:attr:`TimeData.fit_idx`, up to ``FIT_SAMPLES_PER_PERIOD`` samples per period of the band edge) hold more
    than ``total`` samples together, each keeps the same fraction of its training subset as evenly spaced
    contiguous windows (:func:`windows`); the amplitudes and every score still use all samples.
    """
    out: dict[str, tuple[np.ndarray, np.ndarray | None]] = {}
    n = 0
    for d in data:
        tr = train[d.test]
        if not tr.any():
            out[d.test] = (d.fit_idx[:MIN_SAMPLES], None)
        else:
            out[d.test] = (d.fit_idx, None)
            n += int(np.count_nonzero(tr[d.fit_idx]))
    if n <= total:
        return out
    frac = total / n
    return {d.test: out[d.test] if not train[d.test].any() else windows(d, frac, train[d.test]) for d in data}


def windows(d: TimeData, frac: float, train: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A fraction ``frac`` of a record's training subset as evenly spaced contiguous windows, each after a lead-in.

    Windows: ``FIT_WINDOW_PERIODS`` periods of the low band edge long, but at least ``FIT_MIN_WINDOWS`` of them
    and at least one per block (and >= ``MIN_SAMPLES`` samples each), spread from the first training sample of the
    subset to the last.  The memory operators (friction with stick, Dahl, Bouc–Wen, play) run over the view in
    order, so a window would start from the state the previous one left; the ``lead`` samples before each
    window (one period of the band centre, where there is a gap) let the state forget that, and are weighed 0.
    Returns ``(idx, lead)`` as :func:`fit_subsets`.
    """
    idx = d.fit_idx[train[d.fit_idx]]
    keep = min(idx.size, max(int(frac * idx.size), MIN_SAMPLES))
    dt = float(d.t[idx[1]] - d.t[idx[0]]) if idx.size > 1 else 1.0
    per = FIT_WINDOW_PERIODS / d.f_low / dt if math.isfinite(d.f_low) and d.f_low > 0 else math.inf
    w = int(max(MIN_SAMPLES, min(per, keep // max(FIT_MIN_WINDOWS, d.n_blocks))))
    w = min(w, keep)
    n_win = max(1, keep // w)
    w = keep // n_win
    period = 2 * math.pi / d.omega_c / dt if math.isfinite(d.omega_c) and d.omega_c > 0 else MIN_SAMPLES
    n_lead = int(min(max(math.ceil(period), 1), w))
    starts = np.linspace(0, idx.size - w, n_win).astype(np.int64)
    pieces, leads, end = [], [], 0
    for s in starts:
        a = int(max(s - n_lead, end)) if s > end else int(s)  # no lead-in where the previous window ends here
        pieces.append(idx[a:s + w])
        leads.append(np.arange(a, s + w) < s)
        end = int(s + w)
    return np.concatenate(pieces), np.concatenate(leads)


def reversals(xd: np.ndarray) -> np.ndarray:
    """Indices where the smooth velocity changes sign (the sample after the change)."""
    s = np.sign(xd)
    nz_ = np.flatnonzero(s)
    if nz_.size < 2:
        return np.zeros(0, np.int64)
    ss = s[nz_]
    return nz_[1:][ss[1:] != ss[:-1]]


def travel_since_reversal(x: np.ndarray, xd: np.ndarray) -> np.ndarray:
    """|x − x at the last velocity reversal| [mm] per sample (from the first sample before any reversal)."""
    r = reversals(xd)
    start = np.zeros(x.size, np.int64)
    if r.size:
        start[r] = r
    start = np.maximum.accumulate(start)
    return np.abs(x - x[start])


def split_blocks(data: Sequence[TimeData], hold_ids: Sequence[str], holdout_blocks: int
                 ) -> tuple[list[tuple[TimeData, int]], list[tuple[TimeData, int]]]:
    """Training and held-out units (record, block): whole records in ``hold_ids`` are held out (all their
    blocks); with ``holdout_blocks`` > 0 the last block of every other record is held out too."""
    train, hold = [], []
    hs = set(hold_ids)
    for d in data:
        for b in range(d.n_blocks):
            if d.test in hs or (holdout_blocks > 0 and b == d.n_blocks - 1):
                hold.append((d, b))
            else:
                train.append((d, b))
    return train, hold
