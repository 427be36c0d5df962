"""The effect library: named, physically parameterised, bounded additions to the base model (paper Eq. 1).

Every effect is declared once here (:data:`SPECS`): its parameters with their units, the bounds and start value of a
fit (set from the data's scales), whether each enters the force linearly (an *amplitude*: a column of the time-domain fit) or not (a
*shape*), what part of the model the effect changes (its *kind*), and the bases it applies to.  The physical
validity range of every parameter (what a model file or ``--effect`` may hold) is the one table of
:mod:`chainid.model.ranges`.  The force of
each effect is in :mod:`.forms`; the composition of several in :mod:`.compose`.  The selection method is kept
apart (:mod:`chainid.gap.core.selection`), as a library of candidate terms is kept apart from the way a model is
chosen from it.

Kinds: ``stiffness`` changes the base spring itself (composed first, the other effects act on the result); ``play``
feeds the spring through a dead band (backlash);
``force`` adds a force (memoryless or a causal memory operator); ``mass`` adds inertia; ``delay`` shifts the
force channel in time; ``damping`` changes the damping law.

Units: x mm, ẋ mm/s, ẍ mm/s², F N, t s, ω rad/s, m kg (m·ẍ·1e-3 = N).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

__all__ = ["Scales", "Param", "EffectSpec", "SPECS", "EFFECT_NAMES", "STIFFNESS_SIDE", "DEFAULTS", "Effect",
           "make_effect", "valid_range", "applies_to", "pinned", "identifiable"]


@dataclass(frozen=True)
class Scales:
    """Scales of a data set that set an effect's fit bounds.

    F force scale [N] (e.g. the standard deviation of F), x displacement scale [mm] (the largest amplitude),
    omega the largest angular frequency [rad/s], v a velocity scale [mm/s] (the largest |ẋ|), x_mid the mean
    displacement [mm], tau the largest lag to search [s] (default π/omega: half the shortest period).
    """

    F: float = 1e4
    x: float = 1.0
    omega: float = 10.0
    v: float = 10.0
    x_mid: float = 0.0
    tau: float | None = None

    @property
    def lag(self) -> float:
        return float(self.tau) if self.tau is not None else math.pi / max(self.omega, 1e-9)


Bound = Callable[[Scales], tuple[float, float]]


@dataclass(frozen=True)
class Param:
    """One parameter of an effect: name, unit, fit bounds and start, neutral default (its physical validity range is
    in the one table of :mod:`chainid.model.ranges`)."""

    name: str
    unit: str
    bounds: Bound
    guess: Callable[[Scales], float]
    default: float
    amplitude: bool = False
    fitted: bool = True
    #: whether the fit's lower / upper bound is a limit the form may legitimately reach (True) or a sign that the
    #: form does not fit when a parameter is pinned there (False; a lower bound of 0, "absent", never pins)
    limits: tuple[bool, bool] = (False, False)


@dataclass(frozen=True)
class EffectSpec:
    """A library effect: its kind, parameters, the bases it applies to and a one-line description."""

    name: str
    kind: str
    params: tuple[Param, ...]
    description: str
    bases: tuple[str, ...] = ("chain", "linear")


def _P(name: str, unit: str, bounds: Bound, guess: Callable[[Scales], float], default: float,
       amplitude: bool = False, fitted: bool = True, limits: tuple[bool, bool] = (False, False)) -> Param:
    return Param(name, unit, bounds, guess, default, amplitude, fitted, limits)


INF = math.inf

SPECS: dict[str, EffectSpec] = {s.name: s for s in (
    EffectSpec("stiffness_level", "stiffness", (
        _P("scale", "-", lambda s: (0.2, 5.0), lambda s: 1.0, 1.0),),
        "stiffness level of the base model: factor on the links' linear axial stiffness EA (compliance "
        "c_lin/scale); < 1 softer, > 1 stiffer", ("chain",)),
    EffectSpec("friction", "force", (
        _P("F_c", "N", lambda s: (0.0, 5 * s.F), lambda s: 0.05 * s.F, 0.0, amplitude=True),
        _P("mu", "-", lambda s: (0.0, 0.5), lambda s: 0.0, 0.0, amplitude=True),
        _P("x_s", "mm", lambda s: (0.0, 0.5 * s.x), lambda s: 0.0, 0.0)),
        "Coulomb sliding friction (F_c + mu·|F_k|)·sgn(ẋ) with elastic stick travel x_s after reversal (Jenkins "
        "element), rate-independent"),
    EffectSpec("stribeck", "force", (
        _P("F_c", "N", lambda s: (0.0, 5 * s.F), lambda s: 0.05 * s.F, 0.0, amplitude=True),
        _P("dF_s", "N", lambda s: (0.0, 5 * s.F), lambda s: 0.05 * s.F, 0.0, amplitude=True),
        _P("v_s", "mm/s", lambda s: (1e-3 * s.v, s.v), lambda s: 0.1 * s.v, 1.0),
        _P("dF", "N", lambda s: (-5 * s.F, 5 * s.F), lambda s: 0.0, 0.0, amplitude=True)),
        "velocity-weakening (Stribeck) friction sgn(ẋ)·[F_c + dF_s·exp(−(ẋ/v_s)²)] + dF·|sgn(ẋ)|: static force "
        "F_s = F_c + dF_s above the kinetic F_c, direction asymmetry dF (slip force F_c + dF moving +x)"),
    EffectSpec("hysteresis", "force", (
        _P("F_h", "N", lambda s: (0.0, 5 * s.F), lambda s: 0.05 * s.F, 0.0, amplitude=True),
        _P("x_h", "mm", lambda s: (1e-3 * s.x, 10 * s.x), lambda s: 0.3 * s.x, 0.05)),
        "Dahl hysteresis: z → ±F_h over a travel x_h after each reversal"),
    EffectSpec("bouc_wen", "force", (
        _P("F_y", "N", lambda s: (0.0, 5 * s.F), lambda s: 0.05 * s.F, 0.0, amplitude=True),
        _P("x_y", "mm", lambda s: (1e-3 * s.x, 10 * s.x), lambda s: 0.3 * s.x, 0.05),
        _P("n", "-", lambda s: (0.3, 8.0), lambda s: 1.5, 1.0),
        _P("r", "-", lambda s: (0.0, 1.0), lambda s: 0.75, 1.0, limits=(True, True))),
        "Bouc–Wen hysteresis with shape: force F_y·z, dz/dx = (1/x_y)·[1 − (r·sgn(ẋz) + 1 − r)·|z|^n] (yield "
        "travel x_y, knee sharpness n, unloading shape r; Dahl is n = 1, r = 1)"),
    EffectSpec("contact_law", "stiffness", (
        _P("scale", "-", lambda s: (0.05, 5.0), lambda s: 1.0, 1.0),
        _P("beta", "-", lambda s: (0.3, 1.2), lambda s: 2.0 / 3.0, 2.0 / 3.0)),
        "contact compliance c_hertz·scale with exponent beta (Hertz: 1, 2/3)", ("chain",)),
    EffectSpec("slack", "stiffness", (
        _P("s", "mm", lambda s: (-5.0 * s.x, 5.0 * s.x), lambda s: 0.0, 0.0),),
        "displacement offset s (permanent elongation, clearance, sensor zero)", ("chain",)),
    EffectSpec("backlash", "play", (
        _P("b", "mm", lambda s: (0.0, 2.0 * s.x), lambda s: 0.1 * s.x, 0.0),),
        "dead band b of travel after each reversal (play in series with the spring)"),
    EffectSpec("deadband", "force", (
        _P("k_d", "N/mm^p", lambda s: (0.0, 100.0 * s.F / min(s.x, 1.0) ** 4),
           lambda s: s.F / s.x, 0.0, amplitude=True),
        _P("g", "mm", lambda s: (0.0, 1.5 * s.x), lambda s: 0.5 * s.x, 0.0),
        _P("p", "-", lambda s: (1.0, 4.0), lambda s: 1.5, 1.0, limits=(True, False)),
        _P("x_c", "mm", lambda s: (s.x_mid - s.x, s.x_mid + s.x), lambda s: s.x_mid, 0.0)),
        "backlash with hardening contacts (end stops): a dead band of half-width g about x_c, then power-law "
        "stiffening k_d·(|x − x_c| − g)^p on each side"),
    EffectSpec("hardening", "force", (
        _P("k3", "N/mm^3", lambda s: (-100 * s.F / s.x ** 3, 100 * s.F / s.x ** 3),
           lambda s: 0.0, 0.0, amplitude=True),
        _P("k2", "N/mm^2", lambda s: (-100 * s.F / s.x ** 2, 100 * s.F / s.x ** 2),
           lambda s: 0.0, 0.0, amplitude=True),
        _P("x_ref", "mm", lambda s: (s.x_mid, s.x_mid), lambda s: s.x_mid, 0.0, fitted=False)),
        "nonlinear spring of a non-chain base: k3·(x − x_ref)³ + k2·(x − x_ref)² about the training data's mean "
        "displacement x_ref (k3 > 0 hardening, < 0 softening; k2 an asymmetry)", ("linear",)),
    EffectSpec("machine_compliance", "stiffness", (
        _P("c", "mm/N", lambda s: (0.0, 100.0 * s.x / s.F), lambda s: 0.01 * s.x / s.F, 0.0),),
        "series compliance c of test machine / fixture (searched up to 100 times the data's own x/F)", ("chain",)),
    EffectSpec("fixture_mass", "mass", (
        _P("m_f", "kg", lambda s: (0.0, 10.0 * s.F * 1e3 / max(s.x * s.omega ** 2, 1e-9)),
           lambda s: 0.0, 0.0, amplitude=True),),
        "extra moving mass m_f (fixture, load cell, clamp) of a chain base: m_f·ẍ", ("chain",)),
    EffectSpec("sensor_delay", "delay", (
        _P("tau", "s", lambda s: (-s.lag, s.lag), lambda s: 0.0, 0.0),),
        "channel lag: the force lags the displacement by tau (tau < 0: the displacement lags the force)"),
    EffectSpec("damping_law", "damping", (
        _P("eta", "-", lambda s: (0.0, 2.0), lambda s: 0.0, 0.0),
        _P("F_f", "N", lambda s: (0.0, 5 * s.F), lambda s: 0.0, 0.0)),
        "extra damping form: hysteretic eta·k_e(x0)/ω + Coulomb-equivalent 4F_f/(πωA) (harmonic route); on any "
        "excitation, a damping law over record features c = c0 + b_w·(ω_r − w_ref) + b_A·(A_r − A_ref)"),
)}

#: the damping law of the time-domain route (its own parameters: slopes over record features)
TIME_DAMPING_LAW = EffectSpec("damping_law", "damping", (
    _P("b_w", "N·s²/mm", lambda s: (-INF, INF), lambda s: 0.0, 0.0, amplitude=True),
    _P("b_A", "N·s/mm²", lambda s: (-INF, INF), lambda s: 0.0, 0.0, amplitude=True),
    _P("w_ref", "rad/s", lambda s: (0.0, 0.0), lambda s: 0.0, 0.0, fitted=False),
    _P("A_ref", "mm", lambda s: (0.0, 0.0), lambda s: 0.0, 0.0, fitted=False),
    *(_P(k, u, lambda s: (0.0, 0.0), lambda s: 0.0, 0.0, fitted=False)
      for k, u in (("w_lo", "rad/s"), ("w_hi", "rad/s"), ("A_lo", "mm"), ("A_hi", "mm")))),
    "the record's viscous damping follows a law over record features: c_r = c0 + b_w·(ω_r − w_ref) + "
    "b_A·(A_r − A_ref), ω_r the band centre [rad/s], A_r the half range of x [mm], within the box of features "
    "[w_lo, w_hi] × [A_lo, A_hi] it was identified on")

#: library order: the effects of the first release first (the order candidates are tried and listed in)
EFFECT_NAMES: tuple[str, ...] = ("stiffness_level", "friction", "hysteresis", "contact_law", "slack", "backlash",
                                 "machine_compliance", "sensor_delay", "damping_law", "stribeck", "bouc_wen",
                                 "deadband", "hardening", "fixture_mass")
assert set(EFFECT_NAMES) == set(SPECS)
#: effects that change the stiffness model itself (composed first; the other effects act on the result)
STIFFNESS_SIDE = tuple(n for n, s in SPECS.items() if s.kind == "stiffness")
#: neutral parameter values of every effect
DEFAULTS: dict[str, dict[str, float]] = {n: {p.name: p.default for p in s.params} for n, s in SPECS.items()}


def valid_range(effect: str, param: str) -> tuple[float, float]:
    """The physical validity range (lo, hi) of an effect's parameter, in its unit, from the one table of
    :mod:`chainid.model.ranges` (model files, --effect)."""
    from chainid.model.ranges import EFFECT_RANGES

    if effect not in SPECS:
        raise ValueError(f"effect = {effect!r} is unknown; valid: {', '.join(EFFECT_NAMES)}")
    rng = EFFECT_RANGES[effect].get(param)
    if rng is None:
        raise ValueError(f"effect {effect!r}: unknown parameter {param!r}; valid: {', '.join(EFFECT_RANGES[effect])}")
    return rng.lo, rng.hi


def pinned(key: str, u: float, lo: float) -> bool:
    """Whether a fitted ``effect.param`` at unit-box position u (0 its lower, 1 its upper fit bound) is pinned at a
    bound in the sense of the step rule (its form does not fit there): at the upper bound, or at a nonzero lower
    bound — unless the library declares that end a legitimate limit of the form (``Param.limits``)."""
    eff, _, par = key.partition(".")
    spec = SPECS.get(eff)
    lim = next((p.limits for p in spec.params if p.name == par), (False, False)) if spec else (False, False)
    if u >= 1 - 1e-6:
        return not lim[1]
    if u <= 1e-6 and lo != 0.0:
        return not lim[0]
    return False


def identifiable(effect: str, param: str, base: str) -> bool:
    """Whether an effect's parameter can be told apart on a base kind (``chain`` or ``linear``): a load-dependent
    friction μ·|F_k| needs the chain's own spring force (on a linear spring it is the spring times a sign), and a
    direction asymmetry (a constant force while sliding) needs a base with an absolute zero of force — a linear
    device's preload or force offset absorbs it."""
    if base != "chain" and (effect, param) in (("friction", "mu"), ("stribeck", "dF")):
        return False
    return True


def applies_to(effect: str, base: str) -> bool:
    """Whether a library effect applies to a base model kind (``chain`` or ``linear``)."""
    return base in SPECS[effect].bases


@dataclass
class Effect:
    """One named effect with fit bounds set from the data scales (:func:`make_effect`).

    Attributes
    ----------
    name : str
        One of :data:`EFFECT_NAMES`.
    param_names, units : tuple of str
        The fitted parameters (fixed references such as ``hardening.x_ref`` are in ``fixed``).
    bounds : tuple of (low, high)
        Fit bounds of each fitted parameter.
    x0_guess : tuple of float
        Start values for the fit.
    chain_only : bool
        Only meaningful for a nonlinear (chain) stiffness model.
    amplitude : tuple of bool
        Per fitted parameter: enters the force linearly.
    fixed : dict
        Parameters that are references, not fitted (their values from the data scales).
    """

    name: str
    param_names: tuple[str, ...]
    units: tuple[str, ...]
    bounds: tuple[tuple[float, float], ...]
    x0_guess: tuple[float, ...]
    chain_only: bool = False
    description: str = ""
    amplitude: tuple[bool, ...] = ()
    fixed: dict[str, float] = field(default_factory=dict)
    linear_only: bool = False
    kind: str = "force"

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
            if not (math.isfinite(v) and lo <= v <= hi):
                raise ValueError(f"effect {self.name!r}: {k} = {v!r} is out of range; valid range {lo:g} to {hi:g}")


def make_effect(name: str, F_scale: float = 1e4, x_scale: float = 1.0, omega_max: float = 10.0, *,
                v_scale: float | None = None, x_mid: float = 0.0, tau_max: float | None = None,
                time_domain: bool = False) -> Effect:
    """The library entry ``name`` with fit bounds set from the data scales.

    Parameters
    ----------
    name : str
        One of :data:`EFFECT_NAMES`.
    F_scale : float
        Force scale of the data, e.g. RMS(F − mean F) [N] (> 0).
    x_scale : float
        Displacement scale, e.g. the largest amplitude [mm] (> 0).
    omega_max : float
        Largest test frequency [rad/s] (> 0); bounds the delay to ± half its period (π/ω_max) unless ``tau_max``.
    v_scale : float, optional
        Velocity scale [mm/s] (the Stribeck velocity's range); default x_scale·omega_max.
    x_mid : float
        Mean displacement [mm] (the reference of ``hardening``, the centre of ``deadband``).
    tau_max : float, optional
        Largest lag to search [s] (``sensor_delay``).
    time_domain : bool
        ``damping_law`` in its time-domain form (slopes over record features) instead of the harmonic one.
    """
    if name not in SPECS:
        raise ValueError(f"effect = {name!r} is unknown; valid: {', '.join(EFFECT_NAMES)}")
    F_scale = float(max(F_scale, 1e-9))
    x_scale = float(max(x_scale, 1e-9))
    omega_max = float(max(omega_max, 1e-9))
    sc = Scales(F_scale, x_scale, omega_max, float(v_scale) if v_scale else x_scale * omega_max, float(x_mid),
                tau_max)
    spec = TIME_DAMPING_LAW if (name == "damping_law" and time_domain) else SPECS[name]
    fit = [p for p in spec.params if p.fitted]
    return Effect(spec.name, tuple(p.name for p in fit), tuple(p.unit for p in fit),
                  tuple(p.bounds(sc) for p in fit), tuple(p.guess(sc) for p in fit),
                  chain_only=spec.bases == ("chain",), description=spec.description,
                  amplitude=tuple(p.amplitude for p in fit),
                  fixed={p.name: p.guess(sc) for p in spec.params if not p.fitted},
                  linear_only=spec.bases == ("linear",), kind=spec.kind)
