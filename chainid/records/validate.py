"""Validation and analysis of one record: data checks, harmonic estimate, steady window.

* :func:`check_data` -- data errors (NaN, t not increasing, a force compressive on average with a chain):
  always raised; a chain record whose measured force dips below zero, or whose x stays negative under
  tension, is a warning (:class:`RecordWarning`);
* :func:`validate_record` -- data checks plus the analysis checks (samples,
  whole cycles, steady cycles, amplitude above the noise);
* :func:`analyse_record` -- estimate (or side file) + validation, cached on the record;
* :func:`try_analyse` -- the same, but an analysis failure is returned as the
  reason the test is left out instead of raised.

All names are re-exported by :mod:`chainid.records`.  Records are duck-typed
(``test``, ``t`` [s], ``x`` [mm], ``F`` [N], ``estimate``), so this module does
not import :mod:`chainid.records`.

Units: t [s], x [mm], F [N], omega [rad/s].
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from chainid.signal.harmonic import HarmonicEstimate, estimate_harmonic, linear_harmonic, shift_window
from chainid.signal.steady import TOL_MAX, select_steady

if TYPE_CHECKING:  # pragma: no cover
    from chainid.records.record import Record

__all__ = ["check_data", "check_channels", "validate_record", "analyse_record", "try_analyse", "RecordWarning",
           "MAX_ABS_F_N", "MAX_ABS_X_MM"]

#: Largest |F| [N] and |x| [mm] the analyses take: beyond, sums of squares overflow float64 (a chain's
#: breaking load is below 1e8 N; F ~ 1e154 N is a unit or parsing error, not a measurement).
MAX_ABS_F_N = 1e12
MAX_ABS_X_MM = 1e9


def check_channels(records: Any) -> None:
    """The one rule for records no analysis can work on (``identify``, ``audit --data``, ``diagnose``,
    ``predict``): |F| or |x| beyond :data:`MAX_ABS_F_N` / :data:`MAX_ABS_X_MM`, a force that does not vary within
    a test (F ≡ const: a dead force channel) or a displacement that does not vary (x ≡ const: no motion, a dead
    displacement channel; a damping fitted to it is c_e = F/0, e.g. 7e14 N·s/mm).  NaN is judged elsewhere
    (:func:`check_data`).

    Raises
    ------
    ValueError
        Naming the test, the column, the value and the valid range.
    """
    for r in records:
        for col, v, lim, unit in (("F", r.F, MAX_ABS_F_N, "N"), ("x", r.x, MAX_ABS_X_MM, "mm")):
            if v.size and np.all(np.isfinite(v)):
                big = float(np.max(np.abs(v)))
                if big > lim:
                    raise ValueError(f"test {r.test!r}: |{col}| = {big:.4g} {unit} is out of range; valid range "
                                     f"|{col}| <= {lim:g} {unit} (check the column's unit)")
        if r.F.size and np.all(np.isfinite(r.F)) and float(np.ptp(r.F)) == 0.0:
            raise ValueError(f"test {r.test!r}: the force F is constant ({float(r.F[0]):g} N in all {r.F.size} "
                             "samples): a dead channel, nothing to diagnose; valid records have a varying F")
        if r.x.size and np.all(np.isfinite(r.x)) and float(np.ptp(r.x)) == 0.0:
            raise ValueError(f"test {r.test!r}: the displacement x is constant ({float(r.x[0]):g} mm in all "
                             f"{r.x.size} samples): no motion, nothing to identify (a dead displacement channel); "
                             "valid records have a varying x")


class RecordWarning(UserWarning):
    """A record that is valid but implausible for the model it is read for (it is used as given)."""


def _spanned_cycles(t: np.ndarray, x: np.ndarray) -> tuple[float, float]:
    """Best single-sinusoid fit of x(t) with 0.3..3 periods in the record.

    Returns ``(periods spanned, R²)``; used only to say "less than one whole
    cycle" when the regular estimate finds no oscillation.
    """
    step = max(1, t.size // 4096)
    tt, xx = t[::step], x[::step]
    span = float(tt[-1] - tt[0])
    if tt.size < 8 or span <= 0:
        return 0.0, 0.0
    ss = float(np.sum((xx - xx.mean()) ** 2))
    if ss <= 0:
        return 0.0, 0.0
    best = (0.0, -math.inf)
    u = (tt - tt[0]) / span
    for c in np.arange(0.3, 3.0001, 0.05):
        X = np.column_stack([np.ones_like(u), np.sin(2 * math.pi * c * u), np.cos(2 * math.pi * c * u)])
        sol, *_ = np.linalg.lstsq(X, xx, rcond=None)
        r2 = 1.0 - float(np.sum((xx - X @ sol) ** 2)) / ss
        if r2 > best[1]:
            best = (float(c), r2)
    return best


def _raise_if_under_one_cycle(rec: Record) -> None:
    """Raise "less than one whole cycle" if x(t) spans under one period of its oscillation."""
    c, r2 = _spanned_cycles(rec.t, rec.x)
    if c < 1.0 and r2 > 0.5:
        span = float(rec.t[-1] - rec.t[0])
        raise ValueError(
            f"test {rec.test!r}: less than one whole cycle: x(t) spans about {c:.2g} period(s) of its "
            f"oscillation (period ~{span / c:.4g} s, record {span:.4g} s); at least 2 whole cycles are needed"
        )


def check_data(rec: Record, *, allow_compression: bool = False) -> None:
    """Data errors of one record (not analysis problems): raise ValueError naming the test.

    Checks: no NaN/inf in t [s], x [mm], F [N]; t strictly increasing.  These are errors in the file or the
    choice of model, never a reason to leave a test out silently (:func:`try_analyse` raises them).

    Without ``allow_compression`` the record is read for a chain, whose spring cannot push (F_k(x) >= 0).  A
    *measured* force can: F = m·ẍ + F_k(x) + c·ẋ, and the damping, the inertia or the fixture can take it below
    zero while the spring force stays positive throughout (a damped test at a low pretension).  So a force that
    dips below zero is a :class:`RecordWarning`, and the record is analysed on the chain's spring-force model
    as any other.  Over whole cycles the damping and inertia terms average out, so the *mean* force is the
    spring's: a record that goes below zero with a mean force under :data:`MIN_MEAN_TENSION` of its largest
    |F| is no chain in tension and is refused (its sign is flipped, or the part pushes: ``--model linear`` /
    ``--allow-compression``).  A record whose x stays below
    zero while the mean force is a tension is a warning too: a chain at x <= 0 is slack (F_k = 0), so the
    elongation's zero is offset (the ``slack`` effect) or its sign flipped.  ``allow_compression``: none of
    these (a part whose force changes sign, a linear spring).
    """
    _check(rec, allow_compression, warn=True)


def _check(rec: Record, allow_compression: bool, warn: bool) -> None:
    """:func:`check_data`'s checks; its warnings only with ``warn`` (a caller that has issued them once already
    checks again without: one warning per record, not one per layer of the analysis)."""
    name = rec.test
    for col, arr in (("t", rec.t), ("x", rec.x), ("F", rec.F)):
        bad = ~np.isfinite(arr)
        if bad.any():
            i = int(np.argmax(bad))
            raise ValueError(f"test {name!r}: column {col!r} has a NaN/non-finite value at sample {i}")
    dt = np.diff(rec.t)
    if np.any(dt <= 0):
        i = int(np.argmax(dt <= 0))
        raise ValueError(
            f"test {name!r}: t is not strictly increasing at sample {i + 1} "
            f"(t = {rec.t[i]:.9g} s then {rec.t[i + 1]:.9g} s)"
        )
    if not allow_compression:
        _check_chain_signs(rec, warn)


#: a chain record whose force goes below zero must keep a mean tension of at least this share of max |F| (a mean
#: about zero with a force swinging both ways is a part that pushes, not a chain in tension)
MIN_MEAN_TENSION = 0.01


def _check_chain_signs(rec: Record, warn: bool = True) -> None:
    """The sign checks of a record read for a chain (see :func:`check_data`); the warnings only with ``warn``."""
    import warnings

    name = rec.test
    F = rec.F
    if F.size == 0:
        return
    mean = float(np.mean(F))
    scale = float(np.max(np.abs(F)))
    if np.any(F < 0):
        i = int(np.argmin(F))
        where = f"min F = {F[i]:.6g} N at t = {rec.t[i]:.6g} s"
        if mean < MIN_MEAN_TENSION * scale:
            raise ValueError(
                f"test {name!r}: force goes compressive ({where}) and its mean is no tension (mean F = "
                f"{mean:.6g} N, max |F| = {scale:.6g} N): a chain's mean force is its spring's (damping and inertia "
                f"average out over whole cycles) and its spring cannot push; valid: mean F >= "
                f"{100 * MIN_MEAN_TENSION:g} % of max |F| with a chain model. Is F's sign flipped (--scale F=-1)? "
                f"For a part whose force changes sign: --model linear or --allow-compression "
                f"(allow_compression=True)")
        if warn:
            warnings.warn(
                f"test {name!r}: the measured force dips below zero ({where}; mean F = {mean:.6g} N): the chain's "
                f"spring cannot push, but a measured force can (damping c·ẋ, inertia m·ẍ, the fixture); it is "
                f"analysed on the chain's spring-force model as any other (--allow-compression: no warning)",
                RecordWarning, stacklevel=4)
    if warn and rec.x.size and float(np.max(rec.x)) < 0 and mean > 0 and mean > 0.1 * float(np.ptp(F)):
        warnings.warn(
            f"test {name!r}: x < 0 throughout (max x = {float(np.max(rec.x)):.6g} mm) under a mean tension of "
            f"{mean:.6g} N: a chain at x <= 0 is slack and carries nothing (F_k(x <= 0) = 0), so the elongation's "
            f"zero is offset (the slack effect; a displacement measured from another reference) or its sign is "
            f"flipped (--scale x=-1)", RecordWarning, stacklevel=4)


def _check_estimate(
    rec: Record, est: HarmonicEstimate | None, *, min_cycles: float, min_snr: float, steady_tol: float | None
) -> HarmonicEstimate:
    """Analysis checks (enough samples, cycles, steady cycles, amplitude over noise); ValueError if not met."""
    name = rec.test
    if rec.t.size < 16:
        raise ValueError(f"test {name!r}: only {rec.t.size} samples; need at least 16")
    try:
        if est is None:
            est = estimate_harmonic(rec.t, rec.x, rel_tol=steady_tol, test=name)
    except ValueError:
        _raise_if_under_one_cycle(rec)
        raise
    if not (est.A >= min_snr * est.noise and est.A > 0):  # no oscillation found: is it under one cycle?
        _raise_if_under_one_cycle(rec)
    cycles_in_record = (rec.t[-1] - rec.t[0]) * est.omega / (2 * math.pi)
    win = est.window
    # whole steady cycles found, counting the first one that selection drops
    n_whole = (win.n_cycles + 1) if (win is not None and win.n_cycles >= 1) else 0
    if est.A < min_snr * est.noise or est.A <= 0:
        raise ValueError(
            f"test {name!r}: amplitude below the noise: A = {est.A:.4g} mm, RMS noise of x = "
            f"{est.noise:.4g} mm (need A >= {min_snr:g} x noise)"
        )
    if cycles_in_record < 1.0:
        raise ValueError(
            f"test {name!r}: less than one whole cycle: the record ({rec.t[-1] - rec.t[0]:.4g} s) spans "
            f"{cycles_in_record:.3g} period(s) of {2 * math.pi / est.omega:.4g} s; at least {min_cycles:g} whole "
            f"cycles are needed"
        )
    if cycles_in_record < min_cycles or win is None or n_whole < min_cycles or win.n_cycles < 1:
        tol = win.rel_tol if win else 0.03
        how = ""
        if win is not None and win.requested_tol is None:
            how = f" (adaptive tolerance, widened up to {100 * TOL_MAX:g} %; use steady_tol / --steady-tol to set it)"
        raise ValueError(
            f"test {name!r}: fewer than {min_cycles:g} full cycles of steady oscillation: the record spans "
            f"{cycles_in_record:.3g} periods of {2 * math.pi / est.omega:.4g} s and has {n_whole} contiguous "
            f"whole cycle(s) with amplitude and mean within {100 * tol:.3g} % of the "
            f"plateau ({win.n_cycles if win else 0} left after dropping the ramp and the first cycle){how}"
        )
    return est


def validate_record(
    rec: Record,
    *,
    allow_compression: bool = False,
    min_cycles: float = 2.0,
    min_snr: float = 3.0,
    estimate: HarmonicEstimate | None = None,
    steady_tol: float | None = None,
) -> HarmonicEstimate:
    """Check one record; raise ValueError naming the test and the problem.

    Checks: no NaN/inf; t strictly increasing; force never compressive (unless
    ``allow_compression``) (:func:`check_data`); at least 16 samples; at least
    one whole cycle; at least ``min_cycles`` whole oscillation cycles in the
    record and at least one steady cycle after the first is dropped; amplitude
    at least ``min_snr`` times the RMS noise of x.

    Parameters
    ----------
    rec : Record
        The test (t [s], x [mm], F [N]).
    allow_compression : bool
        Accept F < 0 [N].
    min_cycles : float
        Minimum number of whole cycles (default 2).
    min_snr : float
        Minimum amplitude / RMS noise of x (default 3).
    estimate : HarmonicEstimate, optional
        Use this estimate (e.g. from a side file) instead of estimating.
    steady_tol : float or None
        Steady-cycle tolerance (fraction, 0.03 = 3 %); None = adaptive
        (:func:`chainid.signal.steady.select_steady`).

    Returns
    -------
    HarmonicEstimate
        The estimate used for the checks.
    """
    _check(rec, allow_compression, warn=True)
    return _check_estimate(rec, estimate, min_cycles=min_cycles, min_snr=min_snr, steady_tol=steady_tol)


_UNSET: float = -1.0  # sentinel: rel_tol not given


def analyse_record(
    rec: Record,
    side: tuple[float, float, float] | None = None,
    *,
    rel_tol: float | None = _UNSET,
    allow_compression: bool = True,
    min_cycles: float = 2.0,
    min_snr: float = 3.0,
    steady_tol: float | None = None,
) -> HarmonicEstimate:
    """Harmonic estimate and steady window of one record, optionally from a side file.

    With ``side = (omega, x0, A)`` (rad/s, mm, mm) those values are used as given;
    only the phase theta [rad] is fitted (fixed-frequency least squares) and the
    steady window is selected at that frequency.

    Parameters
    ----------
    rec : Record
        The test: t [s], x [mm], F [N].
    side : (omega, x0, A), optional
        [rad/s, mm, mm] from a side file.
    rel_tol : float, optional
        Old name of ``steady_tol`` (kept for existing callers).
    allow_compression : bool
        Accept F < 0 [N] (default True here).
    min_cycles, min_snr : float
        As in :func:`validate_record`.
    steady_tol : float or None
        Steady-cycle tolerance (fraction, 0.03 = 3 %); None (default) = adaptive,
        from the record's cycle-to-cycle scatter (:func:`chainid.steady.select_steady`).

    Returns
    -------
    HarmonicEstimate
        Validated with :func:`validate_record`.

    Raises
    ------
    ValueError
        Any :func:`validate_record` problem (data error or analysis failure).
    """
    tol = steady_tol if (rel_tol is _UNSET or rel_tol is None) else rel_tol
    return _analyse(rec, side, tol, allow_compression, min_cycles, min_snr, warn=True)


def _analyse(rec: Record, side: tuple[float, float, float] | None, tol: float | None, allow_compression: bool,
             min_cycles: float, min_snr: float, warn: bool) -> HarmonicEstimate:
    """:func:`analyse_record`'s work: the data checked once, first (its warnings only with ``warn``)."""
    _check(rec, allow_compression, warn)
    if side is None:
        cached = rec.estimate
        if cached is not None and cached.window is not None and cached.window.requested_tol == tol:
            est = cached
        else:
            est = _check_estimate(rec, None, min_cycles=min_cycles, min_snr=min_snr, steady_tol=tol)
    else:
        w, x0, A = side
        t0 = float(rec.t[0])  # phases from the record's first sample (see HarmonicEstimate.t_origin)
        tr = rec.t - t0
        _, a, b = linear_harmonic(tr, rec.x, w)
        theta = math.atan2(b, a)
        win = select_steady(tr, rec.x, w, theta, rel_tol=tol)
        if win.n_cycles >= 1:
            m = (tr >= win.t_start) & (tr < win.t_end)
            _, a, b = linear_harmonic(tr[m], rec.x[m], w)
            theta = math.atan2(b, a)
            resid = rec.x[m] - (x0 + A * np.sin(w * tr[m] + theta))
            noise = float(np.sqrt(np.mean(resid**2)))
        else:
            noise = float("inf")
        est = HarmonicEstimate(w, x0, A, theta, noise, shift_window(win, t0), source="side file", t_origin=t0)
    return _check_estimate(rec, est, min_cycles=min_cycles, min_snr=min_snr, steady_tol=None)


def try_analyse(
    rec: Record,
    *,
    allow_compression: bool = False,
    steady_tol: float | None = None,
    side: tuple[float, float, float] | None = None,
    min_cycles: float = 2.0,
    min_snr: float = 3.0,
) -> tuple[HarmonicEstimate | None, str]:
    """Analyse one record, or say why it must be left out.

    Data errors (:func:`check_data`: NaN, t not increasing, compressive force
    without ``allow_compression``) are raised: they concern the file or the
    model, not the test.  Everything else that stops the analysis (too few
    samples or cycles, no steady cycles within the tolerance, no harmonic
    oscillation, amplitude below the noise) is returned as a reason.

    Parameters
    ----------
    rec : Record
        The test: t [s], x [mm], F [N].
    allow_compression : bool
        Accept F < 0 [N] (default False: a chain cannot push).
    steady_tol : float or None
        Steady-cycle tolerance (fraction); None = adaptive.
    side : (omega, x0, A), optional
        [rad/s, mm, mm] from a side file.
    min_cycles, min_snr : float
        As in :func:`validate_record`.

    Returns
    -------
    (HarmonicEstimate, str) or (None, str)
        The estimate and a statement of what was kept (window, cycles,
        tolerance and why), or None and the reason the test is left out.

    Raises
    ------
    ValueError
        Data errors only; also an invalid ``steady_tol`` (not in (0, 1)).
    """
    if steady_tol is not None and not (0.0 < steady_tol < 1.0):
        raise ValueError(f"steady_tol = {steady_tol!r} is invalid: must be in (0, 1) (e.g. 0.03 = 3 %), or None")
    check_data(rec, allow_compression=allow_compression)  # data errors raised, its warnings issued once, here
    try:
        est = _analyse(rec, side, steady_tol, allow_compression, min_cycles, min_snr, warn=False)
    except (ValueError, np.linalg.LinAlgError) as exc:
        msg = str(exc)
        prefix = f"test {rec.test!r}: "
        return None, msg[len(prefix):] if msg.startswith(prefix) else msg
    return est, (est.window.statement() if est.window is not None else "")
