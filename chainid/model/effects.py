"""Effect library: named, physically parameterised, bounded additions to Eq. 1.

Each effect changes the *undamped* part of the model force,
F = m·ẍ + F_k(x) + c_e(ω, A)·ẋ (paper Eq. 1), and/or the velocity the damping
acts on.  The library is kept apart from the selection method
(:mod:`chainid.gap.selection`): an :class:`Effect` only knows its parameters,
their physical bounds and how to evaluate the force.

Units: x mm, ẋ mm/s, ẍ mm/s², F N, t s, ω rad/s, m kg (m·ẍ·1e-3 = N).

Stiffness-side effects (``slack``, ``machine_compliance``, ``contact_law``) use
the lead's :class:`chainid.model.base.ChainModel` parameters when the model is a
chain model (generated kernels) and a plain-numpy fallback otherwise.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any, Callable, Sequence

import numpy as np

from chainid.model import operators as ops

__all__ = ["EFFECT_NAMES", "STIFFNESS_SIDE", "Effect", "make_effect", "parse_effect", "parse_spec", "modify_model",
           "play_operator", "dahl_operator", "coulomb_sign", "stick_slip", "series_compliance_force", "undamped_force"]

EFFECT_NAMES = (
    "stiffness_level",
    "friction",
    "hysteresis",
    "contact_law",
    "slack",
    "backlash",
    "machine_compliance",
    "sensor_delay",
    "damping_law",
)


def play_operator(x: np.ndarray, half_width: float, periodic: bool = True) -> np.ndarray:
    """Backlash (play) operator: output follows x with a dead band ±half_width [mm] (:func:`chainid.operators.play`).

    With ``periodic`` the series is run twice and the second pass returned
    (steady state of a periodic input).
    """
    x = np.ascontiguousarray(x, dtype=np.float64)
    if half_width <= 0:
        return x.copy()
    return ops.play(x, float(half_width), periodic=periodic)


def dahl_operator(x: np.ndarray, F_h: float, x_h: float, periodic: bool = True) -> np.ndarray:
    """Rate-independent Dahl hysteresis force z(x) [N] (:func:`chainid.operators.dahl`, z₀ = 0).

    dz/dx = (F_h/x_h)(1 − sgn(ẋ) z/F_h), solved exactly between samples:
    z → ±F_h exponentially over a travel x_h [mm] after each reversal.
    """
    x = np.ascontiguousarray(x, dtype=np.float64)
    if F_h == 0:
        return np.zeros_like(x)
    return ops.dahl(x, float(F_h), max(float(x_h), 1e-9), 0.0, periodic=periodic)[0]


#: sgn(ẋ) of Coulomb sliding with 0 at a reversal (one implementation: :func:`chainid.operators.coulomb_sign`)
coulomb_sign = ops.coulomb_sign


def stick_slip(x: np.ndarray, xd: np.ndarray, x_s: float, periodic: bool = True) -> np.ndarray:
    """Normalised Coulomb friction with elastic stick (Jenkins element), in [-1, 1].

    After a reversal the contact sticks elastically over a travel 2·x_s [mm]
    before sliding again (:func:`chainid.operators.jenkins` with F_c = 1); x_s = 0 (or below
    1e-4 of the stroke) gives sgn(ẋ), pure Coulomb sliding friction.
    """
    x = np.asarray(x, dtype=float)
    if x_s <= 1e-4 * (float(np.ptp(x)) if x.size else 0.0):
        # a stick travel below 1e-4 of the stroke is not resolved by any record: pure Coulomb sliding.
        return coulomb_sign(xd, periodic)
    return ops.jenkins(x, 1.0, float(x_s), periodic=periodic)[0]


def series_compliance_force(model: Any, x: np.ndarray, c: float, iters: int = 8) -> np.ndarray:
    """Force of the spring ``model`` in series with a compliance c [mm/N] at total x [mm].

    Solves F = F_k(x − c·F) by Newton iteration (numpy; any StiffnessModel).
    """
    x = np.asarray(x, dtype=float)
    F = np.asarray(model.force(x), dtype=float)
    if c == 0:
        return F
    for _ in range(iters):
        xs = x - c * F
        g = F - np.asarray(model.force(xs), dtype=float)
        k = np.asarray(model.stiffness(xs), dtype=float)
        F = F - g / (1.0 + c * k)
    return F


#: effects that change the stiffness model itself (composed first; the other effects act on the result)
STIFFNESS_SIDE = ("stiffness_level", "contact_law", "slack", "machine_compliance")


def modify_model(name: str, p: dict[str, float], model: Any) -> Any:
    """The chain model with the stiffness-side effect ``name`` applied (parameters ``p`` in its units).

    Composition is what makes effects combine physically: a delay or friction then acts on the corrected
    stiffness (a sum of separate force corrections would miss their cross terms).
    """
    if not _is_chain(model):
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


def _is_chain(model: Any) -> bool:
    return hasattr(model, "hertz_scale") and hasattr(model, "compliance") and hasattr(model, "slack")


@dataclass
class Effect:
    """One named unmodelled effect.

    Attributes
    ----------
    name : str
        One of :data:`EFFECT_NAMES`.
    param_names, units : tuple of str
    bounds : tuple of (low, high)
        Physical bounds of each parameter (set from the data scale by
        :func:`make_effect`).
    x0_guess : tuple of float
        Start values for the fit.
    chain_only : bool
        Only meaningful for a nonlinear (chain) stiffness model.
    """

    name: str
    param_names: tuple[str, ...]
    units: tuple[str, ...]
    bounds: tuple[tuple[float, float], ...]
    x0_guess: tuple[float, ...]
    chain_only: bool = False
    description: str = ""

    @property
    def n_params(self) -> int:
        return len(self.param_names)

    def check(self, params: dict[str, float]) -> None:
        """Raise ValueError for an unknown or out-of-bounds parameter."""
        for k, v in params.items():
            if k not in self.param_names:
                raise ValueError(
                    f"effect {self.name!r}: unknown parameter {k!r}; valid: {', '.join(self.param_names)}"
                )
            lo, hi = self.bounds[self.param_names.index(k)]
            if not (np.isfinite(v) and lo <= v <= hi):
                raise ValueError(f"effect {self.name!r}: {k} = {v!r} is out of range; valid range {lo:g} to {hi:g}")

    def force(
        self,
        p: dict[str, float],
        model: Any,
        t: np.ndarray,
        x: np.ndarray,
        xd: np.ndarray,
        xdd: np.ndarray,
        omega: float,
        A: float,
        x0: float,
        xfun: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray, np.ndarray]] | None = None,
        periodic: bool = True,
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Undamped force [N], the velocity the damping acts on [mm/s], and an extra c_e factor.

        Returns ``(F_nodamp, xd_damp, extra_c)`` with the model force
        F = F_nodamp + (c_e + extra_c)·xd_damp.  ``periodic``: the memory operators return the periodic
        steady state of a series that is one period (the diagnosis' phase grid); False runs them forward
        from their stated initial state (:mod:`chainid.operators`), for any x(t).
        """
        m = float(getattr(model, "mass_kg", 0.0))
        inert = m * xdd * 1e-3
        Fk = np.asarray(model.force(x), dtype=float)
        extra = 0.0
        if self.name == "friction":
            F = inert + Fk + (p.get("F_c", 0.0) + p.get("mu", 0.0) * np.abs(Fk)) * stick_slip(x, xd, p.get("x_s", 0.0),
                                                                                          periodic)
        elif self.name == "hysteresis":
            F = inert + Fk + dahl_operator(x, p.get("F_h", 0.0), p.get("x_h", 1.0), periodic)
        elif self.name == "backlash":
            F = inert + np.asarray(model.force(play_operator(x, 0.5 * p.get("b", 0.0), periodic)), dtype=float)
        elif self.name == "slack" and not _is_chain(model):
            F = inert + np.asarray(model.force(x - p.get("s", 0.0)), dtype=float)
        elif self.name == "machine_compliance" and not _is_chain(model):
            F = inert + series_compliance_force(model, x, p.get("c", 0.0))
        elif self.name in STIFFNESS_SIDE:  # the changed chain model, in one place (raises without a chain)
            F = inert + np.asarray(modify_model(self.name, p, model).force(x), dtype=float)
        elif self.name == "sensor_delay":
            tau = p.get("tau", 0.0)
            if xfun is None:
                raise ValueError("sensor_delay needs the displacement function xfun(t)")
            xs, xds, xdds = xfun(t - tau)
            F = m * xdds * 1e-3 + np.asarray(model.force(xs), dtype=float)
            return F, xds, np.zeros_like(t)
        elif self.name == "damping_law":
            ke = float(np.asarray(model.stiffness(np.array([x0])), dtype=float)[0])
            extra = p.get("eta", 0.0) * ke / omega + 4.0 * p.get("F_f", 0.0) / (math.pi * omega * A)
            F = inert + Fk
        else:  # pragma: no cover
            raise ValueError(f"unknown effect {self.name!r}")
        return F, xd, np.full_like(t, extra)


def undamped_force(effects: Sequence[tuple[str, dict[str, float]]], model: Any, t: np.ndarray, x: np.ndarray,
                   xd: np.ndarray, xdd: np.ndarray, omega: float, A: float, x0: float,
                   xfun: Callable | None = None, periodic: bool = True) -> np.ndarray:
    """Undamped model force [N] of an ordered effect set on a stiffness model (paper Eq. 1 without c_e·ẋ).

    The one place where effects are composed (the diagnosis and :class:`chainid.augmented.AugmentedModel`):
    stiffness-side effects change the model (:func:`modify_model`), the others add their force change on the
    changed model.  ``sensor_delay`` and ``damping_law`` are not force terms here: the caller evaluates the
    inputs at t − τ and the damping law.  Units: t s, x mm, ẋ mm/s, ẍ mm/s², ω rad/s, A mm, x0 mm.
    """
    rest = []
    for n, pp in effects:
        if n in STIFFNESS_SIDE and _is_chain(model):  # (a linear spring: slack/compliance as force terms)
            model = modify_model(n, pp, model)
        else:
            rest.append((n, pp))
    m = float(getattr(model, "mass_kg", 0.0))
    base = m * xdd * 1e-3 + np.asarray(model.force(x), float)
    Fn = base.copy()
    for n, pp in rest:
        if n in ("damping_law", "sensor_delay"):
            continue
        Fe, _, _ = make_effect(n).force(pp, model, t, x, xd, xdd, omega, A, x0, xfun, periodic)
        Fn += Fe - base
    return Fn


def make_effect(name: str, F_scale: float = 1e4, x_scale: float = 1.0, omega_max: float = 10.0) -> Effect:
    """The library entry ``name`` with bounds set from the data scales.

    Parameters
    ----------
    name : str
        One of :data:`EFFECT_NAMES`.
    F_scale : float
        Force scale of the data, e.g. RMS(F − mean F) [N] (> 0).
    x_scale : float
        Displacement scale, e.g. the largest amplitude [mm] (> 0).
    omega_max : float
        Largest test frequency [rad/s] (> 0); bounds the delay to ± half its period (π/ω_max): a lag up to
        half the shortest period is found (the fit starts from a grid over that range, :mod:`.fitgrid`).
    """
    if name not in EFFECT_NAMES:
        raise ValueError(f"effect = {name!r} is unknown; valid: {', '.join(EFFECT_NAMES)}")
    F_scale = float(max(F_scale, 1e-9))
    x_scale = float(max(x_scale, 1e-9))
    if name == "friction":
        return Effect(name, ("F_c", "mu", "x_s"), ("N", "-", "mm"),
                      ((0.0, 5 * F_scale), (0.0, 0.5), (0.0, 0.5 * x_scale)), (0.05 * F_scale, 0.0, 0.0),
                      description="Coulomb sliding friction (F_c + mu·|F_k|)·sgn(ẋ) with elastic stick travel "
                                  "x_s after reversal (Jenkins element), rate-independent")
    if name == "hysteresis":
        return Effect(name, ("F_h", "x_h"), ("N", "mm"), ((0.0, 5 * F_scale), (1e-3 * x_scale, 10 * x_scale)),
                      (0.05 * F_scale, 0.3 * x_scale),
                      description="Dahl hysteresis: z → ±F_h over a travel x_h after each reversal")
    if name == "backlash":
        return Effect(name, ("b",), ("mm",), ((0.0, 2.0 * x_scale),), (0.1 * x_scale,),
                      description="dead band b of travel after each reversal (play)")
    if name == "slack":
        return Effect(name, ("s",), ("mm",), ((-5.0 * x_scale, 5.0 * x_scale),), (0.0,), chain_only=True,
                      description="displacement offset s (permanent elongation, clearance, sensor zero)")
    if name == "stiffness_level":
        return Effect(name, ("scale",), ("-",), ((0.2, 5.0),), (1.0,), chain_only=True,
                      description="stiffness level of the base model: factor on the links' linear axial "
                                  "stiffness EA (compliance c_lin/scale); < 1 softer, > 1 stiffer")
    if name == "machine_compliance":
        return Effect(name, ("c",), ("mm/N",), ((0.0, 1e-2),), (1e-6,), chain_only=True,
                      description="series compliance c of test machine / fixture")
    if name == "contact_law":
        return Effect(name, ("scale", "beta"), ("-", "-"), ((0.05, 5.0), (0.3, 1.2)), (1.0, 2.0 / 3.0),
                      chain_only=True,
                      description="contact compliance c_hertz·scale with exponent beta (Hertz: 1, 2/3)")
    if name == "sensor_delay":
        q = math.pi / max(omega_max, 1e-9)  # ± half the shortest period
        return Effect(name, ("tau",), ("s",), ((-q, q),), (0.0,),
                      description="force channel lags displacement by tau")
    return Effect(name, ("eta", "F_f"), ("-", "N"), ((0.0, 2.0), (0.0, 5 * F_scale)), (0.0, 0.0),
                  description="extra damping form: hysteretic eta·k_e(x0)/ω + Coulomb-equivalent 4F_f/(πωA)")


def parse_spec(spec: str) -> tuple[str, dict[str, float]]:
    """Parse ``NAME[:param=value,...]`` (also ``a+b`` not allowed here; repeat --effect).

    Raises
    ------
    ValueError
        Unknown effect name, unknown parameter or non-numeric value.
    """
    name, _, rest = spec.strip().partition(":")
    name = name.strip()
    if name not in EFFECT_NAMES:
        raise ValueError(f"--effect {spec!r}: effect {name!r} is unknown; valid: {', '.join(EFFECT_NAMES)}")
    params: dict[str, float] = {}
    for item in filter(None, (s.strip() for s in rest.split(","))):
        k, eq, v = item.partition("=")
        if not eq:
            raise ValueError(f"--effect {spec!r}: parameter {item!r} must be written name=value")
        try:
            params[k.strip()] = float(v)
        except ValueError:
            raise ValueError(f"--effect {spec!r}: {k.strip()} = {v!r} is not a number") from None
    return name, params


DEFAULTS = {
    "stiffness_level": {"scale": 1.0},
    "friction": {"F_c": 0.0, "mu": 0.0, "x_s": 0.0},
    "hysteresis": {"F_h": 0.0, "x_h": 0.05},
    "backlash": {"b": 0.0},
    "slack": {"s": 0.0},
    "machine_compliance": {"c": 0.0},
    "contact_law": {"scale": 1.0, "beta": 2.0 / 3.0},
    "sensor_delay": {"tau": 0.0},
    "damping_law": {"eta": 0.0, "F_f": 0.0},
}


def _xfun_from_series(t: np.ndarray, x: np.ndarray, xd: np.ndarray, xdd: np.ndarray) -> Callable:
    def f(ts: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        return np.interp(ts, t, x), np.interp(ts, t, xd), np.interp(ts, t, xdd)
    return f


def parse_effect(spec: str, model: Any) -> Callable[..., np.ndarray]:
    """A simulation hook ``force_fn(t, x, xdot, xddot, F_model) -> F`` for ``--effect NAME[:p=v,...]``.

    The hook replaces the baseline force of Eq. 1 by the effect-augmented one:
    F = F_model − (m·ẍ + F_k(x)) + F_effect (stiffness side), plus the friction /
    hysteresis / extra damping force, or the whole force delayed (sensor_delay).

    Parameters
    ----------
    spec : str
        e.g. ``"friction:F_c=200,mu=0.01"``, ``"backlash:b=0.05"``, ``"sensor_delay:tau=0.01"``.
    model : StiffnessModel
        The baseline stiffness model used by the simulation.

    Raises
    ------
    ValueError
        Unknown name/parameter, or a value out of its physical range.
    """
    from chainid.model.ranges import EFFECT_RANGES, check_number

    name, params = parse_spec(spec)
    eff = make_effect(name)
    for k, v in params.items():
        if k not in eff.param_names:
            raise ValueError(f"effect {name!r}: unknown parameter {k!r}; valid: {', '.join(eff.param_names)}")
        # the physical ranges of the one table (chainid.model.ranges): an error outside the valid range, a
        # warning outside the plausible one
        _, w = check_number(v, EFFECT_RANGES[name][k], f"effect {name!r}: {k}")
        if w:
            import warnings

            warnings.warn(w, UserWarning, stacklevel=2)
    p = dict(DEFAULTS[name])
    p.update(params)

    def hook(t: np.ndarray, x: np.ndarray, xd: np.ndarray, xdd: np.ndarray, F_model: np.ndarray) -> np.ndarray:
        t = np.asarray(t, float)
        m = float(getattr(model, "mass_kg", 0.0))
        base = m * xdd * 1e-3 + np.asarray(model.force(x), dtype=float)
        damp = F_model - base
        if name == "sensor_delay":
            return np.interp(t - p["tau"], t, F_model)
        A = 0.5 * (float(np.max(x)) - float(np.min(x)))
        omega = float(np.max(np.abs(xd))) / A if A > 0 else 1.0
        x0 = 0.5 * (float(np.max(x)) + float(np.min(x)))
        Fn, xdd_damp, extra = eff.force(p, model, t, x, xd, xdd, omega, max(A, 1e-12), x0,
                                        _xfun_from_series(t, x, xd, xdd))
        # memory operators are not periodic here (ramp / taper): rerun non-periodic
        if name == "friction" and p["x_s"] > 0:
            Fn = base + (p["F_c"] + p["mu"] * np.abs(np.asarray(model.force(x), float))) * stick_slip(
                x, xd, p["x_s"], periodic=False)
        if name == "hysteresis":
            Fn = base + dahl_operator(x, p["F_h"], p["x_h"], periodic=False)
        elif name == "backlash":
            Fn = m * xdd * 1e-3 + np.asarray(model.force(play_operator(x, 0.5 * p["b"], periodic=False)), float)
        return Fn + damp + extra * xdd_damp

    hook.effect_name = name  # type: ignore[attr-defined]
    hook.effect_params = p  # type: ignore[attr-defined]
    return hook
