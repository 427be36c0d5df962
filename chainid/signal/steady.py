"""Steady-state whole cycles of a harmonic displacement record.

Cycle k spans ``omega t + theta`` in [2 pi k, 2 pi (k+1)); every whole cycle is
fitted at fixed omega (mean, drift, amplitude), all at once in O(N)
(:func:`_cycle_stats` on :func:`chainid.signal.cycles.segment_lstsq`), and :func:`select_steady` keeps the longest contiguous
run of cycles whose amplitude and mean stay on the plateau.

Units: t [s], x [mm], omega [rad/s], theta [rad].
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from chainid.signal.cycles import segment_lstsq

__all__ = ["SteadyWindow", "select_steady", "steady_tolerance", "TOL_FLOOR", "TOL_MAX", "MIN_KEPT"]


@dataclass
class SteadyWindow:
    """The steady-state whole cycles kept for identification.

    Attributes
    ----------
    t_start, t_end : float
        Kept time window [s]; it spans exactly ``len(cycles_kept)`` periods.
    cycles_kept : list of int
        Indices of the kept cycles (0 = first whole cycle in the record).
    n_cycles_total : int
        Whole cycles found in the record.
    cycle_amplitudes : list of float
        Amplitude of every whole cycle [mm] (fixed-frequency fit per cycle).
    cycle_means : list of float
        Mean of every whole cycle [mm].
    plateau_A : float
        Plateau amplitude [mm] the cycles were compared with.
    rel_tol : float
        Relative tolerance actually used for "within the plateau" (amplitude,
        mean and drift per period, as fractions of the plateau amplitude).
    requested_tol : float or None
        The tolerance asked for; None = adaptive (see :func:`steady_tolerance`).
    scatter : float
        Robust cycle-to-cycle scatter of the record (relative to the plateau
        amplitude; NaN if fewer than 3 whole cycles).
    reason : str
        Why this tolerance and window were chosen (one line).
    n_cycles_start : int
        Cycles kept at the starting tolerance, before any widening (the
        harmonic estimate compares candidate fits on this first).
    """

    t_start: float
    t_end: float
    cycles_kept: list[int]
    n_cycles_total: int
    cycle_amplitudes: list[float]
    cycle_means: list[float]
    plateau_A: float
    rel_tol: float
    requested_tol: float | None = 0.03
    scatter: float = float("nan")
    reason: str = ""
    n_cycles_start: int = -1

    @property
    def n_cycles(self) -> int:
        """Number of kept whole cycles."""
        return len(self.cycles_kept)

    def describe(self) -> str:
        """One-line human-readable description of the choice."""
        if not self.cycles_kept:
            return "no steady cycles"
        return (
            f"cycles {self.cycles_kept[0]}-{self.cycles_kept[-1]} of {self.n_cycles_total} "
            f"(t = {_t_text(self.t_start, self)}..{_t_text(self.t_end, self)} s)"
        )

    def statement(self) -> str:
        """What was kept and why: window, cycles, tolerance used (one line)."""
        tol = f"{100 * self.rel_tol:.3g} %"
        kind = "given" if self.requested_tol is not None else "adaptive"
        core = f"{self.describe()}, {self.n_cycles} cycle(s) kept, tolerance {tol} ({kind})"
        return f"{core}: {self.reason}" if self.reason else core

    def to_dict(self) -> dict:
        def fin(v: float) -> float | None:
            return v if math.isfinite(v) else None

        return {
            "t_start": self.t_start,
            "t_end": self.t_end,
            "cycles_kept": list(self.cycles_kept),
            "n_cycles_total": self.n_cycles_total,
            "plateau_A": self.plateau_A,
            "rel_tol": self.rel_tol,
            "requested_tol": self.requested_tol,
            "scatter": fin(self.scatter),
            "reason": self.reason,
        }


def _t_text(v: float, win: SteadyWindow) -> str:
    """A window time [s] with 4 significant digits of the window's span (Unix times too: 1700000002..)."""
    span = abs(win.t_end - win.t_start)
    extra = max(0, math.floor(math.log10(max(abs(win.t_start), abs(win.t_end)) / span))) if span > 0 else 0
    return f"{v:.{4 + min(extra, 12)}g}"


def _cycle_stats(
    t: np.ndarray, x: np.ndarray, omega: float, theta: float
) -> tuple[list[float], np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Per whole cycle: fit x = c0 + slope (t - tc) + a sin psi + b cos psi at fixed omega.

    Cycle k spans ``omega t + theta`` in [2 pi k, 2 pi (k+1)); all cycles are
    fitted at once (:func:`chainid.signal.cycles.segment_lstsq`), so the cost is O(N) in the number of samples.

    Returns
    -------
    bounds : list of float
        Cycle boundaries [s] (n + 1 values).
    amps, means, drifts, resid_sd : ndarray
        Amplitude [mm], mean [mm], drift per period [mm] and residual SD [mm];
        0, NaN, inf, NaN for an incomplete cycle (< 6 samples or a gap).
    n_in : ndarray of int
        Samples per cycle.
    """
    T = 2 * math.pi / omega
    psi0 = omega * t[0] + theta
    psi1 = omega * t[-1] + theta
    dt_med = float(np.median(np.diff(t))) if t.size > 1 else T
    # a sample within 1e-3 of a sampling step of a boundary is on it: the time stamps' own resolution
    # (2.4e-7 s for Unix time ~1.7e9 s) must not move the first or last whole cycle out of the record
    eps_t = max(1e-3 * dt_med, 1e-9 * T)
    eps_k = eps_t / T
    k0 = math.ceil(psi0 / (2 * math.pi) - eps_k)
    # last boundary: a cycle is whole if its last sample (one step before the boundary) is present
    k1 = math.floor((psi1 + 1.5 * omega * dt_med) / (2 * math.pi) + eps_k)
    if k1 - k0 > t.size:  # more cycles than samples: omega is above the sampling's Nyquist frequency
        raise ValueError(f"omega = {omega:.6g} rad/s gives {k1 - k0} cycles over {t.size} samples; valid: below "
                         f"the Nyquist frequency pi/dt = {math.pi / dt_med:.6g} rad/s")
    ks = np.arange(k0, k1 + 1, dtype=float)
    b_arr = (2 * math.pi * ks - theta) / omega
    bounds = [float(v) for v in b_arr]
    n = max(len(bounds) - 1, 0)
    if n == 0:
        e = np.zeros(0)
        return bounds, e, e, e, e, np.zeros(0, dtype=int)
    idx = np.searchsorted(t, b_arr - eps_t, side="left")
    lo, hi = idx[:-1], idx[1:]
    n_in = (hi - lo).astype(int)
    span = np.where(n_in > 0, t[np.maximum(hi - 1, 0)] - t[np.minimum(lo, t.size - 1)], -np.inf)
    valid = (n_in >= 6) & (span >= T - 2.5 * dt_med)
    sl = slice(int(lo[0]), int(hi[-1]))
    ts, xs = t[sl], x[sl]
    seg = np.repeat(np.arange(n), n_in)
    tc = 0.5 * (b_arr[:-1] + b_arr[1:])
    u = (ts - tc[seg]) / T  # in [-0.5, 0.5): well scaled against sin/cos
    ph = omega * ts + theta
    beta, rss = segment_lstsq(seg, n, (np.ones_like(ts), u, np.sin(ph), np.cos(ph)), (xs,), valid, rss=True)
    beta, rss = beta[:, :, 0], rss[:, 0]
    nf = np.maximum(n_in, 1).astype(float)
    amps = np.where(valid, np.hypot(beta[:, 2], beta[:, 3]), 0.0)
    means = np.where(valid, beta[:, 0], np.nan)
    drifts = np.where(valid, np.abs(beta[:, 1]), np.inf)  # slope [mm/s] * T = coefficient of u
    resid_sd = np.where(valid, np.sqrt(rss / nf), np.nan)
    return bounds, amps, means, drifts, resid_sd, n_in


def _count_near(values: np.ndarray, half_width: np.ndarray | float) -> np.ndarray:
    """For each value v: how many values lie within ``half_width`` (per value, or one for all) of it (O(n log n))."""
    srt = np.sort(values)
    return np.searchsorted(srt, values + half_width, side="right") - np.searchsorted(srt, values - half_width,
                                                                                     side="left")


def _count_within(amps: np.ndarray, rel_tol: float) -> np.ndarray:
    """For each amplitude a > 0: how many amplitudes lie within ``rel_tol * a`` of it (O(n log n))."""
    return np.where(amps > 0, _count_near(amps, rel_tol * amps), 0)


def select_steady(
    t: np.ndarray,
    x: np.ndarray,
    omega: float,
    theta: float,
    *,
    rel_tol: float | None = 0.03,
    drop_first: bool = True,
    drift_tol: float | None = None,
) -> SteadyWindow:
    """Select the steady-state whole cycles of a harmonic displacement record.

    Cycle k spans ``omega t + theta`` in [2 pi k, 2 pi (k+1)).  For every whole
    cycle inside the record, mean, drift and amplitude are fitted at fixed
    ``omega``.  The plateau amplitude is the median amplitude of the largest
    group of cycles that agree within the tolerance; a cycle is steady when its
    amplitude is within ``tol`` of the plateau, its mean within ``tol * plateau``
    of the median steady mean and its drift per period below ``tol * plateau``;
    each tolerance is widened by four standard errors of the per-cycle
    estimate, from the median per-cycle residual (so measurement noise does not
    break the run).  The longest contiguous run of steady cycles is kept and,
    if ``drop_first``, its first cycle is dropped (transient after the ramp).

    With ``rel_tol=None`` the tolerance adapts to the record
    (:func:`steady_tolerance`): ``tol = clip(4 * scatter, 3 %, 15 %)`` from the
    record's robust cycle-to-cycle scatter (:func:`_scatter`: second
    differences of the per-cycle amplitude and mean, MAD; the 3 % floor when
    fewer than 7 plateau cycles).  A clean record thus keeps the historical 3 %.
    If no cycle is steady at that tolerance (fewer than :data:`MIN_KEPT`), it is
    widened by factors of 1.5 up to 15 % until a window is usable (the longest
    usable window rather than none).  ``SteadyWindow.reason`` says which.

    Parameters
    ----------
    t : ndarray
        Time [s].
    x : ndarray
        Elongation [mm].
    omega : float
        Angular frequency [rad/s], > 0.
    theta : float
        Phase of x = x0 + A sin(omega t + theta) [rad].
    rel_tol : float or None
        Relative tolerance on amplitude and mean (default 0.03 = 3 %); None =
        adaptive.  A given value must be in (0, 1).
    drop_first : bool
        Drop the first cycle of the steady run (default True).
    drift_tol : float, optional
        Relative tolerance on the drift per period (default: the tolerance).

    Returns
    -------
    SteadyWindow
        ``cycles_kept`` may be empty if there are no steady cycles.
    """
    if not omega > 0:
        raise ValueError(f"omega = {omega!r} rad/s is invalid: must be > 0")
    if rel_tol is not None and not (0.0 < rel_tol < 1.0):
        raise ValueError(f"steady tolerance rel_tol = {rel_tol!r} is invalid: must be in (0, 1) (e.g. 0.03 = 3 %)")
    stats = _cycle_stats(t, x, omega, theta)
    scatter = _scatter(stats[1], stats[2], _amp_floor(stats[4], stats[5]))
    if rel_tol is not None:
        return _select_given(t, stats, scatter, rel_tol, drop_first, drift_tol)
    return _select_adaptive(t, stats, scatter, drop_first, drift_tol)


def _select_given(t: np.ndarray, stats: tuple, scatter: float, rel_tol: float, drop_first: bool,
                  drift_tol: float | None) -> SteadyWindow:
    """:func:`select_steady` at the given tolerance ``rel_tol`` (a fraction), with the record's ``scatter`` noted."""
    win = _select_with_tol(t, stats, rel_tol, drop_first, drift_tol)
    win.n_cycles_start = win.n_cycles
    win.requested_tol = rel_tol
    win.scatter = scatter
    win.reason = "tolerance given"
    return win


def _tolerance_reason(scatter: float, tol0: float) -> str:
    """Why the adaptive tolerance ``tol0`` (a fraction) is what it is: the scatter's multiple, the floor or the cap."""
    why = (f"4 x cycle-to-cycle scatter {100 * scatter:.3g} %" if math.isfinite(scatter)
           else f"too few cycles to measure the scatter (< {MIN_TRIPLES + 2} on the plateau)")
    if not math.isfinite(scatter):
        why = f"floor {100 * TOL_FLOOR:g} % ({why})"
    elif tol0 <= TOL_FLOOR:
        why = f"floor {100 * TOL_FLOOR:g} % ({why} is smaller)"
    elif tol0 >= TOL_MAX:
        why = f"cap {100 * TOL_MAX:g} % ({why})"
    return why


def _select_adaptive(t: np.ndarray, stats: tuple, scatter: float, drop_first: bool,
                     drift_tol: float | None) -> SteadyWindow:
    """:func:`select_steady` at the tolerance from the record's ``scatter`` (:func:`steady_tolerance`), widened by
    factors of 1.5 up to :data:`TOL_MAX` while fewer than :data:`MIN_KEPT` cycles are kept."""
    tol0 = steady_tolerance(scatter)
    why = _tolerance_reason(scatter, tol0)
    win = _select_with_tol(t, stats, tol0, drop_first, drift_tol)
    win.reason = f"tolerance from the record: {why}"
    n_start = win.n_cycles
    tol = tol0
    while win.n_cycles < MIN_KEPT and tol < TOL_MAX:
        tol = min(tol * 1.5, TOL_MAX)
        w2 = _select_with_tol(t, stats, tol, drop_first, drift_tol)
        if w2.n_cycles > win.n_cycles:
            w2.reason = (f"widened to {100 * tol:.3g} %: no steady cycle within {100 * tol0:.3g} % "
                         f"({why})")
            win = w2
    win.requested_tol = None
    win.scatter = scatter
    win.n_cycles_start = n_start
    return win


#: Adaptive steady tolerance: floor (never tighter than the historical 3 %), cap (beyond
#: 15 % a cycle is not "steady"), scatter multiple, and the cycles a usable window keeps.
TOL_FLOOR = 0.03
TOL_MAX = 0.15
TOL_K = 4.0
MIN_KEPT = 1
#: Second differences needed for a scatter estimate (7 consecutive candidate cycles).
MIN_TRIPLES = 5


def steady_tolerance(scatter: float) -> float:
    """Adaptive steady tolerance ``clip(TOL_K * scatter, TOL_FLOOR, TOL_MAX)`` (fractions).

    Parameters
    ----------
    scatter : float
        Robust relative cycle-to-cycle scatter (:func:`_scatter`); NaN -> the floor.
    """
    if not math.isfinite(scatter):
        return TOL_FLOOR
    return float(min(max(TOL_K * scatter, TOL_FLOOR), TOL_MAX))


def _amp_floor(sds: np.ndarray, n_in: np.ndarray) -> np.ndarray:
    """Per cycle: the amplitude [mm] not distinguishable from zero (4 standard errors of the per-cycle fit).

    A cycle below it (the ramp of a record whose time stamps are quantised, e.g. Unix time ~1.7e9 s with a
    resolution of 2.4e-7 s) shows no oscillation, however well such cycles agree with each other.
    """
    s_med = float(np.nanmedian(sds)) if np.any(np.isfinite(sds)) else 0.0
    return 4.0 * s_med * np.sqrt(2.0 / np.maximum(n_in.astype(float), 1.0))


def _plateau(amps: np.ndarray, rel_tol: float, floor: np.ndarray | float = 0.0) -> float:
    """The amplitude most cycles agree with within ``rel_tol`` (ties -> the larger one) [mm]; 0 if none.

    Cycles with an amplitude at or below ``floor`` [mm] (no oscillation, see :func:`_amp_floor`) are no
    candidates.
    """
    amps = np.where(amps > floor, amps, 0.0)
    counts = _count_within(amps, rel_tol)
    if amps.size == 0 or counts.max() <= 0:
        return 0.0
    best_i = max(range(amps.size), key=lambda i: (counts[i], amps[i]))
    near = np.abs(amps - amps[best_i]) <= rel_tol * amps[best_i]
    return float(np.median(amps[near]))


def _mean_reference(means: np.ndarray, ok: np.ndarray, width: float) -> float:
    """The cycle mean [mm] most of the cycles ``ok`` agree with within ``width`` [mm] (ties -> the later cycle: a
    steady state follows its ramp), the median of that group.  A mean-load ramp that takes more cycles than the hold
    after it has no two cycles alike, so it cannot outvote the hold (the median of every cycle's mean could sit
    mid-ramp, away from all of them)."""
    idx = np.flatnonzero(ok)
    m = means[idx]
    counts = _count_near(m, width)
    best = max(range(idx.size), key=lambda i: (counts[i], idx[i]))
    return float(np.median(m[np.abs(m - m[best]) <= width]))


def _scatter(amps: np.ndarray, means: np.ndarray, floor: np.ndarray | float = 0.0) -> float:
    """Robust cycle-to-cycle scatter of amplitude and mean, relative to the plateau amplitude.

    Only cycles near the plateau count (amplitude within ``2 * TOL_MAX`` of the
    plateau found at ``TOL_MAX``: ramp, lead-in and taper cycles are not
    candidates).  From the second differences ``d_k = v_{k+1} - 2 v_k + v_{k-1}``
    over runs of three consecutive candidate cycles: a steady taper, ramp or
    drift (linear in k) cancels, so only the jitter is measured; for
    independent jitter of SD sigma, ``var(d) = 6 sigma^2``, hence
    ``sigma = 1.4826 * MAD(d) / sqrt(6)`` (the MAD ignores the few cycles at a
    corner of the envelope).  The larger of the amplitude and mean values,
    divided by the plateau; NaN (-> the 3 % floor) if fewer than :data:`MIN_TRIPLES`
    such triples: a MAD of 3 or 4 values measures the envelope's corners, not the jitter.
    """
    ref = _plateau(amps, TOL_MAX, floor)
    if not ref > 0:
        return float("nan")
    ok = (amps > floor) & (np.abs(amps - ref) <= 2 * TOL_MAX * ref)
    trip = ok[2:] & ok[1:-1] & ok[:-2]
    if trip.sum() < MIN_TRIPLES:
        return float("nan")
    out = 0.0
    for v in (amps, means):
        d = (v[2:] - 2.0 * v[1:-1] + v[:-2])[trip]
        mad = float(np.median(np.abs(d - np.median(d))))
        out = max(out, 1.4826 * mad / math.sqrt(6.0) / ref)
    return out


def _select_with_tol(
    t: np.ndarray,
    stats: tuple,
    rel_tol: float,
    drop_first: bool,
    drift_tol: float | None,
) -> SteadyWindow:
    """:func:`select_steady` at a fixed tolerance on precomputed cycle statistics."""
    bounds, amps_a, means_a, drifts_a, sds, nn_i = stats
    n = amps_a.size
    if n == 0:
        return SteadyWindow(float(t[0]), float(t[0]), [], 0, [], [], 0.0, rel_tol)
    amps = amps_a.tolist()
    means = means_a.tolist()
    # measurement-noise allowance: 4 standard errors of the per-cycle estimates, from the
    # median residual over the cycles (robust to the few transient cycles)
    s_med = float(np.nanmedian(sds)) if np.any(np.isfinite(sds)) else 0.0
    nn = np.maximum(nn_i.astype(float), 1.0)
    se_amp = 4.0 * s_med * np.sqrt(2.0 / nn)
    se_mean = 4.0 * s_med / np.sqrt(nn)
    se_drift = 4.0 * s_med * np.sqrt(12.0 / nn)
    # plateau: the amplitude most cycles agree with (ties -> the larger one)
    plateau = _plateau(amps_a, rel_tol, _amp_floor(sds, nn_i))
    ok_amp = (np.abs(amps_a - plateau) <= rel_tol * plateau + se_amp) & (amps_a > 0)
    if ok_amp.any():
        mean_ref = _mean_reference(means_a, ok_amp, rel_tol * plateau + float(np.median(se_mean[ok_amp])))
        ok = (
            ok_amp
            & (np.abs(means_a - mean_ref) <= rel_tol * plateau + se_mean + 1e-12)
            & (drifts_a <= (rel_tol if drift_tol is None else drift_tol) * plateau + se_drift + 1e-12)
        )
    else:
        ok = ok_amp
    # longest contiguous run
    best: tuple[int, int] = (0, 0)
    i = 0
    while i < n:
        if ok[i]:
            j = i
            while j + 1 < n and ok[j + 1]:
                j += 1
            if (j - i + 1) > (best[1] - best[0]):
                best = (i, j + 1)
            i = j + 1
        else:
            i += 1
    run = list(range(best[0], best[1]))
    # the first oscillation cycle is a transient: drop it if it is in the run
    if drop_first and run:
        run = run[1:]
    if run:
        ts, te = bounds[run[0]], bounds[run[-1] + 1]
    else:
        ts = te = float(t[0])
    return SteadyWindow(float(ts), float(te), run, n, [float(a) for a in amps], [float(m) for m in means], plateau, rel_tol)

