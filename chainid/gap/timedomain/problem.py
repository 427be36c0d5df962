"""The diagnosis problem for any excitation: time-domain records, alone or mixed with harmonic tests.

:class:`AnyProblem` has the interface the forward selection (:mod:`chainid.gap.core.selection`)
uses — ``fit``, ``score``, ``noise_db``, ``n_cells`` — so the same selection and step
rule run on it.  Its parts:

* **time-domain records** (:mod:`chainid.gap.timedomain.data`): the model force on the raw
  samples, F = m·ẍ + F_k(x) + effects + c·ẋ with causal memory operators and one
  viscous c (profiled by least squares at every parameter value);
* **harmonic tests** (when the set has at least ``MIN_TRAIN`` training harmonic tests):
  today's phase-bin route (:class:`chainid.gap.harmonic.problem.Problem`) with its c_e(ω, A)
  law; the effect and spring parameters are shared with the time part (one device).

Scoring units are whole harmonic tests and contiguous time blocks.  A time block's
leave-one-block-out error is the exact leave-out residual of the model linearised at
the fit, e_(b) = e_b + J_b Δ_b with Δ_b = (JᵀJ − J_bᵀJ_b)⁻¹ J_bᵀ e_b, over *all* fitted
parameters (effects, spring, c), J the Jacobian of the weighted residual on the training
samples; parameters pinned at a bound are held fixed, and the step Δ_b is clipped so the
left-out fit stays inside the physical bounds (as a bounded refit would).  The block jack-knife of the same
linearisation gives the parameters' standard deviations while the selection runs; the reported ones of the chosen
steps also take the jack-knife of leave-one-unit-out refits (:meth:`AnyProblem.refit_sd`), whichever is larger.

NRMSE = RMS(residual)/RMS(F − mean F of the record) over the unit's samples (bin means
for a harmonic test).  Units: mm, N, s.
"""

from __future__ import annotations

import math
from typing import Any, Sequence

import numpy as np

from chainid.model.effects import EFFECT_NAMES, make_effect
from chainid.gap.core.candidate import Candidate, jackknife_sd
from chainid.gap.harmonic.problem import Problem
from chainid.gap.timedomain.data import TimeData, split_blocks, undamped

#: finite-difference step of the Jacobian in the unit box of a parameter's physical range
FD_STEP = 1e-4
#: a leave-out step that moves a parameter by more than this fraction of its physical range is checked on the
#: nonlinear model (the Gauss–Newton linearisation is a local one)
LINEAR_STEP = 0.01


def leave_out_step(Ab: np.ndarray, g: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """The linearised leave-one-block-out refit step Δ (θ_(b) = θ − Δ in the unit box of each parameter's
    physical range; the last entry is the viscous c [N·s/mm]).

    The refit without block b minimises ½·ΔᵀA_bΔ − gᵀΔ, A_b = JᵀJ − J_bᵀJ_b and g = J_bᵀe_b (Gauss–Newton at the
    full fit θ), subject to the parameters staying in their physical ranges: lo <= Δ <= hi.  When the unconstrained
    solution A_bΔ = g leaves the box, the box-constrained quadratic is solved (bounded least squares,
    ``scipy.optimize.lsq_linear``) rather than the solution clipped: parameters that trade off against each other
    (a force-channel lag τ against the viscous c, which it mimics as −k·τ·ẋ) must move together, and clipping one of
    them alone predicts a refit no optimiser would return.
    """
    d = np.linalg.lstsq(Ab, g, rcond=1e-12)[0]
    if np.all(d >= lo) and np.all(d <= hi):
        return d
    from scipy.optimize import lsq_linear

    w, V = np.linalg.eigh(0.5 * (Ab + Ab.T))
    keep = w > max(float(w.max()), 0.0) * 1e-12
    if not np.any(keep):
        return np.zeros_like(d)
    sw = np.sqrt(w[keep])
    M = sw[:, None] * V[:, keep].T           # MᵀM = A_b on its range
    y = (V[:, keep].T @ g) / sw              # Mᵀy = g on its range
    x0 = np.clip(d, lo, hi)
    r = lsq_linear(M, y, bounds=(lo, hi), method="bvls", tol=1e-12, max_iter=200)
    return r.x if r.success and np.all(np.isfinite(r.x)) else x0


class AnyProblem(Problem):
    """Time-domain records (+ optional harmonic tests) with a baseline model; fits and scores effect sets.

    Parameters
    ----------
    tdata : sequence of TimeData
    model : StiffnessModel
    holdout : sequence of str
        Held-out test ids (whole records / tests).
    holdout_blocks : int
        > 0: the last block of every record is held out as well.
    hprob : Problem, optional
        The harmonic part (its own train/hold split), sharing the effect parameters.
    """

    def __init__(self, tdata: Sequence[TimeData], model: Any, holdout: Sequence[str], holdout_blocks: int = 0,
                 hprob: Problem | None = None):
        self.tdata = list(tdata)
        self.hprob = hprob
        self.model = model
        self.train_units, self.hold_units = split_blocks(self.tdata, holdout, holdout_blocks)
        hh = list(hprob.hold) if hprob is not None else []
        if not self.hold_units and not hh:
            raise ValueError("nothing is held out: give --holdout IDS (whole tests) or --holdout-blocks K")
        n_train = len(self.train_units) + (len(hprob.train) if hprob is not None else 0)
        if n_train < 3:
            raise ValueError(f"the split leaves {n_train} training unit(s) (time blocks + harmonic tests); at least "
                             "3 are needed for leave-one-out scoring: hold out fewer tests or use more blocks")
        Fs = [d.F for d in self.tdata] + ([h.Fbar for h in hprob.data] if hprob is not None else [])
        self.F_scale = float(np.std(np.concatenate(Fs))) or 1.0
        self.x_scale = float(max([d.A for d in self.tdata] + ([h.A for h in hprob.data] if hprob else [])))
        self.omega_max = float(max([2 * math.pi * d.f_band for d in self.tdata]
                                   + ([h.omega for h in hprob.data] if hprob else [])))
        self.is_chain = hasattr(model, "hertz_scale")
        self.effects = {n: make_effect(n, self.F_scale, self.x_scale, self.omega_max) for n in EFFECT_NAMES}
        self.law = hprob.law if hprob is not None else "viscous"
        self.law_reason = (hprob.law_reason if hprob is not None else
                           "time domain: viscous c·ẋ (rate-independent dissipation is carried by the effects)")
        self.sigma_raw = float(np.sqrt(np.mean([d.sigma**2 for d in self.tdata])))
        self.data = list(self.tdata) + (list(hprob.data) if hprob is not None else [])
        self.hold = [d for d in self.data if any(u[0] is d for u in self.hold_units)] + hh
        self.train = [d for d in self.data if any(u[0] is d for u in self.train_units)] + (
            list(hprob.train) if hprob is not None else [])
        # training / held-out sample masks per record
        self._mask = {}
        for d in self.tdata:
            tr = np.zeros(d.t.size, bool)
            for dd, b in self.train_units:
                if dd is d:
                    tr |= d.block == b
            self._mask[d.test] = tr
        self.F_mean = {d.test: float(np.mean(d.F)) for d in self.tdata}

    # -------------------------------------------------------------- interface
    def applicable(self) -> list[str]:
        """Library effects for this set: chain-only effects need the chain model; ``damping_law`` (a
        c_e(ω, A) form) only with harmonic tests."""
        out = super().applicable()
        if self.hprob is None:
            out = [n for n in out if n != "damping_law"]
        return out

    def train_mask(self, test: str) -> np.ndarray:
        """Boolean mask of a time record's training samples (the rest is held out)."""
        return self._mask[test]

    def n_cells(self, split: str = "train") -> int:
        """Independent noise cells of a split: time samples + harmonic phase bins."""
        n = sum(int(np.sum(self._mask[d.test] if split == "train" else ~self._mask[d.test])) for d in self.tdata)
        if self.hprob is not None:
            n += sum(h.counts.size for h in (self.hprob.train if split == "train" else self.hprob.hold))
        return n

    def _c(self, parts: dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]]) -> float:
        """Viscous c [N·s/mm] >= 0: weighted least squares of F − F_n on v over the training samples given."""
        num = den = 0.0
        for d in self.tdata:
            Fn, v, F = parts[d.test]
            w = 1.0 / d.sigma**2
            num += w * float(np.sum((F - Fn) * v))
            den += w * float(np.sum(v * v))
        # a dashpot dissipates: c >= 0 (a negative c would stand in for a lag of the force channel)
        return max(num / den, 0.0) if den > 0 else 0.0

    def _train_resid(self, names: Sequence[str], p: dict[str, float]) -> np.ndarray:
        """Whitened training residuals: time records on their fit subset (weighted √q for the subsampling), then
        the harmonic part's bin residuals."""
        model = self.model_for(p)
        parts = {}
        for d in self.tdata:
            idx = d.fit_idx[self._mask[d.test][d.fit_idx]]
            Fn, v = undamped(names, p, model, d, idx)
            parts[d.test] = (Fn, v, d.F[idx])
        c = self._c(parts)
        out = []
        for d in self.tdata:
            Fn, v, F = parts[d.test]
            q = d.t.size / max(d.fit_idx.size, 1)
            out.append(math.sqrt(q) * (F - Fn - c * v) / d.sigma)
        if self.hprob is not None:
            out.append(self.hprob._train_resid(names, p))
        return np.concatenate(out) if out else np.zeros(0)

    # ------------------------------------------------------------ evaluation
    def forces(self, names: Sequence[str], p: dict[str, float], c: float | None = None
               ) -> tuple[dict[str, np.ndarray], float]:
        """Model force [N] on every sample of every time record, and the viscous c [N·s/mm] (fitted on the
        training samples unless given)."""
        model = self.model_for(p)
        full = {d.test: undamped(names, p, model, d) for d in self.tdata}
        if c is None:
            c = self._c({d.test: (full[d.test][0][self._mask[d.test]], full[d.test][1][self._mask[d.test]],
                                  d.F[self._mask[d.test]]) for d in self.tdata})
        return {k: Fn + c * v for k, (Fn, v) in full.items()}, c

    def _jacobian(self, names: Sequence[str], p: dict[str, float], Fm: dict[str, np.ndarray], c: float,
                  at_bound: Sequence[str]) -> tuple[np.ndarray, list[str], np.ndarray]:
        """Jacobian [N per unit] of the weighted training model force w.r.t. the free parameters (unit box of
        their physical range) and c; rows = training samples of all time records in order.  Also the present
        position of each column's parameter (u in the unit box, or c) for the bounds of a leave-out step."""
        keys, lo, hi, _ = self._keys(names)
        cols, used, pos = [], [], []
        rows = lambda F: np.concatenate([F[d.test][self._mask[d.test]] / d.sigma for d in self.tdata])  # noqa: E731
        f0 = rows(Fm)
        for k, a, b in zip(keys, lo, hi):
            if k in at_bound or b <= a:
                continue
            u = (p[k] - a) / (b - a)
            h = FD_STEP if u + FD_STEP <= 1 else -FD_STEP
            pp = dict(p)
            pp[k] = a + (u + h) * (b - a)
            F1, _ = self.forces(names, pp, c)
            cols.append((rows(F1) - f0) / h)
            used.append(k)
            pos.append(u)
        v = {d.test: undamped(names, p, self.model_for(p), d)[1] for d in self.tdata}
        cols.append(rows(v))
        used.append("c")
        pos.append(c)
        return np.column_stack(cols), used, np.array(pos)

    def evaluate_time(self, names: Sequence[str], p: dict[str, float], at_bound: Sequence[str] = (),
                      loo: bool = True) -> dict[str, Any]:
        """Time-part errors: per unit SSE (fitted, leave-one-block-out, held out) [N²], variances, residuals."""
        Fm, c = self.forces(names, p)
        res = {d.test: d.F - Fm[d.test] for d in self.tdata}
        var = {(d.test, b): float(np.sum((d.F[d.block == b] - self.F_mean[d.test]) ** 2))
               for d in self.tdata for b in range(d.n_blocks)}
        sse = {(d.test, b): float(np.sum(res[d.test][d.block == b] ** 2)) for d in self.tdata for b in range(d.n_blocks)}
        loo_res = {d.test: res[d.test].copy() for d in self.tdata}
        sd: dict[str, float] = {}
        if loo and self.train_units:
            J, used, pos = self._jacobian(names, p, Fm, c, at_bound)
            # a leave-out refit stays inside the physical bounds: θ_(b) = θ − Δ with u in [0, 1] and c >= 0
            dlo = np.where(np.arange(pos.size) < pos.size - 1, pos - 1.0, -np.inf)
            dhi = pos.copy()
            e = np.concatenate([res[d.test][self._mask[d.test]] / d.sigma for d in self.tdata])
            lab = np.concatenate([d.block[self._mask[d.test]] + 10_000 * i for i, d in enumerate(self.tdata)])
            A = J.T @ J
            deltas = []
            off = 0
            for i, d in enumerate(self.tdata):
                m = self._mask[d.test]
                n_i = int(m.sum())
                for b in np.unique(d.block[m]):
                    sel = off + np.flatnonzero(lab[off:off + n_i] == b + 10_000 * i)
                    Jb, eb = J[sel], e[sel]
                    g = Jb.T @ eb
                    dth = leave_out_step(A - Jb.T @ Jb, g, dlo, dhi)
                    eloo = (eb + Jb @ dth) * d.sigma
                    idx = np.flatnonzero(m)[sel - off]
                    if np.max(np.abs(dth[:-1]), initial=0.0) > LINEAR_STEP:
                        dth, eloo = self._leave_out_checked(names, p, used, c, dth, d, b, e, lab, i, eb * d.sigma)
                    loo_res[d.test][idx] = eloo
                    deltas.append(dth)
                off += n_i
            D = np.array(deltas)
            nb = D.shape[0]
            if nb >= 2:
                s = jackknife_sd(D)
                keys, lo, hi, _ = self._keys(names)
                rng = {k: b - a for k, a, b in zip(keys, lo, hi)}
                sd = {k: float(s[j] * rng.get(k, 1.0)) for j, k in enumerate(used)}
        sse_loo = {(d.test, b): float(np.sum(loo_res[d.test][d.block == b] ** 2))
                   for d in self.tdata for b in range(d.n_blocks)}
        return {"c": c, "res": res, "loo_res": loo_res, "var": var, "sse": sse, "sse_loo": sse_loo, "sd": sd,
                "force": Fm}

    def _leave_out_checked(self, names: Sequence[str], p: dict[str, float], used: list[str], c: float,
                           dth: np.ndarray, d: TimeData, b: int, e: np.ndarray, lab: np.ndarray, i: int,
                           fitted: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """A large leave-one-block-out step checked on the nonlinear model (a backtracking Gauss–Newton step).

        The refit without block b is taken at θ − α·Δ with the largest α in 1, ½, ¼, … (down to 1/64) that does not
        raise the leave-out training cost S_(b) above its value at the full fit θ — an optimiser started at θ would
        not accept a worse point; with none, α = 0 (the full fit: block b's ``fitted`` residual [N]).  Returns α·Δ
        and block b's left-out residual [N], both from the nonlinear model: an effect whose force is strongly
        nonlinear in a parameter near its bound (a presliding displacement x_s → 0) makes the linear prediction of a
        large step meaningless.
        """
        keys, lo, hi, _ = self._keys(names)
        rng = {k: (a, bb) for k, a, bb in zip(keys, lo, hi)}
        keep = lab != b + 10_000 * i          # training rows outside block b, in J's row order
        s0 = float(np.sum(e[keep] ** 2))

        def at(alpha: float) -> tuple[float, dict[str, np.ndarray]]:
            pp = dict(p)
            for j, k in enumerate(used[:-1]):
                a, bb = rng[k]
                pp[k] = a + (min(max((p[k] - a) / (bb - a) - alpha * dth[j], 0.0), 1.0)) * (bb - a)
            Fm, _ = self.forces(names, pp, max(c - alpha * dth[-1], 0.0))
            res = {dd.test: dd.F - Fm[dd.test] for dd in self.tdata}
            ek = np.concatenate([res[dd.test][self._mask[dd.test]] / dd.sigma for dd in self.tdata])
            return float(np.sum(ek[keep] ** 2)), res

        sel = self._mask[d.test] & (d.block == b)
        alpha = 1.0
        while alpha >= 1 / 64:
            s1, res = at(alpha)
            if s1 <= s0:
                return alpha * dth, res[d.test][sel]
            alpha *= 0.5
        return 0.0 * dth, fitted

    def evaluate(self, names: Sequence[str], p: dict[str, float], law: str | None = None,
                 at_bound: Sequence[str] = ()) -> dict[str, Any]:
        """Errors of an effect set (time part + harmonic part) in the form :meth:`Problem.evaluate` returns."""
        et = self.evaluate_time(names, p, at_bound)
        tr_keys = [(d.test, b) for d, b in self.train_units]
        ho_keys = [(d.test, b) for d, b in self.hold_units]
        num_tr = sum(et["sse"][k] for k in tr_keys)
        num_loo = sum(et["sse_loo"][k] for k in tr_keys)
        num_ho = sum(et["sse"][k] for k in ho_keys)
        den_tr = sum(et["var"][k] for k in tr_keys)
        den_ho = sum(et["var"][k] for k in ho_keys)
        loto_num = {f"{t}#{b}": et["sse_loo"][(t, b)] for t, b in tr_keys}
        chi2 = sum(float(np.sum((et["res"][d.test][self._mask[d.test]] / d.sigma) ** 2)) for d in self.tdata)
        per_test = {}
        for d in self.tdata:
            den = float(np.sum((d.F - self.F_mean[d.test]) ** 2))
            per_test[d.test] = math.sqrt(float(np.sum(et["res"][d.test] ** 2)) / den) if den > 0 else float("nan")
        ev: dict[str, Any] = {"time": et, "law_params": [], "c_e": {}, "c_hold": {}, "parts": {}}
        if self.hprob is not None:
            eh = self.hprob.evaluate(names, p, law)
            hp = self.hprob

            def hsse(d: Any) -> float:
                return float(np.sum(d.counts * eh["res"][d.test] ** 2))

            def hvar(d: Any) -> float:
                return float(np.sum(d.counts * (d.Fbar - np.sum(d.counts * d.Fbar) / np.sum(d.counts)) ** 2))

            sse_fit = {d.test: float(np.sum(d.counts * (d.Fbar - eh["parts"][d.test][0]
                                                       - eh["c_e"][d.test] * eh["parts"][d.test][1]) ** 2))
                       for d in hp.train}
            num_tr += sum(sse_fit.values())
            num_loo += sum(eh["loto_num"].values())
            den_tr += sum(hvar(d) for d in hp.train)
            num_ho += sum(hsse(d) for d in hp.hold)
            den_ho += sum(hvar(d) for d in hp.hold)
            loto_num.update(eh["loto_num"])
            chi2 += eh["chi2"]
            per_test.update(eh["per_test"])
            ev.update({"law_params": eh["law_params"], "c_e": eh["c_e"], "c_hold": eh["c_hold"], "parts": eh["parts"],
                       "harmonic": eh})
        f = lambda a, b: math.sqrt(a / b) if b > 0 else float("nan")  # noqa: E731
        ev.update({"nrmse_train": f(num_tr, den_tr), "nrmse_loto": f(num_loo, den_tr), "nrmse_holdout": f(num_ho, den_ho),
                   "loto_num": loto_num, "chi2": chi2, "per_test": per_test})
        return ev

    def refit_sd(self, names: Sequence[str], params: dict[str, float]) -> dict[str, float]:
        """Parameter standard deviations [their units] by leave-one-unit-out refits (jack-knife).

        Every training unit — a time block, or a whole harmonic test — is left out in turn and the effect set is
        re-fitted from ``params`` (a local least-squares polish, as the harmonic route's jack-knife does); the sd is
        the jack-knife spread √((n−1)/n·Σ(θ_(i) − θ̄)²) of those refits.  Unlike the linearised block jack-knife of
        :meth:`evaluate_time`, it sees a cost that is not smooth in a parameter: a lag of a friction force whose
        switching instants move on the sample grid (the lag's linearised sd came out ~100× below its spread over
        noise realisations).
        """
        keys = self._keys(names)[0]
        start = {k: params[k] for k in keys if k in params}
        units: list[tuple[str, Any]] = [("time", u) for u in self.train_units]
        if self.hprob is not None:
            units += [("harmonic", i) for i in range(len(self.hprob.train))]
        if len(units) < 2 or not keys:
            return {}
        vals = []
        for kind, u in units:
            if kind == "time":
                d, b = u
                saved = self._mask[d.test]
                self._mask[d.test] = saved & (d.block != b)
                try:
                    cand = self.fit(names, start=start, polish_only=True)
                finally:
                    self._mask[d.test] = saved
            else:
                hp = self.hprob
                saved_h = hp.train
                hp.train = saved_h[:u] + saved_h[u + 1:]
                try:
                    cand = self.fit(names, start=start, polish_only=True)
                finally:
                    hp.train = saved_h
            vals.append([cand.params.get(k, float("nan")) for k in keys])
        return {k: float(s) for k, s in zip(keys, jackknife_sd(np.array(vals)))}

    def noise_db(self, ev: dict[str, Any], split: str = "hold") -> tuple[float, float, float]:
        """Mean squared residual per noise cell, its noise floor [N²] and the ratio in dB (time samples: σ²;
        harmonic bins: σ²/n per bin). ``train`` uses the leave-one-out residuals."""
        et = ev["time"]
        r2 = f2 = 0.0
        n = 0
        for d in self.tdata:
            m = self._mask[d.test] if split == "train" else ~self._mask[d.test]
            r = (et["loo_res"] if split == "train" else et["res"])[d.test][m]
            r2 += float(np.sum(r**2))
            f2 += d.sigma**2 * r.size
            n += r.size
        if self.hprob is not None and "harmonic" in ev:
            hp = self.hprob
            for d in (hp.train if split == "train" else hp.hold):
                r = ev["harmonic"]["res"][d.test]
                r2 += float(np.sum(r**2))
                f2 += float(np.sum(d.sigma**2 / np.maximum(d.counts, 1)))
                n += r.size
        if n == 0:
            return float("nan"), float("nan"), float("nan")
        r2, f2 = r2 / n, f2 / n
        return r2, f2, 10 * math.log10(max(r2, 1e-300) / max(f2, 1e-300))

    def score(self, cand: Candidate, names: Sequence[str], base_hold: float) -> Candidate:
        """Score a fitted candidate (the harmonic part's damping law re-identified, LOTO-best)."""
        laws = self.laws_for(names) if self.hprob is not None else ["viscous"]
        best = None
        for law in laws:
            ev = self.evaluate(names, cand.params, law, cand.at_bound)
            if best is None or ev["nrmse_loto"] < best[1]["nrmse_loto"]:
                best = (law, ev)
        law, ev = best
        cand.law = law if self.hprob is not None else "viscous"
        cand.law_params = ev["law_params"] if self.hprob is not None else [ev["time"]["c"]]
        cand.nrmse_train, cand.nrmse_loto, cand.nrmse_holdout = ev["nrmse_train"], ev["nrmse_loto"], ev["nrmse_holdout"]
        cand.shrinkage = 1.0 - ev["nrmse_holdout"] / base_hold if base_hold > 0 else float("nan")
        cand.chi2_train = ev["chi2"]
        cand.loto_num = ev["loto_num"]
        cand.db_holdout = self.noise_db(ev, "hold")[2]
        cand.db_train = self.noise_db(ev, "train")[2]
        k = cand.n_params + len(cand.law_params)
        cand.bic = ev["chi2"] + k * math.log(max(self.n_cells("train"), 2))
        cand.per_test = ev["per_test"]
        cand.param_sd = {k: v for k, v in ev["time"]["sd"].items() if k != "c"}
        cand.params = dict(cand.params) | {"damping.c": ev["time"]["c"]}
        if "damping_law" in names and self.hprob is not None:
            cand.params |= {f"law.{i}": v for i, v in enumerate(ev["law_params"])}
        cand._ev = ev  # type: ignore[attr-defined]
        return cand
