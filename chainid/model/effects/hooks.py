"""``chainid simulate --effect NAME[:p=v,...]``: an effect as a hook on a simulated record's force.

:func:`parse_spec` reads the option; :func:`parse_effect` checks every parameter against its physical range (one
table: :mod:`.library`) and returns the hook that replaces the baseline force of Eq. 1 by the effect-augmented one.

Units: x mm, ẋ mm/s, ẍ mm/s², F N, t s.
"""

from __future__ import annotations

from typing import Any, Callable

import numpy as np

from chainid.model.effects.compose import effect_force
from chainid.model.effects.library import DEFAULTS, EFFECT_NAMES, SPECS, make_effect

__all__ = ["parse_spec", "parse_effect", "check_params", "compose_hooks"]


def parse_spec(spec: str) -> tuple[str, dict[str, float]]:
    """Parse ``NAME[:param=value,...]`` (one effect; repeat --effect for several).

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


def check_params(name: str, params: dict[str, float], where: str = "effect") -> None:
    """Every parameter of effect ``name`` known and inside its physical validity range (the one table of
    :mod:`chainid.model.ranges`); a value outside the plausible range is a warning.

    Raises
    ------
    ValueError
        Naming the effect, the parameter, the value and the valid range.
    """
    import warnings

    from chainid.model.ranges import EFFECT_RANGES, check_number

    spec = SPECS[name]
    known = [p.name for p in spec.params]
    for k, v in params.items():
        if k not in known:
            raise ValueError(f"{where} {name!r}: unknown parameter {k!r}; valid: {', '.join(known)}")
        _, w = check_number(v, EFFECT_RANGES[name][k], f"{where} {name!r}: {k}")
        if w:
            warnings.warn(w, UserWarning, stacklevel=3)


def _xfun_from_series(t: np.ndarray, x: np.ndarray, xd: np.ndarray, xdd: np.ndarray) -> Callable:
    def f(ts: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        return np.interp(ts, t, x), np.interp(ts, t, xd), np.interp(ts, t, xdd)
    return f


def parse_effect(spec: str, model: Any) -> Callable[..., np.ndarray]:
    """A simulation hook ``force_fn(t, x, xdot, xddot, F_model) -> F`` for ``--effect NAME[:p=v,...]``.

    The hook replaces the baseline force of Eq. 1 by the effect-augmented one:
    F = F_model − (m·ẍ + F_k(x)) + F_effect (stiffness side), plus the effect's force (memory operators run
    forward from their stated initial state), or the whole force delayed (sensor_delay).

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
    name, params = parse_spec(spec)
    check_params(name, params)
    eff = make_effect(name)
    p = dict(DEFAULTS[name])
    p.update(params)

    def hook(t: np.ndarray, x: np.ndarray, xd: np.ndarray, xdd: np.ndarray, F_model: np.ndarray) -> np.ndarray:
        t = np.asarray(t, float)
        m = float(getattr(model, "mass_kg", 0.0))
        base = m * xdd * 1e-3 + np.asarray(model.force(x), dtype=float)
        damp = F_model - base
        if name == "sensor_delay":  # alone: the model force is smooth, its samples interpolate it
            return np.interp(t - p["tau"], t, F_model)
        A = 0.5 * (float(np.max(x)) - float(np.min(x)))
        omega = float(np.max(np.abs(xd))) / A if A > 0 else 1.0
        x0 = 0.5 * (float(np.max(x)) + float(np.min(x)))
        Fn, xd_damp, extra = effect_force(eff, p, model, t, x, xd, xdd, omega, max(A, 1e-12), x0,
                                       _xfun_from_series(t, x, xd, xdd), periodic=False)
        return Fn + damp + extra * xd_damp

    hook.effect_name = name  # type: ignore[attr-defined]
    hook.effect_params = p  # type: ignore[attr-defined]
    if name == "sensor_delay":
        hook.delay_s = float(p["tau"])  # type: ignore[attr-defined]
    return hook


def compose_hooks(hooks: list[Callable[..., np.ndarray]]) -> Callable[..., np.ndarray] | None:
    """One hook applying ``hooks`` in order (None for none), a delay at the instants it lags to.

    A sensor delay τ (a hook with ``delay_s``) measures the force at t − τ.  Interpolating the force already built
    from the samples would put a switch (a friction's sign, a contact) between two samples on a ramp: the force of
    no instant.  So everything before the delay (the model force and the earlier hooks) is evaluated again at the
    lagged instants t − τ, on the kinematics interpolated there (smooth: linear interpolation errs by O(Δt²)),
    and a friction there takes the sign of the velocity at that instant
    (:func:`chainid.model.operators.coulomb_sign`).  Before the record's start the first sample's state is held.
    """
    if not hooks:
        return None

    def run(hs: list[Callable[..., np.ndarray]], t: np.ndarray, x: np.ndarray, xd: np.ndarray, xdd: np.ndarray,
            F: np.ndarray) -> np.ndarray:
        for i in range(len(hs) - 1, -1, -1):  # the last delay wraps everything before it
            tau = getattr(hs[i], "delay_s", None)
            if tau is not None:
                ts = np.asarray(t, float) - tau
                lag = [np.interp(ts, t, np.asarray(v, float)) for v in (x, xd, xdd, F)]
                F = run(hs[:i], ts, *lag)
                return run(hs[i + 1:], t, x, xd, xdd, F)
        for h in hs:
            F = h(t, x, xd, xdd, F)
        return F

    def hook(t: np.ndarray, x: np.ndarray, xd: np.ndarray, xdd: np.ndarray, F: np.ndarray) -> np.ndarray:
        return run(list(hooks), np.asarray(t, float), x, xd, xdd, F)

    return hook
