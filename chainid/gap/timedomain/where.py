"""Where the model misses on a time-domain record: residual against the state, its spectrum, ringing, drift.

* **State maps.** The residual's means over quantile bins of x, ẋ, the travel since the last
  reversal and the load level (the model force).  The share of the residual variance a
  variable's bin means carry says what the miss follows: x → stiffness side, ẋ → damping
  or sliding friction, travel since reversal → memory (stick, hysteresis, play), load →
  load-dependent friction or stiffness.  A map counts when its bin-mean variance exceeds
  the noise's (σ²/n per bin) by ``Z_MAP`` standard errors.
* **Spectrum outside the band.** The residual's RMS above ``CUT_FACTOR``·band against
  white noise of the record's σ over the same bandwidth.
* **Ringing after reversals (stick-slip chatter).** The residual high-passed above the
  band while the contact slides (after breakaway, until it turns: |ẋ| above ``SLIDE`` of
  its 99th percentile) against the rest of the record (at rest, turning).  Ringing is a
  narrow spectral peak (``PEAK`` times the median power within ± one octave, and times the
  record's force-noise density 2σ²/fs, which the band-limited residual no longer shows; a step
  or a sloped spectrum gives 1–3) above 1.5× the cut, with ``RING_RATIO`` times the mean
  square elsewhere (a sensor resonance or mains hum is not tied to reversals).
  No library effect covers chatter: it is reported as such, never as an effect name.
* **Backbone after reversals** (model-free): the measured force change against the travel since
  the last reversal; a dead band then stiffening (play closing onto a contact) or stiff-then-soft
  (stick, pre-sliding) when the small-travel and large-travel slopes differ by ``BACKBONE``.
* **Drift.** Per record, the residual's means over ``N_DRIFT`` contiguous blocks are
  regressed on time with the block's mean x as a covariate
  (:func:`chainid.gap.core.stationarity.trend`): a slope over ``Z_TREND`` standard errors in at
  least a quarter of the records is a non-stationarity no static effect explains.

Units: mm, N, s, Hz.
"""

from __future__ import annotations

import bisect
import math
import warnings
from typing import Any, Sequence

import numpy as np

from chainid.gap.core.noise import CUT_FACTOR, lowpass
from chainid.gap.core.stationarity import Z_TREND, trend
from chainid.gap.timedomain.data import TimeData, travel_since_reversal

#: quantile bins of a state map
N_MAP = 16
#: standard errors of bin-mean variance over the noise for a state map to count
Z_MAP = 5.0
#: narrowband peak (peak / median power of the post-reversal spectrum) that makes ringing
PEAK = 10.0
#: post-reversal high-frequency mean square over the rest that makes ringing
RING_RATIO = 2.0
#: neighbourhood of a spectral peak: ± this factor in frequency (one octave each side)
OCT = 2.0
#: sliding: |ẋ| above this fraction of the record's 99th percentile of |ẋ|
SLIDE = 0.2
#: backbone slopes differing by this factor (small against large travel) make a finding
BACKBONE = 2.0
#: blocks per record of the drift test
N_DRIFT = 20

_HINT = {"x": "stiffness side (level, contact law, offset)", "xd": "damping or sliding friction (sgn ẋ)",
         "travel": "memory after reversals (stick, hysteresis, play)", "load": "load-dependent friction or stiffness"}
_NAME = {"x": "displacement x", "xd": "velocity ẋ", "travel": "travel since the last reversal",
         "load": "load level (model force)"}


def state_maps(data: Sequence[TimeData], res: dict[str, np.ndarray], force: dict[str, np.ndarray]) -> list[dict]:
    """Residual bin means against x, ẋ, travel since reversal and load (pooled over records)."""
    r = np.concatenate([res[d.test] for d in data])
    var = {"x": np.concatenate([d.x for d in data]), "xd": np.concatenate([d.xd for d in data]),
           "travel": np.concatenate([travel_since_reversal(d.x, d.xd) for d in data]),
           "load": np.concatenate([force[d.test] for d in data])}
    s2 = float(np.mean(np.concatenate([np.full(d.t.size, d.sigma**2) for d in data])))
    tot = float(np.var(r)) or 1e-300
    out = []
    for k, v in var.items():
        edges = np.unique(np.quantile(v, np.linspace(0, 1, N_MAP + 1)))
        if edges.size < 3:
            continue
        b = np.clip(np.searchsorted(edges, v, side="right") - 1, 0, edges.size - 2)
        cnt = np.bincount(b).astype(float)
        mean = np.bincount(b, weights=r) / np.maximum(cnt, 1)
        ok = cnt > 0
        between = float(np.sum(cnt[ok] * (mean[ok] - r.mean()) ** 2) / r.size)
        noise = s2 * ok.sum() / r.size  # expected between-bin variance of pure noise
        z = (between - noise) / (noise * math.sqrt(2.0 / max(ok.sum() - 1, 1)))
        centres = 0.5 * (edges[:-1] + edges[1:])
        if z >= Z_MAP:
            out.append({"finding": f"residual follows the {_NAME[k]}: bin means from {mean[ok].min():+.3g} to "
                        f"{mean[ok].max():+.3g} N carry {100 * between / tot:.0f} % of its variance "
                        f"(→ {_HINT[k]})", "kind": "state", "variable": k, "share": between / tot,
                        "bin_centres": [float(c) for c in centres[ok]], "bin_means_N": [float(m) for m in mean[ok]],
                        "score": math.sqrt(between)})
    return out


def spectrum_outside(data: Sequence[TimeData], res: dict[str, np.ndarray]) -> dict[str, Any]:
    """Residual RMS above CUT_FACTOR·band against white noise of σ over that bandwidth (pooled)."""
    num = den = 0.0
    for d in data:
        fc = CUT_FACTOR * d.f_band
        if fc >= 0.45 * d.fs:
            continue
        hp = res[d.test] - lowpass(res[d.test], d.fs, fc)
        num += float(np.sum(hp**2))
        den += d.sigma**2 * (1.0 - fc / (0.5 * d.fs)) * d.t.size
    if den <= 0:
        return {}
    ratio = math.sqrt(num / den)
    return {"finding": f"residual above {CUT_FACTOR:g}× the excitation band: RMS {ratio:.2f}× white noise of the "
            f"records' σ over that bandwidth" + (" (content outside the excitation's band: ringing, impacts, "
            "chatter or a sensor resonance)" if ratio > 1.5 else " (noise)"), "kind": "spectrum",
            "ratio_to_noise": ratio, "score": 0.0}


def _local_peak(f: np.ndarray, P: np.ndarray, fmin: float, floor: float = 0.0) -> tuple[float, float]:
    """Frequency [Hz] and height of the strongest narrow peak above fmin: power over the median power within
    ± one octave (a smooth or sloped spectrum gives ~1–3), or over ``floor`` [P's unit] where that is larger.
    ``f`` ascending; bins whose octave holds fewer than 5 bins are skipped; the first of equal heights wins."""
    f = np.asarray(f, float)
    P = np.asarray(P, float)
    ks = np.flatnonzero(f >= fmin)
    lo = np.searchsorted(f, f[ks] / OCT, side="left")
    hi = np.searchsorted(f, f[ks] * OCT, side="right")
    keep = hi - lo >= 5
    ks, lo, hi = ks[keep], lo[keep], hi[keep]
    if not ks.size:
        return (float("nan"), 0.0)
    r = P[ks] / np.maximum(np.maximum(sliding_median(P, lo, hi), floor), 1e-300)
    r = np.where(np.isnan(r), 0.0, r)  # a bin or window with NaN power is no peak (the old loop's comparison)
    j = int(np.argmax(r))
    return (float(f[ks[j]]), float(r[j])) if r[j] > 0.0 else (float("nan"), 0.0)


def sliding_median(values: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Median of ``values[lo[i]:hi[i]]`` for every i, with ``lo`` and ``hi`` non-decreasing (windows that slide
    one way): each value enters and leaves a sorted window once, O(n·w) moves in C instead of one
    ``np.median`` per window.  Same numbers as ``np.median`` (the mean of the two middle values of an even
    window); window edges are clipped to the array, and an empty window's median is NaN, as ``np.median``'s.

    Parameters
    ----------
    values : 1-D array (any unit)
    lo, hi : the windows' first index and one past their last, each non-decreasing

    Returns
    -------
    numpy.ndarray
        One median per window, in ``values``' unit.
    """
    arr = np.asarray(values, float)
    lo = np.clip(np.asarray(lo, int), 0, arr.size)
    hi = np.clip(np.asarray(hi, int), 0, arr.size)
    if not np.isfinite(arr).all() or np.any(hi <= lo):  # NaN or empty windows: one np.median per window (NaN there)
        with np.errstate(invalid="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            return np.array([np.median(arr[i:j]) if j > i else np.nan for i, j in zip(lo, hi)])
    vals = arr.tolist()
    window: list[float] = []
    a = b = 0
    out = np.empty(len(lo))
    for i, (l_i, h_i) in enumerate(zip(np.asarray(lo).tolist(), np.asarray(hi).tolist())):
        if l_i >= b:  # the new window does not overlap the old one
            window, a, b = [], l_i, l_i
        while b < h_i:
            bisect.insort(window, vals[b])
            b += 1
        while a < l_i:
            del window[bisect.bisect_left(window, vals[a])]
            a += 1
        n = len(window)
        out[i] = window[n // 2] if n % 2 else 0.5 * (window[n // 2 - 1] + window[n // 2])
    return out


def ringing(data: Sequence[TimeData], res: dict[str, np.ndarray]) -> dict[str, Any]:
    """Narrowband ringing of the residual while the contact slides after a reversal (stick-slip chatter), or {}.

    Per record: the residual high-passed above ``CUT_FACTOR``·band; sliding samples (|ẋ| >= ``SLIDE``× its
    99th percentile) against the rest (at rest, turning).  Ringing = a narrow peak (``PEAK``× the local
    median, and × the force noise's density 2σ²/fs over the sliding share of the samples) of the sliding
    residual's spectrum above 1.5× the cut, with its mean square ``RING_RATIO``× the rest's.
    """
    from scipy.signal import welch

    best: dict[str, Any] = {}
    for d in data:
        fc = CUT_FACTOR * d.f_band
        if fc >= 0.2 * d.fs:
            continue
        hp = res[d.test] - lowpass(res[d.test], d.fs, fc)
        # sliding: the travel between reversals (stick-slip chatter starts at breakaway and lasts while the
        # contact slides); at rest or turning: the rest
        v99 = float(np.quantile(np.abs(d.xd), 0.99))
        inwin = np.abs(d.xd) >= SLIDE * v99
        if inwin.all() or not inwin.any():
            continue
        post = float(np.mean(hp[inwin] ** 2))
        rest = float(np.mean(hp[~inwin] ** 2))
        nper = int(min(hp.size, 2 ** int(math.ceil(math.log2(16 * d.fs / fc)))))
        f, P = welch(np.where(inwin, hp, 0.0), d.fs, nperseg=nper)
        # the neighbourhood a peak must stand out of includes the record's own force noise (white, σ² over fs/2,
        # present in the sliding share of the samples): the residual is of the band-limited force, and a ring
        # below the noise the raw record carries at its frequency cannot be told from the processing's own
        fk, peak = _local_peak(f, P, 1.5 * fc, floor=float(np.mean(inwin)) * 2.0 * d.sigma**2 / d.fs)
        ratio = post / rest if rest > 0 else float("inf")
        row = {"test": d.test, "frequency_Hz": fk, "peak_ratio": peak, "ratio": ratio, "rms_N": math.sqrt(post),
               "chatter": bool(peak >= PEAK and ratio >= RING_RATIO)}
        if not best or (row["chatter"], row["rms_N"]) > (best["chatter"], best["rms_N"]):
            best = row
    if not best:
        return {}
    if best["chatter"]:
        txt = (f"ringing while sliding after reversals at {best['frequency_Hz']:.3g} Hz in test {best['test']} (RMS "
               f"{best['rms_N']:.3g} N, {best['ratio']:.1f}× the mean square elsewhere, narrow spectral peak "
               f"{best['peak_ratio']:.0f}× its neighbourhood and the force noise): stick-slip chatter — no library "
               "effect covers it, so it is reported, not named")
    else:
        txt = (f"no ringing after reversals (sliding high-frequency residual {best['ratio']:.2f}× elsewhere, "
               f"largest narrow peak {best['peak_ratio']:.1f}× its neighbourhood and the force noise)")
    return best | {"finding": txt, "kind": "chatter" if best["chatter"] else "ringing",
                   "score": best["rms_N"] if best["chatter"] else 0.0}


def backbone(data: Sequence[TimeData]) -> list[dict[str, Any]]:
    """Model-free backbone after reversals, per record: the measured force change |F − F_rev| against the travel
    |x − x_rev| since the last velocity reversal.

    k_small is the secant over the first quarter of the travels (travel up to its 25th percentile T25),
    k_large the slope from T25 to T75 (75th percentile), each from the median |ΔF| in a window of ± 5
    percentiles of travel.  k_small/k_large <= 1/``BACKBONE``: a dead band then stiffening (play closing
    onto a contact); >= ``BACKBONE``: stiff at small travel then softer (stick / pre-sliding, then sliding).
    """
    out = []
    for d in data:
        tr = travel_since_reversal(d.x, d.xd)
        dF = np.abs(d.F - d.F[_last_reversal(d.xd)])
        m = tr > 0
        if m.sum() < 200:
            continue
        tr, dF = tr[m], dF[m]
        q = np.quantile(tr, [0.2, 0.25, 0.3, 0.7, 0.75, 0.8])
        f25 = float(np.median(dF[(tr >= q[0]) & (tr <= q[2])]))
        f75 = float(np.median(dF[(tr >= q[3]) & (tr <= q[5])]))
        T25, T75 = float(q[1]), float(q[4])
        if not (T25 > 0 and T75 > T25):
            continue
        k_small, k_large = f25 / T25, (f75 - f25) / (T75 - T25)
        ratio = k_small / k_large if k_large > 0 else float("inf")
        if ratio <= 1.0 / BACKBONE:
            kind = (f"a dead band then stiffening: {k_small:.3g} N/mm over the first {T25:.3g} mm of travel after a "
                    f"reversal, {k_large:.3g} N/mm beyond (play closing onto a contact)")
        elif ratio >= BACKBONE:
            kind = (f"stiff at small travel then softer: {k_small:.3g} N/mm up to {T25:.3g} mm after a reversal, "
                    f"{k_large:.3g} N/mm beyond (stick / pre-sliding, then sliding)")
        else:
            continue
        out.append({"finding": f"test {d.test}: the measured force after reversals shows {kind}", "kind": "backbone",
                    "test": d.test, "k_small_N_per_mm": k_small, "k_large_N_per_mm": k_large, "travel_T25_mm": T25,
                    "travel_T75_mm": T75, "ratio": ratio, "score": 0.0})
    return out


def _last_reversal(xd: np.ndarray) -> np.ndarray:
    """Index of the last velocity reversal at or before each sample (0 before the first)."""
    from chainid.gap.timedomain.data import reversals

    start = np.zeros(xd.size, np.int64)
    r = reversals(xd)
    if r.size:
        start[r] = r
    return np.maximum.accumulate(start)


def drift(data: Sequence[TimeData], res: dict[str, np.ndarray]) -> dict[str, Any]:
    """Trend of the residual's block means over time per record (covariate: the block's mean x)."""
    rows = []
    for d in data:
        nb = min(N_DRIFT, d.t.size // 32)
        if nb < 6:
            continue
        b = np.minimum((np.arange(d.t.size) * nb) // d.t.size, nb - 1)
        cnt = np.bincount(b).astype(float)
        tm = np.bincount(b, weights=d.t) / cnt
        rm = np.bincount(b, weights=res[d.test]) / cnt
        xm = np.bincount(b, weights=d.x) / cnt
        sl, se, chg = trend(tm, rm, xm, d.sigma / math.sqrt(float(cnt.mean())))
        rows.append({"test": d.test, "slope_N_per_s": sl, "z": abs(sl) / se if se > 0 else float("inf"),
                     "change_N": chg})
    if not rows:
        return {"stationary": None, "trend_change_N": 0.0, "z": 0.0, "tests": [],
                "finding": "stationarity not checked: records too short for the drift test"}
    sig = [r for r in rows if r["z"] >= Z_TREND]
    stationary = len(sig) < max(1, math.ceil(0.25 * len(rows)))
    chg = math.sqrt(float(np.mean([r["change_N"] ** 2 if r["z"] >= Z_TREND else 0.0 for r in rows])))
    zmax = max(r["z"] for r in rows)
    finding = ("the residual is stationary over each record (no significant drift of its block means)" if stationary
               else f"non-stationary: the residual drifts with time in {len(sig)} of {len(rows)} records (change "
               f"{chg:.3g} N RMS over records, up to {zmax:.1f} standard errors) beyond what x explains: drift, "
               "relaxation, heating or wear, which no static library effect explains")
    return {"stationary": stationary, "trend_change_N": chg, "z": zmax, "tests": rows, "finding": finding}


def localise_time(data: Sequence[TimeData], res: dict[str, np.ndarray], force: dict[str, np.ndarray]
                  ) -> list[dict[str, Any]]:
    """Ranked time-domain findings on a residual (largest first): level, state maps, spectrum, ringing."""
    r = np.concatenate([res[d.test] for d in data])
    sig = math.sqrt(float(np.mean(np.concatenate([np.full(d.t.size, d.sigma**2) for d in data]))))
    rms = math.sqrt(float(np.mean(r**2)))
    out = [{"finding": f"time-domain residual RMS {rms:.4g} N, {20 * math.log10(max(rms, 1e-300) / max(sig, 1e-300)):.1f}"
            f" dB over the noise σ {sig:.3g} N (σ from the records' own second differences)", "kind": "level",
            "rms_N": rms, "noise_floor_N": sig, "score": rms}]
    out += state_maps(data, res, force)
    sp = spectrum_outside(data, res)
    if sp:
        out.append(sp)
    rg = ringing(data, res)
    if rg:
        out.append(rg)
    out += backbone(data)
    out.sort(key=lambda f: -f.get("score", 0.0))
    return out
