"""`chainid diagnose`: where the model misses, which effects cause it (in order), how much each shrinks it.

Pipeline: check the records → prepare every test as a steady harmonic test where it is one (tests that cannot be
analysed are excluded with their reason) → the route → the model of every step (:mod:`.modelio`) → the transfer
to another set (``validate``, :mod:`.transfer`).

**The route rule.**  A set of steady harmonic tests whose tests run at one operating condition takes the harmonic
route (:mod:`.harmonic.route`: phase bins, c_e(ω, A) per test and a damping law over the tests).  Every other set
takes the time-domain route (:mod:`.timedomain.route`), all its records sample by sample: a record that is not a
steady harmonic test (a transient, sweep, random or seismic record, a resonant device's response), a set whose
tests carry covariates that differ (operating conditions: the damping and the effects may follow them), or
``holdout_blocks`` > 0.
"""

from __future__ import annotations

import math
import sys
import warnings
from typing import Any, Sequence

import numpy as np

from chainid.gap.modelio import attach_models
from chainid.gap.harmonic.prepare import Unusable, prepare_test
from chainid.gap.core.candidate import MIN_TRAIN
from chainid.gap.core.verdict import MIN_SHRINK, NONSTAT_FRACTION  # noqa: F401  (the verdict rule, one place)
from chainid.gap.harmonic.route import diagnose_harmonic
from chainid.infra.progress import stage
# the one rule for records no analysis can work on (magnitudes, a dead force or displacement channel) is the
# records' validation: identify, audit, predict and the diagnosis use it alike
from chainid.records.validate import MAX_ABS_F_N, MAX_ABS_X_MM  # noqa: F401  (re-exported)
from chainid.records.validate import check_channels as check_magnitudes
from chainid.records.validate import check_data


def fit_linear_model(records: Sequence[Any], holdout: Sequence[str], mass_kg: float = 0.0) -> Any:
    """LinearModel F = k(x − x_ref) [N/mm, mm] fitted on the training records' samples, with mass ``mass_kg``."""
    from chainid.model.base import LinearModel

    xs = np.concatenate([r.x for r in records if r.test not in set(holdout)])
    Fs = np.concatenate([r.F for r in records if r.test not in set(holdout)])
    return LinearModel.fit(xs, Fs, mass=mass_kg)


def _prepare(records: Sequence[Any], n_bins: int, allow_compression: bool, steady_tol: float | None,
             strict: bool) -> tuple[list[Any], list[dict[str, str]]]:
    """The harmonic tests prepared for the phase-bin route (``prepare_test``) and the records left out, each with
    its reason: a broadband record (its data checked) or an unusable test (an error with ``strict``)."""
    from chainid.gap.core.noise import is_broadband

    data, excluded = [], []
    for r in records:
        finite = bool(np.all(np.isfinite(r.t)) and np.all(np.isfinite(r.x)))  # else prepare_test names the sample
        if r.t.size >= 64 and finite and is_broadband(r.t, r.x):  # clearly not one sine: no harmonic estimate
            # its data are checked as any record's: a data error (a chain force without mean tension) is raised,
            # never a reason to leave the record out; its sign warnings said once
            check_data(r, allow_compression=allow_compression)
            excluded.append({"test": r.test, "reason": "not a harmonic test (broadband displacement)"})
            continue
        try:
            data.append(prepare_test(r, n_bins=n_bins, allow_compression=allow_compression, steady_tol=steady_tol))
        except Unusable as exc:
            if strict:
                raise ValueError(f"test {r.test!r} cannot be used (--strict): {exc}") from None
            excluded.append({"test": r.test, "reason": str(exc)})
    return data, excluded


def diagnose(records: Sequence[Any], holdout: Sequence[str], model: Any | None = None, *,
             effects: Sequence[str] | None = None, max_combo: int = 3, n_bins: int = 64, uncertainty: bool = True,
             damping_law: str = "auto", allow_compression: bool = False, steady_tol: float | None = None,
             strict: bool = False, quiet: bool = False, holdout_blocks: int = 0,
             validate: Sequence[Any] | None = None, mass_kg: float | None = None, resamples: int = 0,
             seed: int = 0) -> dict[str, Any]:
    """Diagnose the sim-to-real gap of a test series.

    Parameters
    ----------
    records : sequence of Record
        Measured tests (t s, x mm, F N; ``covariates`` name → value when the tests carry operating conditions).
    holdout : sequence of str
        Held-out test ids (whole tests).
    model : StiffnessModel, optional
        Baseline stiffness: a chain model; None: a linear device fitted on the training tests (harmonic route: a
        spring k(x − x_ref) with its mass; time route: a mass–spring–damper m·ẍ + c·ẋ + k·x with a force offset per
        test).
    effects : sequence of str, optional
        Restrict the library (default: all applicable).
    max_combo : int
        Most effects in the explanation chain (1–3).
    n_bins : int
        Phase bins per cycle.
    uncertainty : bool
        Standard deviations of every step's parameters (harmonic route: leave-one-test-out refits; time route:
        the jack-knife of the leave-one-block-out amplitude refits).
    damping_law : str
        Baseline damping law of the harmonic route: ``auto`` (default; the paper's Eq. 21 when the plan separates
        it, else the leave-one-out best simple law), ``polynomial``, ``viscous``, ``coulomb``,
        ``viscous+coulomb``, ``hysteretic``.  Time route: ``viscous`` gives the base one dashpot c for every
        record; any other keeps the default, a dashpot following the records' band centre and amplitude
        (passive on every record) where >= 3 training records separate it.
    allow_compression : bool
        Accept compressive (negative) forces with a chain model, which carries none.
    steady_tol : float, optional
        Steady-cycle tolerance (None: adaptive, from each record's cycle-to-cycle scatter).
    strict : bool
        A test that cannot be analysed is an error instead of being excluded.
    quiet : bool
        No line on stderr per excluded test.
    holdout_blocks : int
        K > 0: every record is cut into K contiguous time blocks and the last block of each is held out
        (time-domain route for every record; whole tests in ``holdout`` are held out as well).
    validate : sequence of Record, optional
        Another set (another excitation): the chain fitted here is evaluated on it (key ``transfer``,
        :func:`chainid.gap.transfer.transfer`).
    mass_kg : float, optional
        The moving mass of a linear base [kg], given instead of fitted (``--mass``).
    resamples, seed : int
        Resamples of the training units (whole tests, time blocks) for the stability of every step and the 90 %
        intervals of every parameter (:mod:`chainid.gap.core.resample`; 0: none; ``chainid diagnose`` runs
        :data:`chainid.gap.core.resample.RESAMPLES`), and the seed of their draws.

    Notes
    -----
    The route each set takes is stated in the module docstring.

    Returns
    -------
    dict
        The JSON contract: baseline, where, ranking, verdict, plus steps (the explanation chain), excluded,
        residual, mechanism, best, confounded, interpretation, warnings, tests.

    Raises
    ------
    ValueError
        Unknown holdout id, all tests held out, fewer than 3 usable training tests, compressive records with a
        chain model without ``allow_compression``, |F| > 1e12 N or |x| > 1e9 mm, a constant force or displacement
        (:func:`check_magnitudes`, i.e. :func:`chainid.records.validate.check_channels`).
    """
    from chainid.infra.threads import one_thread

    with one_thread():  # many small products and one small learner: more threads only wait (chainid.infra.threads)
        return _diagnose(records, holdout, model, effects=effects, max_combo=max_combo, n_bins=n_bins,
                         uncertainty=uncertainty, damping_law=damping_law, allow_compression=allow_compression,
                         steady_tol=steady_tol, strict=strict, quiet=quiet, holdout_blocks=holdout_blocks,
                         validate=validate, mass_kg=mass_kg, resamples=resamples, seed=seed)


def _diagnose(records: Sequence[Any], holdout: Sequence[str], model: Any | None, *, effects: Sequence[str] | None,
              max_combo: int, n_bins: int, uncertainty: bool, damping_law: str, allow_compression: bool,
              steady_tol: float | None, strict: bool, quiet: bool, holdout_blocks: int,
              validate: Sequence[Any] | None, mass_kg: float | None, resamples: int, seed: int) -> dict[str, Any]:
    """:func:`diagnose`'s work (its arguments, as documented there)."""
    holdout = _check_args(records, holdout, max_combo, holdout_blocks, validate, mass_kg)
    holdout_blocks = int(holdout_blocks)
    is_chain = model is not None and hasattr(model, "hertz_scale")
    # how predict evaluates a harmonic test of the set, stored in the model file
    evaluation = {"n_bins": int(n_bins), "steady_tol": steady_tol,
                  "allow_compression": bool(allow_compression or not is_chain)}
    stage("preparing", f"{len(records)} records")
    data, excluded = _prepare(records, n_bins, allow_compression or not is_chain, steady_tol, False)
    from chainid.gap.timedomain.data import MIN_SAMPLES

    # records that are not steady harmonic tests go to the time-domain route when long enough for it
    time_ids = {r.test for r in records if r.t.size >= MIN_SAMPLES} & {e["test"] for e in excluded}
    reasons = {e["test"]: e["reason"] for e in excluded}
    excluded = [e for e in excluded if e["test"] not in time_ids]
    if strict and excluded:
        e = excluded[0]
        raise ValueError(f"test {e['test']!r} cannot be used (--strict): {e['reason']}")
    for e in excluded:
        if not quiet:
            print(f"chainid diagnose: test {e['test']} excluded: {e['reason']}", file=sys.stderr)
    ex_ids = {e["test"] for e in excluded}
    usable = [r for r in records if r.test not in ex_ids]
    hold_ok = [h for h in holdout if h not in ex_ids]
    why = _why_time_route([r.test for r in records if r.test in time_ids], reasons, holdout_blocks, usable)
    if why:
        from chainid.gap.timedomain.route import diagnose_any

        res = diagnose_any(usable, hold_ok, model if is_chain else None, holdout_blocks=holdout_blocks,
                           effects=effects, max_combo=max_combo, excluded=excluded, quiet=quiet, mass_kg=mass_kg,
                           warn=[f"test {e['test']} excluded: {e['reason']}" for e in excluded],
                           resamples=resamples, seed=seed, damping_law=damping_law, why=why)
    else:
        if not hold_ok:
            raise ValueError(f"--holdout: every held-out test was excluded ({', '.join(holdout)}); "
                             f"reasons: {'; '.join(e['reason'] for e in excluded if e['test'] in holdout)}")
        fit_mass = model is None and mass_kg is None
        if model is None:
            model = fit_linear_model(usable, hold_ok, mass_kg or 0.0)
        res = diagnose_harmonic(data, hold_ok, model, effects=effects, max_combo=max_combo, damping_law=damping_law,
                                uncertainty=uncertainty, excluded=excluded, resamples=resamples, seed=seed,
                                fit_mass=fit_mass)
    evaluation["route"] = res["route"] = "time" if res.get("route") == "time" else "harmonic"
    stage("models")
    for msg in attach_models(res, evaluation):  # the model found, runnable and savable on any excitation
        warnings.warn(msg, stacklevel=3)
    if validate is not None:
        from chainid.gap.transfer import transfer

        stage("transfer")
        res["transfer"] = transfer(res, validate, n_bins=n_bins, steady_tol=steady_tol)
    return res


def _why_time_route(time_ids: Sequence[str], reasons: dict[str, str], holdout_blocks: int,
                    records: Sequence[Any]) -> str:
    """Why a set takes the time-domain route, in words (empty: it takes the phase-bin route): a record that is not
    a steady harmonic test (the first in the records' order, with its reason, and how many more), held-out blocks,
    or operating conditions that differ between the records."""
    if time_ids:
        more = f" (and {len(time_ids) - 1} more)" if len(time_ids) > 1 else ""
        reason = reasons.get(time_ids[0], "").removesuffix(": time-domain route")
        return f"test {time_ids[0]}{more}: {reason}"
    if holdout_blocks:
        return f"--holdout-blocks {holdout_blocks}"
    if _operating_conditions_differ(records):
        return "the records' operating conditions (covariates) differ"
    return ""


def _operating_conditions_differ(records: Sequence[Any]) -> bool:
    """Whether the records carry a covariate (an operating condition) with more than one value."""
    names = set().union(*[set(getattr(r, "covariates", None) or {}) for r in records]) if records else set()
    return any(len({(getattr(r, "covariates", None) or {}).get(n) for r in records}) > 1 for n in names)


def _check_args(records: Sequence[Any], holdout: Sequence[str], max_combo: int, holdout_blocks: int,
                validate: Sequence[Any] | None, mass_kg: float | None) -> list[str]:
    """The arguments' checks (see :func:`diagnose`'s Raises); returns the cleaned held-out ids."""
    if not 1 <= int(max_combo) <= 3:
        raise ValueError(f"max_combo = {max_combo!r} is out of range; valid range 1 to 3")
    if mass_kg is not None and not (math.isfinite(mass_kg) and 0.0 <= mass_kg <= 1e6):
        raise ValueError(f"--mass = {mass_kg!r} kg is out of range; valid range 0 to 1e6 kg")
    check_magnitudes(records)
    if validate is not None:
        check_magnitudes(validate)
    holdout = [h.strip() for h in holdout if h.strip()]
    ids = [r.test for r in records]
    bad = [h for h in holdout if h not in ids]
    if bad:
        raise ValueError(f"--holdout: test id(s) {bad} not in the data; valid ids: {', '.join(ids)}")
    holdout_blocks = int(holdout_blocks)
    if holdout_blocks < 0 or holdout_blocks == 1:
        raise ValueError(f"--holdout-blocks = {holdout_blocks!r} is out of range; valid: 0 (off) or >= 2")
    if not holdout and holdout_blocks == 0:
        raise ValueError("--holdout: no test held out; give test ids or --holdout-blocks K")
    if len(set(holdout)) >= len(set(ids)):
        raise ValueError(f"--holdout: all {len(ids)} tests are held out; leave at least {MIN_TRAIN} for training")
    return holdout
