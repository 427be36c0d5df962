"""Composition of library effects on a base model: the one place where several effects make one force.

Stiffness-side effects change the base spring first (:func:`modify_model`: a chain kernel with another stiffness
level, contact law, offset or series compliance); the other effects then act on the changed spring — a friction
force on the changed spring's load, a delay of the whole — so combined effects carry their cross terms (a sum of
separate force corrections would miss them).

Units: t s, x mm, ẋ mm/s, ẍ mm/s², ω rad/s, A mm, x0 mm, F N.
"""

from __future__ import annotations

import functools
from dataclasses import replace
from typing import Any, Callable, Sequence

import math

import numpy as np

from chainid.model.effects.forms import columns, is_chain, play_operator, series_compliance_force
from chainid.model.effects.library import STIFFNESS_SIDE, make_effect

__all__ = ["modify_model", "effect_force", "undamped_force"]


def modify_model(name: str, p: dict[str, float], model: Any) -> Any:
    """The chain model with the stiffness-side effect ``name`` applied (parameters ``p`` in its units).

    Raises
    ------
    ValueError
        The model is not a chain model, or ``name`` is not a stiffness-side effect.
    """
    if not is_chain(model):
        raise ValueError(f"effect {name!r} needs a chain model (not --model linear)")
    if name == "stiffness_level":
        return replace(model, ea_scale=model.ea_scale * p.get("scale", 1.0))
    if name == "slack":
        return replace(model, slack=model.slack + p.get("s", 0.0))
    if name == "machine_compliance":
        return replace(model, compliance=model.compliance + p.get("c", 0.0))
    if name == "contact_law":
        beta = p.get("beta", 2.0 / 3.0)
        return replace(model, hertz_scale=model.hertz_scale * p.get("scale", 1.0),
                       contact_exponent=None if abs(beta - 2.0 / 3.0) < 1e-9 else beta)
    raise ValueError(f"effect {name!r} is not a stiffness-side effect; those are: {', '.join(STIFFNESS_SIDE)}")


def changed_model(effects: Sequence[tuple[str, dict[str, float]]], model: Any) -> Any:
    """The stiffness model as the stiffness-side effects of an ordered effect set change it (a chain model only: on
    a linear spring, slack and compliance are force terms); the other effects leave it as it is.

    Parameters
    ----------
    effects : (name, parameters) of each effect, in order (parameters in their library units)
    model : the base stiffness model (F_k(x) [N] of x [mm])

    Returns
    -------
    The changed model (``model`` itself when no stiffness-side effect applies).
    """
    for n, pp in effects:
        if n in STIFFNESS_SIDE and is_chain(model):
            model = modify_model(n, pp, model)
    return model


@functools.cache
def _named(name: str) -> Any:
    """The library effect ``name`` at the default scales (its kind and fixed references: what composing needs),
    made once."""
    return make_effect(name)


def undamped_force(effects: Sequence[tuple[str, dict[str, float]]], model: Any, t: np.ndarray, x: np.ndarray,
                   xd: np.ndarray, xdd: np.ndarray, omega: float, A: float, x0: float,
                   xfun: Callable | None = None, periodic: bool = True,
                   v_err: float | np.ndarray = 0.0, Fk: np.ndarray | None = None) -> np.ndarray:
    """Undamped model force [N] of an ordered effect set on a stiffness model (paper Eq. 1 without c_e·ẋ).

    The one place where effects are composed (the diagnosis and :class:`chainid.model.augmented.AugmentedModel`):
    stiffness-side effects change the model (:func:`modify_model`), the others add their force change on the
    changed model.  ``sensor_delay`` and ``damping_law`` are not force terms here: the caller evaluates the
    inputs at t − τ and the damping law.  ``v_err`` [mm/s]: the RMS error of an estimated velocity (the sign of
    sliding friction).  ``Fk`` [N]: the spring force at x of the model as the stiffness-side effects change it, when
    the caller has it already (computed otherwise).  Units: t s, x mm, ẋ mm/s, ẍ mm/s², ω rad/s, A mm, x0 mm.
    """
    model = changed_model(effects, model)
    rest = [(n, pp) for n, pp in effects if not (n in STIFFNESS_SIDE and is_chain(model))]
    m = float(getattr(model, "mass_kg", 0.0))
    Fk = np.asarray(model.force(x), float) if Fk is None else Fk
    base = m * xdd * 1e-3 + Fk
    Fn = base.copy()
    for n, pp in rest:
        if n in ("damping_law", "sensor_delay"):
            continue
        Fe, _, _ = effect_force(_named(n), pp, model, t, x, xd, xdd, omega, A, x0, xfun, periodic, v_err,
                                Fk=Fk)
        Fn += Fe - base
    return Fn


def effect_force(eff: Any, p: dict[str, float], model: Any, t: np.ndarray, x: np.ndarray, xd: np.ndarray,
                 xdd: np.ndarray, omega: float, A: float, x0: float, xfun: Callable | None = None,
                 periodic: bool = True, v_err: float | np.ndarray = 0.0, Fk: np.ndarray | None = None
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Undamped force [N], the velocity the damping acts on [mm/s], and an extra c_e factor [N·s/mm] of one
    effect ``eff`` (:class:`.library.Effect`) with parameters ``p`` on ``model``.

    Returns ``(F_nodamp, xd_damp, extra_c)`` with the model force F = F_nodamp + (c_e + extra_c)·xd_damp.
    ``periodic``: the memory operators return the periodic steady state of a series that is one period (the
    diagnosis' phase grid); False runs them forward from their stated initial state, for any x(t).  ``v_err``
    [mm/s]: the RMS error of an estimated velocity (the sign of sliding, :func:`sliding_sign`).  ``Fk``: the
    model's spring force at x [N] when the caller has it already (it is computed otherwise).
    """
    m = float(getattr(model, "mass_kg", 0.0))
    inert = m * xdd * 1e-3
    Fk = np.asarray(model.force(x), dtype=float) if Fk is None else Fk
    name = eff.name
    if eff.kind in ("force", "mass"):
        q = dict(eff.fixed) | p
        F = inert + Fk + sum(q.get(a, 0.0) * c for a, c in columns(name, q, x, xd, xdd, Fk, periodic, v_err).items())
    elif name == "backlash":
        F = inert + np.asarray(model.force(play_operator(x, 0.5 * p.get("b", 0.0), periodic)), dtype=float)
    elif name == "slack" and not is_chain(model):
        F = inert + np.asarray(model.force(x - p.get("s", 0.0)), dtype=float)
    elif name == "machine_compliance" and not is_chain(model):
        F = inert + series_compliance_force(model, x, p.get("c", 0.0))
    elif eff.kind == "stiffness":  # the changed chain model, in one place (raises without a chain)
        F = inert + np.asarray(modify_model(name, p, model).force(x), dtype=float)
    elif name == "sensor_delay":
        tau = p.get("tau", 0.0)
        if xfun is None:
            raise ValueError("sensor_delay needs the displacement function xfun(t)")
        xs, xds, xdds = xfun(t - tau)
        F = m * xdds * 1e-3 + np.asarray(model.force(xs), dtype=float)
        return F, xds, np.zeros_like(t)
    elif name == "damping_law":
        ke = float(np.asarray(model.stiffness(np.array([x0])), dtype=float)[0])
        extra = p.get("eta", 0.0) * ke / omega + 4.0 * p.get("F_f", 0.0) / (math.pi * omega * A)
        return inert + Fk, xd, np.full_like(t, extra)
    else:  # pragma: no cover
        raise ValueError(f"unknown effect {name!r}")
    return F, xd, np.zeros_like(t)
