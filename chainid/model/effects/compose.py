"""Composition of library effects on a base model: the one place where several effects make one force.

Stiffness-side effects change the base spring first (:func:`modify_model`: a chain kernel with another stiffness
level, contact law, offset or series compliance); the other effects then act on the changed spring — a friction
force on the changed spring's load, a delay of the whole — so combined effects carry their cross terms (a sum of
separate force corrections would miss them).

Units: t s, x mm, ẋ mm/s, ẍ mm/s², ω rad/s, A mm, x0 mm, F N.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any, Callable, Sequence

import numpy as np

from chainid.model.effects.forms import is_chain
from chainid.model.effects.library import STIFFNESS_SIDE, make_effect

__all__ = ["modify_model", "undamped_force"]


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


def undamped_force(effects: Sequence[tuple[str, dict[str, float]]], model: Any, t: np.ndarray, x: np.ndarray,
                   xd: np.ndarray, xdd: np.ndarray, omega: float, A: float, x0: float,
                   xfun: Callable | None = None, periodic: bool = True,
                   v_err: float | np.ndarray = 0.0) -> np.ndarray:
    """Undamped model force [N] of an ordered effect set on a stiffness model (paper Eq. 1 without c_e·ẋ).

    The one place where effects are composed (the diagnosis and :class:`chainid.model.augmented.AugmentedModel`):
    stiffness-side effects change the model (:func:`modify_model`), the others add their force change on the
    changed model.  ``sensor_delay`` and ``damping_law`` are not force terms here: the caller evaluates the
    inputs at t − τ and the damping law.  ``v_err`` [mm/s]: the RMS error of an estimated velocity (the sign of
    sliding friction).  Units: t s, x mm, ẋ mm/s, ẍ mm/s², ω rad/s, A mm, x0 mm.
    """
    rest = []
    for n, pp in effects:
        if n in STIFFNESS_SIDE and is_chain(model):  # (a linear spring: slack/compliance as force terms)
            model = modify_model(n, pp, model)
        else:
            rest.append((n, pp))
    m = float(getattr(model, "mass_kg", 0.0))
    base = m * xdd * 1e-3 + np.asarray(model.force(x), float)
    Fn = base.copy()
    for n, pp in rest:
        if n in ("damping_law", "sensor_delay"):
            continue
        Fe, _, _ = make_effect(n).force(pp, model, t, x, xd, xdd, omega, A, x0, xfun, periodic, v_err)
        Fn += Fe - base
    return Fn
