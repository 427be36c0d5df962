"""The one rule for a damping that turns into a negative dashpot: a run that would use it is refused.

A model's damping is resolved at an operating point — circular frequency ω [rad/s], amplitude A [mm], mean
elongation x0 [mm] — into a time-domain force (:meth:`chainid.model.timedamping.Damping.resolve`).  An identified
law c_e(ω, A) is a fitted surface: extrapolated beyond its tests, or after effects that over-explain the
dissipation, it can give c < 0 [N·s/mm].  A negative dashpot feeds energy in, which no passive device (a chain,
a friction damper, a seal) does, so any number computed with it — a prediction's NRMSE, simulated records, a
chain line's tensions — describes an active device that does not exist.

**The rule** (:func:`check_passive`): a command that runs a model at operating points — ``predict`` (each
record: a harmonic test's ω, A, x0; a transient's dominant ω and A), ``simulate --model`` (each planned test) and
``dynamics --segment-model`` (the stated operating point) — refuses it when its damping (or its baseline's) is a
negative dashpot at any of them: one error naming the points, the lowest c and where it occurs.  It is an error
with or without ``--strict`` (nothing to relax: the result would be unphysical).  ``predict --tests`` runs the
other tests.  The diagnosis, which *finds* such a model, reports it as a warning
(:func:`chainid.gap.modelio.negative_damping`, the same test, :func:`negative_dashpots`).

A ``feature`` law fitted onto its passive boundary (c = 0 at a corner of its records' feature box) is 0 there,
not −1e-16: the law itself returns a c within its floating-point round-off of 0 as 0
(:meth:`chainid.model.timedamping.Damping.feature_value`), for this rule and every run alike.

The damping forms ``hysteretic``, ``dahl`` and ``coulomb`` are passive by construction (their parameters are >= 0:
:mod:`chainid.model.ranges`); a viscous ``c`` and a law are judged here.  Units: N, mm, s.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Iterable

__all__ = ["OperatingPoint", "negative_dashpots", "describe", "refusal", "check_passive"]


@dataclass(frozen=True)
class OperatingPoint:
    """Where a model is run: ``label`` (a test id), ω [rad/s], A [mm], x0 [mm]; ``test``: the id a law's
    per-test c_e is looked up by (``fitted``)."""

    label: str
    omega: float | None
    A: float | None
    x0: float
    test: str | None = None


def _c_at(model: Any, p: OperatingPoint, fitted: bool) -> float | None:
    """The viscous c [N·s/mm] of the model's damping at ``p`` (None for a form that has none)."""
    d = model.damping
    if d.form == "viscous":
        return float(d.params.get("c", 0.0))
    if d.form == "feature":  # a viscous c over record features: ω, A are the record's band centre and half range
        return d.feature_value(p.omega, p.A) if p.omega is not None and p.A is not None else None
    if d.form != "law":
        return None
    if fitted and p.test is not None and p.test in d.per_test:
        return float(d.per_test[p.test])
    return float(d.ce(p.omega, p.A, model.ke(p.x0)))


def negative_dashpots(model: Any, points: Iterable[OperatingPoint], fitted: bool = False
                      ) -> list[tuple[OperatingPoint, float]]:
    """The operating points at which ``model`` (an :class:`~chainid.model.augmented.AugmentedModel`) has a
    viscous c < 0 [N·s/mm], with that c (a law's c_e before any rule converts it)."""
    out = []
    for p in points:
        c = _c_at(model, p, fitted)
        if c is not None and c < 0:
            out.append((p, c))
    return out


def describe(bad: list[tuple[OperatingPoint, float]]) -> str:
    """One sentence: the points, the lowest c and its ω, A."""
    p, c = min(bad, key=lambda b: b[1])
    ids = ", ".join(b[0].label for b in bad)
    at = f" at ω = {p.omega:.4g} rad/s, A = {p.A:.4g} mm" if p.omega is not None and p.A is not None else ""
    return (f"the damping gives a negative viscous c at test(s) {ids} (lowest c = {c:.4g} N·s/mm{at}): the model "
            "feeds energy in there, which a passive device cannot; the effects over-explain the dissipation or the "
            "law is extrapolated")


def refusal(who: str, bad: list[tuple[OperatingPoint, float]], hint: str = "") -> str:
    """The error refusing a run of ``who`` where its damping is a negative dashpot at the points ``bad`` (with their
    c [N·s/mm]): the points, the lowest c and where, the valid range (c >= 0) and ``hint``."""
    c = min(b[1] for b in bad)
    return (f"{who}: {describe(bad)}; c = {c:.4g} N·s/mm is invalid: valid range >= 0 N·s/mm at every operating "
            "point of the run" + (f" ({hint})" if hint else ""))


def check_passive(model: Any, points: Iterable[OperatingPoint], *, fitted: bool = False, what: str = "model",
                  hint: str = "", with_baseline: bool = False) -> None:
    """Refuse a run of ``model`` (and, ``with_baseline``, of its ``baseline``: ``predict`` runs both) at
    ``points`` where its damping is a negative dashpot (see the module docstring).

    Raises
    ------
    ValueError
        Naming ``what``, the points, the lowest c [N·s/mm] with its ω [rad/s] and A [mm], the valid range
        (c >= 0) and ``hint``.
    """
    points = list(points)
    runs = [(what, model)] + ([(f"{what}'s baseline", getattr(model, "baseline", None))] if with_baseline else [])
    for who, m in runs:
        if m is None:
            continue
        bad = negative_dashpots(m, points, fitted)
        if bad:
            raise ValueError(refusal(who, bad, hint))
