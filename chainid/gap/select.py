"""Selection: fit each library effect on training tests only, score it, give a verdict.

Method (all on whole tests, never on random samples):

1. Each test's steady window (:func:`chainid.records.analyse_record`) is folded
   into ``B`` phase bins of ψ = ωt + θ.  The cycle-averaged force per bin is the
   "measured" force used for all errors (noise averaged over the cycles); the
   noise σ [N] is the cycle-to-cycle scatter within the bins (local regression
   on phase and time removed), so the noise floor of a bin mean is σ/√n_bin.
2. Baseline: F = m·ẍ + F_k(x) + c_e·ẋ, c_e per training test from the bin
   means, damping law (paper Eq. 21 polynomial) fitted on training tests only,
   held-out c_e predicted by the law.
3. Candidate effect: its physical parameters are fitted by
   ``scipy.optimize.least_squares`` (bounded) on the training tests with the
   per-test c_e re-identified at every step; score = leave-one-test-out NRMSE
   over the training tests (damping law re-fitted without the test; effect
   parameters kept) and BIC; held-out NRMSE and shrinkage are reported.
4. Verdict: ``none`` if the baseline's held-out systematic residual is
   consistent with the noise; else the best candidate if it shrinks the
   held-out gap by >= 50 %, else ``unexplained``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable, Sequence

import numpy as np
from scipy.optimize import least_squares

from .effects import EFFECT_NAMES, make_effect

MIN_TRAIN = 6  # polynomial damping law: 5 coefficients, M > 5 (paper Eq. 22)


@dataclass
class TestData:
    """Steady window of one test prepared for the diagnosis (units mm, N, s)."""

    __test__ = False
    test: str
    omega: float
    A: float
    x0: float
    theta: float
    t: np.ndarray
    F: np.ndarray
    x: np.ndarray
    xd: np.ndarray
    xdd: np.ndarray
    xfun: Callable[[np.ndarray], tuple[np.ndarray, np.ndarray, np.ndarray]]
    bins: np.ndarray
    counts: np.ndarray
    Fbar: np.ndarray
    sigma: float
    drift: float  # RMS of the linear-in-time drift of F over the window [N]
    drift_se: float

    def binmean(self, y: np.ndarray) -> np.ndarray:
        return np.bincount(self.bins, weights=y, minlength=self.counts.size) / np.maximum(self.counts, 1)


def _fourier_x(t: np.ndarray, x: np.ndarray, omega: float, theta: float, H: int) -> Callable:
    psi = omega * t + theta
    cols = [np.ones_like(t)]
    for k in range(1, H + 1):
        cols += [np.cos(k * psi), np.sin(k * psi)]
    coef, *_ = np.linalg.lstsq(np.column_stack(cols), x, rcond=None)

    def f(ts: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        ps = omega * np.asarray(ts, float) + theta
        xv = np.full_like(ps, coef[0])
        xd = np.zeros_like(ps)
        xdd = np.zeros_like(ps)
        for k in range(1, H + 1):
            a, b = coef[2 * k - 1], coef[2 * k]
            c, s = np.cos(k * ps), np.sin(k * ps)
            xv += a * c + b * s
            w = k * omega
            xd += w * (-a * s + b * c)
            xdd += -w * w * (a * c + b * s)
        return xv, xd, xdd

    return f


def prepare_test(rec: Any, n_bins: int = 64, allow_compression: bool = True) -> TestData:
    """Fold one record's steady window into phase bins; estimate the noise σ [N].

    Raises
    ------
    ValueError
        No steady cycles in the record.
    """
    from ..records import analyse_record

    est = analyse_record(rec, allow_compression=allow_compression)
    win = est.window
    if win is None or win.n_cycles < 1:
        raise ValueError(f"test {rec.test!r}: no steady cycles found")
    m = (rec.t >= win.t_start) & (rec.t < win.t_end)
    t, x, F = rec.t[m], rec.x[m], rec.F[m]
    spc = t.size / max(win.n_cycles, 1)
    B = int(max(8, min(n_bins, 4 * (int(spc) // 8))))
    xfun = _fourier_x(t, x, est.omega, est.theta, H=5)
    xs, xd, xdd = xfun(t)
    psi = np.mod(est.omega * t + est.theta, 2 * math.pi)
    bins = np.minimum((psi / (2 * math.pi) * B).astype(np.int64), B - 1)
    counts = np.bincount(bins, minlength=B).astype(float)
    # noise: per bin, regress F on (1, ψ − ψc, t − t̄); pooled residual variance
    rss, dof = 0.0, 0
    slopes_t = []
    for b in range(B):
        idx = np.nonzero(bins == b)[0]
        if idx.size < 5:
            continue
        u = psi[idx] - psi[idx].mean()
        v = t[idx] - t[idx].mean()
        X = np.column_stack([np.ones(idx.size), u, v])
        coef, res, rank, _ = np.linalg.lstsq(X, F[idx], rcond=None)
        r = F[idx] - X @ coef
        rss += float(r @ r)
        dof += idx.size - rank
        slopes_t.append(coef[2])
    sigma = math.sqrt(rss / dof) if dof > 0 else 0.0
    sig_floor = 1e-6 * float(np.std(F)) + 1e-9
    sigma = max(sigma, sig_floor)
    # drift: common time slope of F about the periodic mean
    Fbar = np.bincount(bins, weights=F, minlength=B) / np.maximum(counts, 1)
    r = F - Fbar[bins]
    tc = t - t.mean()
    sl = float(tc @ r / (tc @ tc))
    se = sigma / math.sqrt(float(tc @ tc))
    span = float(t[-1] - t[0])
    drift = abs(sl) * span / math.sqrt(12)
    drift_se = se * span / math.sqrt(12)
    return TestData(rec.test, est.omega, est.A, est.x0, est.theta, t, F, xs, xd, xdd, xfun, bins, counts, Fbar,
                    sigma, drift, drift_se)._fix(x)


def _fix(self: TestData, x_meas: np.ndarray) -> TestData:
    self.x_meas = x_meas  # type: ignore[attr-defined]
    return self


TestData._fix = _fix  # type: ignore[attr-defined]


# ---------------------------------------------------------------- damping laws
def _law_design(kind: str, w: np.ndarray, A: np.ndarray, ke: np.ndarray) -> np.ndarray:
    one = np.ones_like(w)
    if kind == "polynomial":
        return np.column_stack([w**2, w, A**2, A, one])
    if kind == "viscous":
        return one[:, None]
    if kind == "viscous+hysteretic":
        return np.column_stack([one, ke / w])
    if kind == "viscous+coulomb":
        return np.column_stack([one, 4.0 / (math.pi * w * A)])
    if kind == "viscous+coulomb+hysteretic":
        return np.column_stack([one, 4.0 / (math.pi * w * A), ke / w])
    raise ValueError(f"damping law {kind!r} unknown")


ALT_LAWS = ("viscous+hysteretic", "viscous+coulomb", "viscous+coulomb+hysteretic")


def _law_fit_loo(X: np.ndarray, c: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Least squares params and leave-one-out predictions of c."""
    p, *_ = np.linalg.lstsq(X, c, rcond=None)
    H = X @ np.linalg.pinv(X)
    h = np.clip(np.diag(H), 0, 1 - 1e-9)
    resid = c - X @ p
    return p, c - resid / (1 - h)


# --------------------------------------------------------------- candidate eval
@dataclass
class Candidate:
    """A fitted effect (or combination) with its scores."""

    name: str
    params: dict[str, float]
    n_params: int
    law: str = "polynomial"
    law_params: list[float] = field(default_factory=list)
    nrmse_train: float = float("nan")
    nrmse_loto: float = float("nan")
    nrmse_holdout: float = float("nan")
    shrinkage: float = float("nan")
    bic: float = float("nan")
    chi2_train: float = float("nan")
    param_sd: dict[str, float] = field(default_factory=dict)
    per_test: dict[str, float] = field(default_factory=dict)
    at_bound: list[str] = field(default_factory=list)

    def to_dict(self) -> dict[str, Any]:
        f = lambda v: None if isinstance(v, float) and not math.isfinite(v) else v  # noqa: E731
        return {
            "effect": self.name,
            "params": {k: f(float(v)) for k, v in self.params.items()},
            "params_sd": {k: f(float(v)) for k, v in self.param_sd.items()},
            "damping_law": self.law,
            "nrmse_train": f(self.nrmse_train),
            "nrmse_loto": f(self.nrmse_loto),
            "nrmse_holdout": f(self.nrmse_holdout),
            "shrinkage": f(self.shrinkage),
            "bic": f(self.bic),
            "n_params": self.n_params,
            "at_bound": list(self.at_bound),
        }


class Problem:
    """Prepared data + baseline model; evaluates any effect combination."""

    def __init__(self, data: Sequence[TestData], model: Any, holdout: Sequence[str]):
        self.data = list(data)
        self.model = model
        ids = [d.test for d in self.data]
        unknown = [h for h in holdout if h not in ids]
        if unknown:
            raise ValueError(f"--holdout: test id(s) {unknown} not in the data; valid ids: {', '.join(ids)}")
        self.hold = [d for d in self.data if d.test in set(holdout)]
        self.train = [d for d in self.data if d.test not in set(holdout)]
        if not self.hold:
            raise ValueError("--holdout: no test held out; give at least one test id")
        if len(self.train) < MIN_TRAIN:
            raise ValueError(
                f"--holdout leaves {len(self.train)} training test(s); at least {MIN_TRAIN} are needed "
                "(the polynomial damping law of Eq. 21 has 5 coefficients, M > 5)"
            )
        allF = np.concatenate([d.Fbar for d in self.data])
        self.F_scale = float(np.std(allF)) or 1.0
        self.x_scale = float(max(d.A for d in self.data))
        self.omega_max = float(max(d.omega for d in self.data))
        self.is_chain = hasattr(model, "hertz_scale")
        self.ke = {d.test: float(np.asarray(model.stiffness(np.array([d.x0])), float)[0]) for d in self.data}
        self.sigma_raw = float(np.sqrt(np.mean([d.sigma**2 for d in self.data])))
        self.effects = {n: make_effect(n, self.F_scale, self.x_scale, self.omega_max) for n in EFFECT_NAMES}

    def model_for(self, p: dict[str, float]) -> Any:
        """The stiffness model, with a re-fitted linear spring when ``spring.k`` is in p."""
        if "spring.k" in p:
            from ..models import LinearModel

            return LinearModel(max(p["spring.k"], 0.0), p["spring.x_ref"], mass=float(getattr(self.model, "mass_kg", 0.0)))
        return self.model

    def applicable(self) -> list[str]:
        return [n for n, e in self.effects.items() if self.is_chain or not e.chain_only]

    # -- core evaluation
    def _parts(self, names: Sequence[str], p: dict[str, float], d: TestData) -> tuple[np.ndarray, np.ndarray]:
        """Bin means of the undamped force and of the velocity the damping acts on."""
        model = self.model_for(p)
        m = float(getattr(model, "mass_kg", 0.0))
        base = m * d.xdd * 1e-3 + np.asarray(model.force(d.x), float)
        Fn = base.copy()
        v = d.xd
        for n in names:
            if n == "damping_law":
                continue
            e = self.effects[n]
            pp = {k.split(".", 1)[1]: val for k, val in p.items() if k.startswith(n + ".")}
            Fe, ve, _ = e.force(pp, model, d.t, d.x, d.xd, d.xdd, d.omega, d.A, d.x0, d.xfun)
            Fn += Fe - base
            if n == "sensor_delay":
                v = ve
        return d.binmean(Fn), d.binmean(v)

    def evaluate(self, names: Sequence[str], p: dict[str, float], law: str = "polynomial") -> dict[str, Any]:
        parts = {d.test: self._parts(names, p, d) for d in self.data}
        c_e = {}
        for d in self.data:
            Fn, v = parts[d.test]
            w = d.counts
            c_e[d.test] = float(np.sum(w * (d.Fbar - Fn) * v) / max(np.sum(w * v * v), 1e-300))
        tr = self.train
        wv = np.array([d.omega for d in tr])
        Av = np.array([d.A for d in tr])
        kv = np.array([self.ke[d.test] for d in tr])
        X = _law_design(law, wv, Av, kv)
        cv = np.array([c_e[d.test] for d in tr])
        lp, cloo = _law_fit_loo(X, cv)

        def res(d: TestData, c: float) -> np.ndarray:
            Fn, v = parts[d.test]
            return d.Fbar - Fn - c * v

        def nrmse(ds: Sequence[TestData], cs: Sequence[float]) -> float:
            num = sum(float(np.sum(d.counts * res(d, c) ** 2)) for d, c in zip(ds, cs))
            den = sum(float(np.sum(d.counts * (d.Fbar - np.sum(d.counts * d.Fbar) / np.sum(d.counts)) ** 2)) for d in ds)
            return math.sqrt(num / den) if den > 0 else float("nan")

        hw = np.array([d.omega for d in self.hold])
        hA = np.array([d.A for d in self.hold])
        hk = np.array([self.ke[d.test] for d in self.hold])
        c_hold = _law_design(law, hw, hA, hk) @ lp
        chi2 = sum(float(np.sum(d.counts * res(d, c_e[d.test]) ** 2)) / d.sigma**2 for d in tr)
        per_test = {d.test: nrmse([d], [c]) for d, c in zip(self.hold, c_hold)}
        per_test.update({d.test: nrmse([d], [c_e[d.test]]) for d in tr})
        return {
            "nrmse_train": nrmse(tr, [c_e[d.test] for d in tr]),
            "nrmse_loto": nrmse(tr, cloo),
            "nrmse_holdout": nrmse(self.hold, c_hold),
            "chi2": chi2,
            "law_params": [float(v) for v in lp],
            "c_e": c_e,
            "c_hold": dict(zip([d.test for d in self.hold], c_hold)),
            "parts": parts,
            "per_test": per_test,
            "res": {d.test: res(d, c) for d, c in zip(self.hold, c_hold)} | {d.test: res(d, c_e[d.test]) for d in tr},
        }

    def _train_resid(self, names: Sequence[str], p: dict[str, float]) -> np.ndarray:
        out = []
        for d in self.train:
            Fn, v = self._parts(names, p, d)
            w = d.counts
            c = float(np.sum(w * (d.Fbar - Fn) * v) / max(np.sum(w * v * v), 1e-300))
            out.append(np.sqrt(w) * (d.Fbar - Fn - c * v) / d.sigma)
        return np.concatenate(out)

    def fit(self, names: Sequence[str], train_only: Sequence[TestData] | None = None) -> Candidate:
        """Fit the parameters of an effect or a combination on the training tests."""
        keys, lo, hi, x0 = [], [], [], []
        if not self.is_chain and hasattr(self.model, "k"):
            k0 = float(self.model.k)
            xr = float(self.model.x_ref)
            xs = self.x_scale
            keys += ["spring.k", "spring.x_ref"]
            lo += [0.0, xr - 2 * xs]
            hi += [max(10 * k0, 10 * self.F_scale / xs), xr + 2 * xs]
            x0 += [k0, xr]
        for n in names:
            e = self.effects[n]
            if n == "damping_law":
                continue
            for k, (a, b), g in zip(e.param_names, e.bounds, e.x0_guess):
                keys.append(f"{n}.{k}")
                lo.append(a)
                hi.append(b)
                x0.append(g)
        lo_a, hi_a = np.array(lo), np.array(hi)
        saved = self.train
        if train_only is not None:
            self.train = list(train_only)
        try:
            def unpack(u: np.ndarray) -> dict[str, float]:
                return dict(zip(keys, lo_a + np.clip(u, 0, 1) * (hi_a - lo_a)))

            def fun(u: np.ndarray) -> np.ndarray:
                return self._train_resid(names, unpack(u))

            if keys:
                # coarse start: a small grid over the unit box (log-spaced toward low values)
                grid1 = np.array([0.0, 0.003, 0.01, 0.03, 0.1, 0.3, 0.6])
                ug = (np.array(x0) - lo_a) / (hi_a - lo_a)
                ns = 2 if keys[0] == "spring.k" else 0
                ne = len(keys) - ns

                def put(vals: Sequence[float]) -> np.ndarray:
                    u = ug.copy()
                    u[ns : ns + len(vals)] = vals
                    return u

                u0s = [ug]
                if ne == 1:
                    u0s += [put([g]) for g in grid1] + [put([0.5 - g]) for g in (0.01, 0.05, 0.2)]
                    if lo_a[ns] < 0 < hi_a[ns]:
                        z = -lo_a[ns] / (hi_a[ns] - lo_a[ns])
                        u0s += [put([z + s * g]) for g in (0.002, 0.01, 0.05, 0.15) for s in (-1, 1)]
                elif ne >= 2:
                    g2 = np.array([0.0, 0.003, 0.03, 0.2])
                    for a in g2:
                        for b in g2:
                            u0s.append(put([a, b]))
                    if list(names) == ["friction"]:
                        u0s += [put([a, 0.0, c]) for a in (0.03, 0.2) for c in (0.02, 0.1, 0.4)]
                    if list(names) == ["contact_law"]:
                        u0s += [put([a, b]) for a in (0.05, 0.18, 0.4) for b in (0.2, 0.39, 0.6)]
                if ns:  # the spring may soften a lot once an effect carries the force
                    u0s += [np.concatenate([[ug[0] * f, ug[1]], u[2:]]) for f in (0.1, 0.01) for u in list(u0s)]
                u0s = [np.clip(u, 0, 1) for u in u0s]
                costs = [float(np.sum(fun(u) ** 2)) for u in u0s]
                order = np.argsort(costs)[:2]
                best = None
                for i in order:
                    r = least_squares(fun, u0s[i], bounds=(0.0, 1.0), x_scale=1.0, diff_step=1e-3, max_nfev=60)
                    if best is None or r.cost < best.cost:
                        best = r
                p = unpack(best.x)
                # a parameter pinned at a physical bound (other than a zero lower bound, "effect absent")
                ub = np.clip(best.x, 0, 1)
                at_bound = [k for k, v, a in zip(keys, ub, lo_a) if v >= 1 - 1e-6 or (v <= 1e-6 and a != 0.0)]
            else:
                p, at_bound = {}, []
            return Candidate("+".join(names), p, len(keys), at_bound=at_bound)
        finally:
            self.train = saved

    def score(self, cand: Candidate, names: Sequence[str], base_hold: float) -> Candidate:
        laws = ["polynomial", "viscous"] if names else ["polynomial"]
        if "damping_law" in names:
            laws = list(ALT_LAWS)
        best = None
        for law in laws:
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
        nb = sum(d.counts.size for d in self.train)
        k = cand.n_params + len(cand.law_params) - 5
        cand.bic = ev["chi2"] + k * math.log(nb)
        cand.per_test = ev["per_test"]
        if law != "polynomial":
            cand.params = dict(cand.params) | {f"law.{i}": v for i, v in enumerate(ev["law_params"])}
        return cand


def damping_separable(data: Sequence[TestData]) -> tuple[bool, str]:
    """Whether the plan can separate damping forms: needs ≥ 3 distinct ω and ≥ 3 distinct A
    (polynomial Eq. 21 has ω², ω, A², A terms) and a design matrix of full rank."""
    w = np.array([d.omega for d in data])
    A = np.array([d.A for d in data])
    nw = np.unique(np.round(w / w.max(), 3)).size
    nA = np.unique(np.round(A / A.max(), 3)).size
    X = _law_design("polynomial", w, A, np.ones_like(w))
    Xn = X / np.linalg.norm(X, axis=0)
    cond = float(np.linalg.cond(Xn))
    if nw < 3 or nA < 3 or cond > 1e8:
        return False, (
            f"the training plan has {nw} distinct frequencies and {nA} distinct amplitudes (cond {cond:.3g}); "
            "damping forms (viscous ∝ 1, Coulomb ∝ 1/(ωA), hysteretic ∝ 1/ω, polynomial Eq. 21) cannot be "
            "separated: add tests at >= 3 frequencies and >= 3 amplitudes"
        )
    return True, ""
