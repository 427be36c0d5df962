"""The augmented model: base spring + stiffness-side corrections + memory effects + damping + delay + mass.

F(t) = m·ẍ + F_k'(x) + Σ memory-effect forces + F_d, all evaluated at t − τ (a force channel lagging the
displacement by τ), where F_k' is the base (chain kernels of a variant, or a linear spring k·(x − x_ref))
with the stiffness-side effects applied (``stiffness_level``, ``contact_law``, ``slack``,
``machine_compliance``), the memory effects are the causal operators of :mod:`chainid.operators`
(``friction``: Jenkins element with stick; ``hysteresis``: Dahl; ``backlash``: play) and F_d a
time-domain damping (:mod:`chainid.timedamping`).  The effect names and parameters are those of the gap
library (:mod:`chainid.model.effects`, :func:`~chainid.model.effects.undamped_force` composes them: one place),
so a diagnosis step (``effects`` + ``params``) rebuilds a model exactly.

Operating conditions: ``covariate_terms`` maps ``effect.param@cov`` (or ``damping.c@cov``, ``spring.k@cov``) to
a slope, so that for a record with covariates the parameter is p + slope·(cov − ref), ``covariate_refs`` the ref of
each covariate.  ``offsets``: the tests ran at different preloads, so each record's force offset is a nuisance
parameter (a prediction takes the record's own mean residual).

Two evaluations:

* :meth:`AugmentedModel.force` — any sampled x(t) (uniform or not): ẋ, ẍ by ``np.gradient`` with t, the
  operators run forward from their stated initial state, the damping law resolved at the record's dominant
  ω and A (:func:`chainid.timedamping.dominant`);
* :meth:`AugmentedModel.cycle_parts` — the diagnosis' steady-cycle evaluation on a prepared test's phase grid
  (operators in their periodic steady state), which reproduces the diagnosis' predictions exactly.

Units: t s, x mm, F N, m kg (m·ẍ·1e-3 = N), τ s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Sequence

import numpy as np

from chainid.model.effects import DEFAULTS, EFFECT_NAMES, make_effect, undamped_force
from chainid.model.ranges import EFFECT_RANGES, MODEL_RANGES, check_number
from chainid.model.timedamping import Damping, dominant, record_features

#: effects that are not force terms of the model (the delay is ``delay_s``; ``damping_law`` is the law choice)
NOT_FORCE = ("sensor_delay", "damping_law")


@dataclass
class AugmentedModel:
    """A runnable model of one device (see the module docstring).

    Parameters
    ----------
    base : StiffnessModel
        :class:`chainid.models.ChainModel` (unmodified kernels of a variant) or
        :class:`chainid.models.LinearModel` (k [N/mm], x_ref [mm]).
    effects : list of (name, params)
        Ordered gap-library effects other than ``sensor_delay`` / ``damping_law`` (params in their units).
    damping : Damping
        Time-domain damping or an identified law (:class:`chainid.timedamping.Damping`).
    delay_s : float
        Lag τ [s] of the force channel: F_meas(t) = F(t − τ).
    mass_kg : float or None
        Moving mass m [kg] (None: the base's).
    baseline : AugmentedModel or None
        The model this one is compared with (``predict``'s baseline), e.g. the diagnosis' step 0.
    info : dict
        Free metadata (variant, chain, provenance) carried to the model file.
    offsets : bool
        Per-record force offsets are nuisance parameters (tests at different preloads).
    covariate_terms, covariate_refs : dict
        Slopes of parameters over covariates and the covariates' reference values (module docstring).
    """

    base: Any
    effects: list[tuple[str, dict[str, float]]] = field(default_factory=list)
    damping: Damping = field(default_factory=Damping)
    delay_s: float = 0.0
    mass_kg: float | None = None
    baseline: "AugmentedModel | None" = None
    info: dict[str, Any] = field(default_factory=dict)
    offsets: bool = False
    covariate_terms: dict[str, float] = field(default_factory=dict)
    covariate_refs: dict[str, float] = field(default_factory=dict)

    def __post_init__(self) -> None:
        chain = hasattr(self.base, "hertz_scale")
        out = []
        for name, params in self.effects:
            if name not in EFFECT_NAMES or name in NOT_FORCE:
                valid = ", ".join(n for n in EFFECT_NAMES if n not in NOT_FORCE)
                raise ValueError(f"effect {name!r} is not a model force term; valid: {valid} "
                                 "(sensor_delay is delay_s, damping_law is the damping)")
            eff = make_effect(name)
            if eff.chain_only and not chain and name not in ("slack", "machine_compliance"):
                raise ValueError(f"effect {name!r} needs a chain base (the base is a linear spring)")
            unknown = set(params) - set(eff.param_names) - set(eff.fixed)
            if unknown:
                raise ValueError(f"effect {name!r}: unknown parameter(s) {sorted(unknown)}; "
                                 f"valid: {', '.join(list(eff.param_names) + list(eff.fixed))}")
            # the valid ranges of the one table (chainid.model.ranges); implausible values are the loader's warnings
            checked = {k: check_number(v, EFFECT_RANGES[name][k], f"effect {name!r}: {k}")[0]
                       for k, v in params.items()}
            out.append((name, dict(DEFAULTS[name]) | checked))
        self.effects = out
        self.delay_s = check_number(self.delay_s, MODEL_RANGES["delay_s"], "delay_s")[0]
        if self.mass_kg is not None:
            self.mass_kg = check_number(self.mass_kg, MODEL_RANGES["mass_kg"], "mass_kg")[0]
        for term, v in self.covariate_terms.items():
            head, at, cov = term.partition("@")
            if not at or "." not in head or not cov:
                raise ValueError(f"covariate term {term!r} is invalid; valid: 'effect.param@covariate' "
                                 "(e.g. friction.F_c@i, damping.c@i, spring.k@p)")
            if not math.isfinite(float(v)):
                raise ValueError(f"covariate term {term} = {v!r} must be finite")
            if cov not in self.covariate_refs:
                raise ValueError(f"covariate term {term!r}: covariate {cov!r} has no reference value in "
                                 f"covariate_refs (known: {', '.join(self.covariate_refs) or 'none'})")

    def at_conditions(self, covariates: dict[str, float] | None) -> "AugmentedModel":
        """The model at a record's operating conditions: every covariate term applied (p + slope·(cov − ref)).

        Raises
        ------
        ValueError
            A covariate the model depends on is missing from ``covariates``.
        """
        if not self.covariate_terms:
            return self
        from dataclasses import replace as _replace

        cov = dict(covariates or {})
        effects = [(n, dict(p)) for n, p in self.effects]
        damping = self.damping
        base = self.base
        for term, slope in self.covariate_terms.items():
            head, _, name = term.partition("@")
            if name not in cov:
                raise ValueError(f"the model depends on covariate {name!r} ({term}); the record carries "
                                 f"{', '.join(cov) or 'none'}")
            dv = float(slope) * (float(cov[name]) - self.covariate_refs[name])
            eff, _, par = head.partition(".")
            if eff == "damping" and par == "c":
                damping = _replace(damping, params=dict(damping.params) | {"c": damping.params.get("c", 0.0) + dv})
            elif eff == "spring" and par == "k":
                base = _replace(base, k=max(float(base.k) + dv, 0.0))
            else:
                for n, p in effects:
                    if n == eff:
                        p[par] = p.get(par, 0.0) + dv
        return _replace(self, base=base, effects=effects, damping=damping, covariate_terms={})

    # ------------------------------------------------------------------ helpers
    @property
    def mass(self) -> float:
        """Moving mass m [kg]."""
        return float(self.base.mass_kg if self.mass_kg is None else self.mass_kg)

    def ke(self, x0: float) -> float:
        """k_e [N/mm] the damping law uses: the law's fixed k_e, else the base's tangent stiffness at x0 [mm]."""
        if self.damping.k_e is not None:
            return float(self.damping.k_e)
        return float(np.asarray(self.base.stiffness(np.array([float(x0)])), float)[0])

    def _mass_fix(self, xdd: np.ndarray) -> np.ndarray | float:
        dm = self.mass - float(getattr(self.base, "mass_kg", 0.0))
        return dm * xdd * 1e-3 if dm != 0.0 else 0.0

    # ------------------------------------------------------------------ evaluations
    def cycle_parts(self, d: Any) -> tuple[np.ndarray, np.ndarray]:
        """Bin means of the undamped force [N] and of the damped velocity [mm/s] on a prepared test's phase grid.

        ``d`` is a :class:`chainid.gap.harmonic.prepare.TestData` (phase grid, smooth periodic x(t), ω, A, x0); the
        operators run in their periodic steady state, exactly as the diagnosis evaluates a step.
        """
        g = d.grid
        t, x, xd, xdd = g["t"], g["x"], g["xd"], g["xdd"]
        if self.delay_s != 0.0:
            x, xd, xdd = d.xfun(t - self.delay_s)
        Fn = undamped_force(self.effects, self.base, t, x, xd, xdd, d.omega, d.A, d.x0, d.xfun) + self._mass_fix(xdd)
        return d.gridmean(Fn), d.gridmean(xd)

    def cycle_force(self, d: Any, fitted: bool = False) -> np.ndarray:
        """Model force bin means [N] of a prepared harmonic test (damping: the law at the test's ω, A, x0; with
        ``fitted`` the per-test c_e of a test the law was fitted on)."""
        Fn, v = self.cycle_parts(d)
        dmp = self.damping.resolve(d.omega, d.A, self.ke(d.x0), d.test, fitted, d.x0)
        if dmp.form == "viscous":
            return Fn + dmp.params["c"] * v
        # a rate-independent form: evaluate on the grid in its periodic steady state
        g = d.grid
        x, xd = (g["x"], g["xd"]) if self.delay_s == 0.0 else d.xfun(g["t"] - self.delay_s)[:2]
        return Fn + d.gridmean(dmp.force(x, xd, periodic=True)[0])

    def force(self, t: Sequence[float], x: Sequence[float], return_parts: bool = False,
              xd: Sequence[float] | None = None, xdd: Sequence[float] | None = None,
              v_err: float | np.ndarray = 0.0) -> Any:
        """Model force F(t) [N] for any sampled x(t) [s, mm] (uniform or not, strictly increasing t).

        ẋ, ẍ by ``np.gradient`` with t; the force channel lags by τ (inputs interpolated at t − τ, held at
        the ends); memory operators run forward from their stated initial state; a damping law is resolved at
        the record's dominant ω and A.  ``xd``, ``xdd`` [mm/s, mm/s²]: exact derivatives when known (a
        simulation), instead of the finite differences; ``v_err`` [mm/s] the RMS error of an estimated ``xd`` (the sign of
        sliding friction is then its expectation).  ``return_parts``: also a dict with the undamped force, damping force,
        dissipated-energy increments of the damping [N·mm] and the resolved damping.
        """
        t = np.asarray(t, float)
        x = np.asarray(x, float)
        if t.ndim != 1 or t.shape != x.shape or t.size < 3:
            raise ValueError(f"t and x must be 1-D of equal length >= 3; got {t.shape} and {x.shape}")
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(x))):
            raise ValueError("t or x contains NaN or infinite values")
        if np.any(np.diff(t) <= 0):
            raise ValueError("t must be strictly increasing [s]")
        xd = np.gradient(x, t) if xd is None else np.asarray(xd, float)
        xdd = None if xdd is None else np.asarray(xdd, float)
        if xd.shape != t.shape or (xdd is not None and xdd.shape != t.shape):  # before ẍ is made from ẋ
            raise ValueError(f"xd and xdd must have the shape of t {t.shape}; got {xd.shape} and "
                             f"{None if xdd is None else xdd.shape}")
        xdd = np.gradient(xd, t) if xdd is None else xdd
        if self.delay_s != 0.0:
            ts = t - self.delay_s
            x, xd, xdd = np.interp(ts, t, x), np.interp(ts, t, xd), np.interp(ts, t, xdd)
            if np.ndim(v_err):
                v_err = np.interp(ts, t, np.asarray(v_err, float))

        def xfun(ts: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
            return np.interp(ts, t, x), np.interp(ts, t, xd), np.interp(ts, t, xdd)

        w, A, x0 = dominant(t, x)
        Fn = undamped_force(self.effects, self.base, t, x, xd, xdd, w, max(A, 1e-12), x0, xfun,
                            periodic=False, v_err=v_err) + self._mass_fix(xdd)
        if self.damping.form == "feature":
            w, A = record_features(t, x)
        dmp = self.damping.resolve(w, max(A, 1e-12), self.ke(x0), x0=x0)
        Fd, dE = dmp.force(x, xd, periodic=False)
        F = Fn + Fd
        if return_parts:
            return F, {"undamped": Fn, "damping": Fd, "damping_dE": dE, "damping_form": dmp, "omega": w, "A": A}
        return F
