"""Time-domain route of the diagnosis: a record that is not a steady harmonic test.

The model force is evaluated on the record's own samples with *causal* memory
operators (friction with stick, Dahl hysteresis, play run forward from a stated
initial state: the operator starts relaxed, z = 0 and the play centred, at the
first sample), so any excitation can be analysed: start-ups, load steps, sweeps,
band-limited random and seismic displacement.  The damping of a non-harmonic
record is viscous, c·ẋ (one c for the whole set); the rate-independent
dissipation is carried by the effects (friction, hysteresis).  A c_e(ω, A) law
has no meaning without a frequency and an amplitude.

Each record is cut into contiguous time blocks (never random samples): the units
of leave-one-block-out scoring and, with ``--holdout-blocks K``, of the held-out
set (the last of K blocks of each record).

Units: t s, x mm, ẋ mm/s, ẍ mm/s², F N.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Sequence

import numpy as np

from chainid.gap.core import noise as nz
from chainid.model.effects import STIFFNESS_SIDE, dahl_operator, modify_model, play_operator, stick_slip

#: fewest samples of a time-domain record
MIN_SAMPLES = 64
#: samples per period of the band edge kept by the fit subset (the score uses every sample)
FIT_SAMPLES_PER_PERIOD = 40
#: most samples per record in the fit subset
FIT_MAX = 4000


@dataclass
class TimeData:
    """One non-harmonic record prepared for the time-domain diagnosis (units mm, N, s, Hz)."""

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

    @property
    def omega(self) -> float:
        """Dominant angular frequency [rad/s] (peak of the displacement spectrum)."""
        f, P = nz._psd(self.x, self.fs)
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


def prepare_time(rec: Any, n_blocks: int = 4) -> TimeData:
    """Prepare one record for the time domain: band, smooth kinematics, force noise, blocks, fit subset.

    Parameters
    ----------
    rec : Record
        t [s] (increasing), x [mm], F [N].
    n_blocks : int
        Contiguous time blocks of the record (>= 1).

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
    fb, xs, xd, xdd = nz.record_kinematics(t, rec.x)
    F = np.asarray(rec.F, float)
    sigma = max(nz.force_noise(F), 1e-6 * float(np.std(F)) + 1e-9)
    block = np.minimum((np.arange(t.size) * n_blocks) // t.size, n_blocks - 1).astype(np.int64)
    q = max(1, min(int(fs / (FIT_SAMPLES_PER_PERIOD * fb)), int(math.ceil(t.size / FIT_MAX))))
    return TimeData(rec.test, t, xs, xd, xdd, F, np.asarray(rec.x, float), sigma, fb, fs,
                    nz.hf_floor(t, F, fb), block, n_blocks, np.arange(0, t.size, q, dtype=np.int64))


def effect_params(names_p: dict[str, float], name: str) -> dict[str, float]:
    """The parameters of one effect from a flat ``effect.param`` dict."""
    pre = name + "."
    return {k[len(pre):]: v for k, v in names_p.items() if k.startswith(pre)}


def undamped(names: Sequence[str], p: dict[str, float], model: Any, d: TimeData,
             idx: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Undamped model force [N] and the velocity the viscous damping acts on [mm/s], on the samples ``idx``
    (all when None) of a time-domain record.

    The memory operators always run over the whole record from its first sample (causal); only the output
    is taken at ``idx``.  Stiffness-side effects change the model first, the others act on the result
    (composition, as in the harmonic route); ``sensor_delay`` evaluates the whole model at t − τ.
    ``damping_law`` has no time-domain form and is ignored here.
    """
    rest = []
    for n in names:
        if n in STIFFNESS_SIDE:
            model = modify_model(n, effect_params(p, n), model)
        else:
            rest.append(n)
    t, x, xd, xdd = d.t, d.x, d.xd, d.xdd
    if "sensor_delay" in rest:
        tau = float(p.get("sensor_delay.tau", 0.0))
        ts = t - tau
        x, xd, xdd = np.interp(ts, t, x), np.interp(ts, t, xd), np.interp(ts, t, xdd)
    sel = slice(None) if idx is None else idx
    m = float(getattr(model, "mass_kg", 0.0))
    Fk = np.asarray(model.force(x[sel]), float)
    Fn = m * xdd[sel] * 1e-3 + Fk
    for n in rest:
        e = effect_params(p, n)
        if n == "friction":
            amp = e.get("F_c", 0.0) + e.get("mu", 0.0) * np.abs(Fk)
            Fn = Fn + amp * stick_slip(x, xd, e.get("x_s", 0.0), periodic=False)[sel]
        elif n == "hysteresis":
            Fn = Fn + dahl_operator(x, e.get("F_h", 0.0), e.get("x_h", 1.0), periodic=False)[sel]
        elif n == "backlash":
            xp = play_operator(x, 0.5 * e.get("b", 0.0), periodic=False)[sel]
            Fn = Fn - Fk + np.asarray(model.force(xp), float)
    return Fn, xd[sel]


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
