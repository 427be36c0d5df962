"""The diagnosis problem: prepared tests + baseline model; fits and scores any set of effects.

Method (all on whole tests, never on random samples):

* Baseline: F = m·ẍ + F_k(x) + c_e·ẋ (paper Eq. 1); c_e per training test from
  the bin means, damping law (:mod:`chainid.gap.harmonic.law_choice`) fitted on training tests
  only, held-out c_e predicted by the law.
* An effect set: its physical parameters (all of them, jointly) are fitted by
  ``scipy.optimize.least_squares`` (bounded) on the training tests, the
  per-test c_e re-identified at every step (or, for an effect set in ``ties``, every test's c_e from one
  damping law fitted with them: :mod:`chainid.gap.harmonic.tie`); score = leave-one-test-out NRMSE
  over the training tests (damping law re-fitted without the test) and BIC;
  held-out NRMSE and shrinkage are reported.

Units: mm, N, s; NRMSE = RMS(residual)/RMS(F − mean F) over whole tests.
"""

from __future__ import annotations

import math
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Any, Iterator, Sequence

import numpy as np
from scipy.optimize import least_squares

from chainid.gap.core.candidate import MIN_TRAIN, Candidate, jackknife_sd  # noqa: F401  (re-exported)
from chainid.gap.core.delayscan import refine_delay
from chainid.gap.core.fitgrid import DELAY_GRID, starts
from chainid.gap.harmonic import law_choice as L
from chainid.gap.harmonic.bin_fits import damping_separable, linear_start  # noqa: F401  (re-exported)
from chainid.gap.harmonic.prepare import TestData
from chainid.model.effects import (EFFECT_NAMES, STIFFNESS_SIDE, changed_model, identifiable, make_effect, pinned,
                                   undamped_force)


def _ce(d: TestData, Fn: np.ndarray, v: np.ndarray) -> float:
    """c_e of one test [N·s/mm]: the count-weighted least-squares projection of what the undamped model leaves,
    F̄ − F_n, on the damping velocity v (bin means) — Eq. 27 on the cycle-averaged loop."""
    return float(np.sum(d.counts * (d.Fbar - Fn) * v) / max(np.sum(d.counts * v * v), 1e-300))


#: most remembered (effect set, parameters, test) evaluations of a problem (:meth:`Problem._parts`)
PARTS_MEMO = 20_000
#: relative tolerance (of the cost and of the unit-scaled parameters) of a polish refit
POLISH_TOL = 1e-5
#: most evaluations of a polish refit (it converges in 3 or 4 from a nearby optimum)
POLISH_NFEV = 12


class Problem:
    """Prepared data + baseline model; evaluates any effect set.

    Parameters
    ----------
    data : sequence of TestData
    model : StiffnessModel
        Baseline stiffness (chain model or linear spring).
    holdout : sequence of str
        Held-out test ids.
    damping_law : str
        Baseline law name or "auto" (:func:`chainid.gap.harmonic.law_choice.choose`).
    fit_mass : bool
        A linear baseline fits its moving mass (>= 0) with its spring (False: the model's mass, e.g. ``--mass``).
    """

    def __init__(self, data: Sequence[TestData], model: Any, holdout: Sequence[str], damping_law: str = "auto",
                 require_hold: bool = True, fit_mass: bool = False):
        self.data = list(data)
        self.model = model
        self.fit_mass = bool(fit_mass) and not hasattr(model, "hertz_scale")
        ids = [d.test for d in self.data]
        unknown = [h for h in holdout if h not in ids]
        if unknown:
            raise ValueError(f"--holdout: test id(s) {unknown} not in the usable data; usable ids: {', '.join(ids)}")
        hs = set(holdout)
        self.hold = [d for d in self.data if d.test in hs]
        self.train = [d for d in self.data if d.test not in hs]
        if not self.hold and require_hold:  # (a mixed set may hold out only time-domain records)
            raise ValueError("--holdout: no test held out; give at least one test id")
        if len(self.train) < MIN_TRAIN:
            raise ValueError(
                f"--holdout leaves {len(self.train)} usable training test(s); at least {MIN_TRAIN} are needed "
                "(a damping law fitted and scored leave-one-test-out needs >= 3 tests)"
            )
        allF = np.concatenate([d.Fbar for d in self.data])
        self.F_scale = float(np.std(allF)) or 1.0
        self.x_scale = float(max(d.A for d in self.data))
        self.omega_max = float(max(d.omega for d in self.data))
        self.is_chain = hasattr(model, "hertz_scale")
        self.ke = {d.test: float(np.asarray(model.stiffness(np.array([d.x0])), float)[0]) for d in self.data}
        self.sigma_raw = float(np.sqrt(np.mean([d.sigma**2 for d in self.data])))
        self._mult: np.ndarray | None = None  # multiplicities of the training tests in a fit (a resample)
        #: effect sets (sorted names) whose fits tie the training tests' c_e to a damping law (:meth:`tied`)
        self.ties: dict[tuple[str, ...], str] = {}
        self._own = {d.test: d for d in self.data}
        self._memo: dict[tuple, tuple[np.ndarray, np.ndarray]] = {}
        self._fk: dict[tuple, np.ndarray] = {}
        self._start: dict[str, float] | None = None
        x_mid = float(np.mean([d.x0 for d in self.data]))
        v_max = float(max(d.omega * d.A for d in self.data))
        self.effects = {n: make_effect(n, self.F_scale, self.x_scale, self.omega_max, v_scale=v_max, x_mid=x_mid)
                        for n in EFFECT_NAMES}
        self.law, self.law_reason = self._baseline_law(damping_law)

    # ------------------------------------------------------------- damping law
    def _baseline_law(self, choice: str) -> tuple[str, str]:
        if choice != "auto":
            if choice not in L.LAWS:
                raise ValueError(f"--damping-law = {choice!r} is unknown; valid: {', '.join(L.CHOICES)}")
            if L.LAWS[choice] > len(self.train) - 1:
                raise ValueError(f"--damping-law {choice} has {L.LAWS[choice]} coefficients; with "
                                 f"{len(self.train)} training tests at most {len(self.train) - 1} can be scored "
                                 "leave-one-out: choose a simpler law or 'auto'")
            return choice, "given"
        ok, _ = damping_separable(self.train)
        if ok:
            return "polynomial", "the paper's Eq. 21 (the plan separates ω and A)"
        c = self._ce_baseline()
        cand = L.allowed(len(self.train), ("viscous", "coulomb", "hysteretic", "viscous+coulomb"))
        w, A, k = self._wak(self.train)
        best, errs = L.choose(w, A, k, np.array([c[d.test] for d in self.train]), cand)
        txt = ", ".join(f"{n} {e:.3g}" for n, e in sorted(errs.items(), key=lambda z: z[1]))
        return best, (f"leave-one-out best of the laws with <= {len(self.train) - 1} coefficient(s) "
                      f"(c_e LOO RMS N·s/mm: {txt}); the plan cannot fit Eq. 21's 5 coefficients")

    def _ce_baseline(self) -> dict[str, float]:
        out = {}
        for d in self.train:
            out[d.test] = _ce(d, *self._parts([], self._spring_start(), d))
        return out

    def _wak(self, ds: Sequence[TestData]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        return (np.array([d.omega for d in ds]), np.array([d.A for d in ds]),
                np.array([self.ke[d.test] for d in ds]))

    def laws_for(self, names: Sequence[str]) -> list[str]:
        """Damping laws a candidate is scored with (the baseline's, viscous; alternatives for ``damping_law``)."""
        n = len(self.train)
        if "damping_law" in names:
            return L.allowed(n, [k for k in L.ALT_LAWS if k != self.law]) or [self.law]
        out = [self.law]
        if names and self.law != "viscous":
            out.append("viscous")
        return out

    # ------------------------------------------------------------------- model
    def _spring_start(self) -> dict[str, float]:
        """Start of a linear base's spring (and mass, when fitted): :func:`linear_start` on the training tests, the
        given model's spring when that fails; {} for a chain."""
        if self.is_chain or not hasattr(self.model, "k"):
            return {}
        if self._start is None:
            m0 = float(getattr(self.model, "mass_kg", 0.0))
            self._start = linear_start(self.train, self.fit_mass, m0) or {
                "spring.k": float(self.model.k), "spring.x_ref": float(self.model.x_ref)}
        return self._start

    def model_for(self, p: dict[str, float]) -> Any:
        """The stiffness model, with a re-fitted linear spring when ``spring.k`` is in p."""
        if "spring.k" in p:
            from chainid.model.base import LinearModel

            m = max(float(p["spring.m"]), 0.0) if "spring.m" in p else float(getattr(self.model, "mass_kg", 0.0))
            return LinearModel(max(p["spring.k"], 0.0), p["spring.x_ref"], mass=m)
        return self.model

    def applicable(self) -> list[str]:
        """Library effects that apply to this baseline (chain-only effects need the chain model, linear-only ones a
        linear spring)."""
        return [n for n, e in self.effects.items()
                if not (e.chain_only and not self.is_chain) and not (e.linear_only and self.is_chain)]

    def parts(self, names: Sequence[str], p: dict[str, float], d: TestData) -> tuple[np.ndarray, np.ndarray]:
        """Bin means of the undamped force [N] and of the damping velocity [mm/s] of an effect set on a
        prepared harmonic test (any test: also one outside this problem, e.g. for a transfer)."""
        return self._parts(names, p, d)

    def _parts(self, names: Sequence[str], p: dict[str, float], d: TestData) -> tuple[np.ndarray, np.ndarray]:
        """Bin means of the undamped force [N] and of the velocity the damping acts on [mm/s], remembered per test
        of this problem, effect set and parameters (a resample's refits all start from the same parameters; a score
        evaluates those a fit ended at; at most ``PARTS_MEMO`` entries of 2 × n_bins numbers)."""
        key = (tuple(names), tuple(sorted(p.items())), d.test)
        return self._remembered(self._memo, key, d, lambda: self._compute_parts(names, p, d))

    def _remembered(self, store: dict[tuple, Any], key: tuple, d: TestData, make: Any) -> Any:
        """``store[key]`` for a test of this problem, made by ``make()`` on a miss (its arrays read-only: shared by
        every caller of the key); at most ``PARTS_MEMO`` entries, the store emptied when full.  A test from outside
        the problem (a transfer's) is made every time, never stored."""
        mine = self._own.get(d.test) is d
        if mine and key in store:
            return store[key]
        out = make()
        for a in out if isinstance(out, tuple) else (out,):
            a.setflags(write=False)
        if mine:
            if len(store) >= PARTS_MEMO:
                store.clear()
            store[key] = out
        return out

    def _compute_parts(self, names: Sequence[str], p: dict[str, float], d: TestData
                       ) -> tuple[np.ndarray, np.ndarray]:
        model = self.model_for(p)
        eff = [(n, {k.split(".", 1)[1]: val for k, val in p.items() if k.startswith(n + ".")}) for n in names]
        g = d.grid
        t, x, xd, xdd = g["t"], g["x"], g["xd"], g["xdd"]
        tau = float(p.get("sensor_delay.tau", 0.0)) if "sensor_delay" in names else 0.0
        if "sensor_delay" in names:  # the force channel lags the whole force: evaluate everything at t − τ
            x, xd, xdd = d.xfun(t - tau)
        Fk = self._spring(d, eff, p, model, x, tau)
        Fn = undamped_force(eff, model, t, x, xd, xdd, d.omega, d.A, d.x0, d.xfun, Fk=Fk)
        v = xd
        return d.gridmean(Fn), d.gridmean(v)

    def _spring(self, d: TestData, eff: list[tuple[str, dict[str, float]]], p: dict[str, float], model: Any,
                x: np.ndarray, tau: float) -> np.ndarray:
        """The spring force [N] at x (lagged by ``tau`` [s]) of the model as the stiffness-side effects change it,
        kept per test of this problem between the evaluations of a fit that moves only the other effects'
        parameters (it depends on the stiffness-side parameters, a fitted linear spring and the lag alone)."""
        side = tuple((n, tuple(sorted(pp.items()))) for n, pp in eff if n in STIFFNESS_SIDE)
        key = (d.test, side, tau,
               tuple(sorted((k, v) for k, v in p.items() if k.startswith("spring."))))
        return self._remembered(self._fk, key, d, lambda: np.asarray(changed_model(eff, model).force(x), float))

    def evaluate(self, names: Sequence[str], p: dict[str, float], law: str | None = None) -> dict[str, Any]:
        """Errors of an effect set with parameters ``p`` and damping law ``law`` (default: the baseline's)."""
        law = law or self.law
        parts = {d.test: self._parts(names, p, d) for d in self.data}
        c_e = {d.test: _ce(d, *parts[d.test]) for d in self.data}
        tr, ho = self.train, self.hold
        X = L.design(law, *self._wak(tr))
        cv = np.array([c_e[d.test] for d in tr])
        lp, cloo = L.fit_loo(X, cv)
        c_hold = L.design(law, *self._wak(ho)) @ lp

        def res(d: TestData, c: float) -> np.ndarray:
            Fn, v = parts[d.test]
            return d.Fbar - Fn - c * v

        def sse(d: TestData, c: float) -> float:
            return float(np.sum(d.counts * res(d, c) ** 2))

        def var(d: TestData) -> float:
            return float(np.sum(d.counts * (d.Fbar - np.sum(d.counts * d.Fbar) / np.sum(d.counts)) ** 2))

        def nrmse(ds: Sequence[TestData], cs: Sequence[float]) -> float:
            den = sum(var(d) for d in ds)
            return math.sqrt(sum(sse(d, c) for d, c in zip(ds, cs)) / den) if den > 0 else float("nan")

        loto_num = {d.test: sse(d, c) for d, c in zip(tr, cloo)}
        chi2 = sum(sse(d, c_e[d.test]) / d.sigma**2 for d in tr)
        per_test = {d.test: nrmse([d], [c]) for d, c in zip(ho, c_hold)}
        per_test.update({d.test: nrmse([d], [c_e[d.test]]) for d in tr})
        return {
            "nrmse_train": nrmse(tr, [c_e[d.test] for d in tr]),
            "nrmse_loto": nrmse(tr, cloo),
            "nrmse_holdout": nrmse(ho, c_hold),
            "loto_num": loto_num,
            "chi2": chi2,
            "law_params": [float(v) for v in lp],
            "c_e": c_e,
            "c_hold": dict(zip([d.test for d in ho], c_hold)),
            "parts": parts,
            "per_test": per_test,
            "res": {d.test: res(d, c) for d, c in zip(ho, c_hold)} | {d.test: res(d, c) for d, c in zip(tr, cloo)},
        }

    def n_cells(self, split: str = "train") -> int:
        """Independent noise cells of a split: the phase bins of its tests."""
        return sum(d.counts.size for d in (self.hold if split == "hold" else self.train))

    def noise_db(self, ev: dict[str, Any], split: str = "hold") -> tuple[float, float, float]:
        """Mean squared bin residual, its noise floor (σ²/n per bin) [N²] and the ratio in dB."""
        ds = self.hold if split == "hold" else self.train
        nb = self.n_cells(split)
        r2 = sum(float(np.sum(ev["res"][d.test] ** 2)) for d in ds) / nb
        f2 = sum(float(np.sum(d.sigma**2 / np.maximum(d.counts, 1))) for d in ds) / nb
        return r2, f2, 10 * math.log10(max(r2, 1e-300) / max(f2, 1e-300))

    def state_table(self, ev: dict[str, Any]) -> dict[str, Any]:
        """The state of every phase bin (x, ẋ, ẍ, travel since the reversal, direction, x a quarter period earlier,
        the model force) and the residual of evaluation ``ev``, split into training and held-out tests, for the
        model-free check (:mod:`chainid.gap.core.openworld`)."""
        rows: dict[str, list[Any]] = {"Xt": [], "rt": [], "Xh": [], "rh": [], "uh": []}
        hold = {d.test for d in self.hold}
        for d in self.data:
            g = d.grid
            xb, vb, ab = d.gridmean(g["x"]), d.gridmean(g["xd"]), d.gridmean(g["xdd"])
            B = d.counts.size
            psi = 2 * math.pi * (np.arange(B) + 0.5) / B
            travel = np.where(vb > 0, xb - (d.x0 - d.A), (d.x0 + d.A) - xb)
            r = ev["res"][d.test]
            X = np.column_stack([xb, vb, ab, travel, np.sign(vb), d.x0 - d.A * np.cos(psi), d.Fbar - r])
            k = "h" if d.test in hold else "t"
            rows["X" + k].append(X)
            rows["r" + k].append(r)
            if k == "h":
                rows["uh"].append(np.full(B, d.test))
        cat = lambda k: np.concatenate(rows[k]) if rows[k] else np.zeros(0)  # noqa: E731
        return {"X_train": cat("Xt"), "r_train": cat("rt"), "X_hold": cat("Xh"), "r_hold": cat("rh"),
                "unit_hold": cat("uh"), "names": ["x", "xd", "xdd", "travel", "direction", "x_lag", "load"]}

    # --------------------------------------------------------------------- fit
    @contextmanager
    def tied(self, names: Sequence[str], law: str) -> Iterator[None]:
        """Within the block, fits of the effect set ``names`` tie every training test's c_e to ``law``
        (:mod:`chainid.gap.harmonic.tie`); outside it each test's c_e is its own again."""
        key = tuple(sorted(names))
        self.ties[key] = law
        try:
            yield
        finally:
            del self.ties[key]

    def _tied_law(self, names: Sequence[str]) -> str | None:
        """The law an effect set's c_e are tied to (:meth:`tied`), or None: each test's own."""
        return self.ties.get(tuple(sorted(names)))

    def _train_resid(self, names: Sequence[str], p: dict[str, float]) -> np.ndarray:
        """Whitened residuals of the training tests, each weighted by √(its multiplicity) in a resample (the same
        sum of squares as the test repeated, without evaluating it again).  Each test's c_e is its own projection,
        or, for an effect set in :attr:`ties`, the tied law's c_e(ω, A) with coefficients fitted over the tests."""
        law = self._tied_law(names)
        rows = []
        for i, d in enumerate(self.train):
            Fn, v = self._parts(names, p, d)
            w = np.sqrt(d.counts) if self._mult is None else np.sqrt(d.counts * self._mult[i])
            rows.append((w / d.sigma, Fn, v))
        if law is None:
            return np.concatenate([w * (d.Fbar - Fn - _ce(d, Fn, v) * v) for d, (w, Fn, v) in zip(self.train, rows)])
        X = L.design(law, *self._wak(self.train))
        # c_e,r = X_r·b for every test: the residual is linear in b, projected out over all tests at once
        D = np.concatenate([(w * v)[:, None] * X[i][None, :] for i, (w, _, v) in enumerate(rows)])
        y = np.concatenate([w * (d.Fbar - Fn) for d, (w, Fn, _) in zip(self.train, rows)])
        return y - D @ np.linalg.lstsq(D, y, rcond=None)[0]

    def _keys(self, names: Sequence[str]) -> tuple[list[str], list[float], list[float], list[float]]:
        keys, lo, hi, x0 = [], [], [], []
        sp = self._spring_start()
        if sp:
            k0, xr, xs = sp["spring.k"], sp["spring.x_ref"], self.x_scale
            keys += ["spring.k", "spring.x_ref"]
            lo += [0.0, xr - 2 * xs]
            hi += [max(10 * k0, 10 * self.F_scale / xs), xr + 2 * xs]
            x0 += [k0, xr]
            if self.fit_mass:  # m·ω² up to 10 times the force scale over the displacement scale
                keys.append("spring.m")
                lo.append(0.0)
                hi.append(max(10.0 * self.F_scale * 1e3 / (xs * self.omega_max ** 2), 2.0 * sp.get("spring.m", 0.0)))
                x0.append(sp.get("spring.m", 0.0))
        for n in names:
            if n == "damping_law":
                continue
            e = self.effects[n]
            for k, (a, b), g in zip(e.param_names, e.bounds, e.x0_guess):
                if not identifiable(n, k, "chain" if self.is_chain else "linear"):
                    continue  # held at its neutral value on this base
                keys.append(f"{n}.{k}")
                lo.append(a)
                hi.append(b)
                x0.append(g)
        return keys, lo, hi, x0

    def param_bounds(self, names: Sequence[str]) -> dict[str, tuple[float, float]]:
        """The fitted parameters of an effect set (the spring's on a linear baseline first) and their bounds
        [their units]."""
        keys, lo, hi, _ = self._keys(names)
        return {k: (a, b) for k, a, b in zip(keys, lo, hi)}

    def train_chi2(self, names: Sequence[str], p: dict[str, float]) -> tuple[float, int, int]:
        """χ² of the training tests at ``p`` (bin residuals over σ/√counts, each test's c_e its projection or the
        tied law's), the number of residuals and of fitted values (the parameters and one c_e per training test,
        or the tied law's coefficients)."""
        r = self._train_resid(names, p)
        law = self._tied_law(names)
        n_ce = len(self.train) if law is None else L.LAWS[law]
        return float(np.sum(r**2)), int(r.size), len(self._keys(names)[0]) + n_ce

    def fit(self, names: Sequence[str], train_only: Sequence[TestData] | None = None,
            start: dict[str, float] | None = None, polish_only: bool = False,
            weights: Sequence[float] | None = None, fix: dict[str, float] | None = None) -> Candidate:
        """Fit all parameters of an effect set jointly on the training tests.

        A full fit (not a polish, on the training tests as they are) that adds a delay then scans the delay's
        profile around the fit (:func:`chainid.gap.core.delayscan.refine_delay`; Δ: the start grid's spacing).

        Parameters
        ----------
        names : sequence of str
            Effect names.
        train_only : sequence of TestData, optional
            Fit on these tests instead of the training tests (jack-knife).
        start : dict, optional
            Start values of some parameters (e.g. the previous step's fit); the other
            effects' parameters are started from a coarse grid.
        polish_only : bool
            Only a local least-squares polish from ``start`` (jack-knife refits).
        weights : sequence of float, optional
            A multiplicity (> 0) per test fitted (a resample's draw counts), instead of 1 each.
        fix : dict, optional
            Parameters held at these values [their units] (a profile's point); the others are fitted.
        """
        c = self._fit(names, train_only, start, polish_only, weights, fix)
        if polish_only or train_only is not None or weights is not None:
            return c
        return refine_delay(self, list(names), c, dict(start or {}), dict(fix or {}),
                            lambda lo, hi: (hi - lo) / DELAY_GRID)

    def _fit(self, names: Sequence[str], train_only: Sequence[TestData] | None, start: dict[str, float] | None,
             polish_only: bool, weights: Sequence[float] | None, fix: dict[str, float] | None) -> Candidate:
        """One fit of :meth:`fit` (its multi-start search, or its polish)."""
        keys, lo, hi, x0 = self._keys(names)
        fix = dict(fix or {})
        unknown = sorted(set(fix) - set(keys))
        if unknown:
            raise ValueError(f"fix: {unknown} are not fitted parameters of {'+'.join(names) or 'the baseline'} "
                             f"(valid: {keys})")
        keep = [i for i, k in enumerate(keys) if k not in fix]
        keys, lo, hi, x0 = ([v[i] for i in keep] for v in (keys, lo, hi, x0))
        lo_a, hi_a = np.array(lo), np.array(hi)
        tests = list(train_only) if train_only is not None else self.train
        mult = None if weights is None else np.asarray(weights, float)
        if mult is not None and mult.shape != (len(tests),):
            raise ValueError(f"weights: {mult.size} given for {len(tests)} tests")
        saved = self.train
        self.train, self._mult = tests, mult
        try:
            fixed_p = {f"{n}.{k}": v for n in names if n in self.effects for k, v in self.effects[n].fixed.items()}
            fixed_p |= fix
            if not keys:
                return Candidate("+".join(names), fix, 0)

            def unpack(u: np.ndarray) -> dict[str, float]:
                return fixed_p | dict(zip(keys, lo_a + np.clip(u, 0, 1) * (hi_a - lo_a)))

            def fun(u: np.ndarray) -> np.ndarray:
                return self._train_resid(names, unpack(u))

            ug = (np.array(x0) - lo_a) / (hi_a - lo_a)
            fixed = np.zeros(len(keys), bool)
            if start:
                for i, k in enumerate(keys):
                    if k in start and math.isfinite(start[k]):
                        ug[i] = (start[k] - lo_a[i]) / (hi_a[i] - lo_a[i])
                        fixed[i] = True
            u0s = [np.clip(ug, 0, 1)] if polish_only else starts(keys, names, ug, fixed, lo_a, hi_a)
            costs = [float(np.sum(fun(u) ** 2)) for u in u0s]
            order = np.argsort(costs)[: (1 if polish_only or start else 2)]
            # a polish (a resample's or a jack-knife's refit) starts at an optimum of nearby data, often with
            # parameters on a bound (friction's x_s, μ at 0): dogbox's active set converges there in 3 or 4
            # evaluations, where the interior trust region ran out of its evaluations up to 2 N (2 sd) short of
            # the resample's own F_c; it stops at 1e-5 of the parameter range or of the cost
            polish = {"ftol": POLISH_TOL, "xtol": POLISH_TOL, "method": "dogbox"} if polish_only else {}
            best = None
            for i in order:
                r = least_squares(fun, u0s[i], bounds=(0.0, 1.0), x_scale=1.0, diff_step=1e-3,
                                  max_nfev=POLISH_NFEV if polish_only else 20 + 20 * len(keys), **polish)
                if best is None or r.cost < best.cost:
                    best = r
            p = unpack(best.x)
            ub = np.clip(best.x, 0, 1)
            # a parameter pinned at a physical bound (other than a zero lower bound, "effect absent")
            # (the re-fitted linear spring of a --model linear baseline is not an effect: its x_ref is free)
            at_bound = [k for k, v, a in zip(keys, ub, lo_a)
                        if not k.startswith("spring.") and pinned(k, float(v), float(a))]
            return Candidate("+".join(names), p, len(keys), at_bound=at_bound)
        finally:
            self.train = saved
            self._mult = None

    def score(self, cand: Candidate, names: Sequence[str], base_hold: float,
              laws: Sequence[str] | None = None) -> Candidate:
        """Score a fitted candidate: the damping law re-identified (LOTO-best of ``laws``, default
        :meth:`laws_for`)."""
        best = None
        for law in laws if laws is not None else self.laws_for(names):
            ev = self.evaluate(names, cand.params, law)
            if best is None or ev["nrmse_loto"] < best[1]["nrmse_loto"]:
                best = (law, ev)
        law, ev = best
        cand.law = law
        cand.law_params = ev["law_params"]
        cand.nrmse_train = ev["nrmse_train"]
        cand.nrmse_loto = ev["nrmse_loto"]
        cand.nrmse_holdout = ev["nrmse_holdout"]
        cand.shrinkage = 1.0 - ev["nrmse_holdout"] / base_hold if base_hold > 0 else float("nan")
        cand.chi2_train = ev["chi2"]
        cand.loto_num = ev["loto_num"]
        cand.db_holdout = self.noise_db(ev, "hold")[2]
        cand.db_train = self.noise_db(ev, "train")[2]
        nb = self.n_cells("train")
        k = cand.n_params + len(cand.law_params)
        cand.bic = ev["chi2"] + k * math.log(nb)
        cand.per_test = ev["per_test"]
        if "damping_law" in names:
            cand.params = dict(cand.params) | {f"law.{i}": v for i, v in enumerate(ev["law_params"])}
        cand._ev = ev  # type: ignore[attr-defined]
        return cand
