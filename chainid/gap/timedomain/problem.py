"""The diagnosis problem on time-domain records: fit and score any effect set, sample by sample.

:class:`TimeProblem` has the interface the forward selection (:mod:`chainid.gap.core.selection`) uses — ``fit``,
``score``, ``noise_db``, ``n_cells``, ``applicable`` — so the same selection and step rule run on it as on the
harmonic route.

Method.  The model force of an effect set is a fixed part plus columns times amplitudes
(:mod:`.design`); for given shape parameters the amplitudes are a bounded linear least-squares fit
(:mod:`.lsq`), so the shape parameters are searched with the amplitudes profiled out (:mod:`.search`, on each
record's fit subset), then the amplitudes are fitted on every training sample.  Scoring units are contiguous time
blocks (whole records when held out): a training block's leave-one-block-out error is the exact refit of every
amplitude without that block (the shape parameters kept), from the blocks' Gram matrices.  Records are weighted by
1/σ², σ the record's force noise.

The noise floor is each record's force noise σ_F² (the kinematics' predicted errors carried through the fitted
base, (c·e_v)² + (m·e_a·1e-3)² + (k·e_x)², :mod:`chainid.gap.core.kinematics`, are reported beside it).

NRMSE = RMS(residual)/RMS(F − mean F of the record) over the unit's samples.  Units: mm, N, s, kg.
"""

from __future__ import annotations

import math
from typing import Any, Sequence

import numpy as np

from chainid.gap.core.candidate import Candidate, jackknife_sd
from chainid.gap.core.delayscan import refine_delay
from chainid.gap.timedomain.basechoice import MIN_LAW_RECORDS, distinct_covariates, law_choice
from chainid.gap.timedomain.data import TimeData, fit_subsets, split_blocks
from chainid.gap.timedomain.design import (Base, ColumnCache, amplitude_bounds, amplitude_names, build, law_features,
                                           shape_names, split_name)
from chainid.gap.timedomain.lsq import Blocks, solve_held, sse_at
from chainid.gap.timedomain.passivity import LAW_AMPS, law_box, passive_solve
from chainid.gap.timedomain.search import lag_points, search
from chainid.model.effects import EFFECT_NAMES, SPECS, sliding_sign
from chainid.model.timedamping import feature_c

__all__ = ["TimeProblem"]

#: records of at least this many samples together fit a selection round's effect sets on forked workers
#: (:func:`chainid.gap.core.selection.prefetch`); below it a round takes a few seconds, and the workers' start and
#: the column-cache entries they make and lose with them cost about what they save
PARALLEL_SAMPLES = 200_000
#: relative sd × √n of the force-noise estimate σ̂² (1.4826·MAD(Δ²F))²/6 on n samples of white noise (Monte Carlo:
#: 2.83, 2.92, 2.84 at n = 1 000, 8 000, 30 000, 400 draws each)
SIGMA2_REL_SD = 2.9


class TimeProblem:
    """Time-domain records with a base model; fits and scores effect sets (see the module docstring).

    Parameters
    ----------
    tdata : sequence of TimeData
    model : ChainModel or None
        The chain base (its kernels and mass), or None for a linear device fitted here (k, m, c, offsets).
    holdout : sequence of str
        Held-out test ids (whole records).
    holdout_blocks : int
        > 0: the last block of every record is held out as well.
    mass_kg : float, optional
        The given moving mass of a linear base [kg] (None: fitted, >= 0).
    damping_law : str
        ``viscous``: one dashpot c for every record; otherwise (default ``auto``) the dashpot follows the records'
        features where >= ``MIN_LAW_RECORDS`` training records separate them and no operating condition (a
        covariate) differs between them (:func:`law_choice`).
    """

    hprob = None  # no phase-bin part: every record is evaluated sample by sample
    fits_base = True  # the base's amplitudes (dashpot; spring and mass of a linear device) are fitted

    def __init__(self, tdata: Sequence[TimeData], model: Any, holdout: Sequence[str], holdout_blocks: int = 0,
                 mass_kg: float | None = None, damping_law: str = "auto"):
        self.tdata = list(tdata)
        self.model = model
        self.is_chain = model is not None and hasattr(model, "hertz_scale")
        self.train_units, self.hold_units = split_blocks(self.tdata, holdout, holdout_blocks)
        if not self.hold_units:
            raise ValueError("nothing is held out: give --holdout IDS (whole tests) or --holdout-blocks K")
        if len(self.train_units) < 3:
            raise ValueError(f"the split leaves {len(self.train_units)} training unit(s) (time blocks); at least 3 "
                             "are needed for leave-one-out scoring: hold out fewer tests or use more blocks")
        self._mask = {}
        for d in self.tdata:
            tr = np.zeros(d.t.size, bool)
            for dd, b in self.train_units:
                if dd is d:
                    tr |= d.block == b
            self._mask[d.test] = tr
        self.data = self.tdata
        # the shape search's samples per record (bounded; lead-in samples weighed 0)
        self._fit = fit_subsets(self.tdata, self._mask)
        self.hold = [d for d in self.tdata if any(u[0] is d for u in self.hold_units)]
        self.train = [d for d in self.tdata if any(u[0] is d for u in self.train_units)]
        train_recs = [d for d in self.tdata if self._mask[d.test].any()]
        covs = sorted(set.intersection(*[set(d.covariates) for d in self.tdata])) if self.tdata else []
        refs = {"x_mid": float(np.mean([d.x0 for d in train_recs])),
                "w_ref": float(np.mean([d.omega_c for d in train_recs])),
                "A_ref": float(np.mean([d.A_c for d in train_recs]))}
        refs |= {f"cov:{c}": float(np.mean([d.covariates[c] for d in train_recs])) for c in covs}
        self.covariates = distinct_covariates(train_recs, covs)
        feats = law_features([d.omega_c for d in self.train], [d.A_c for d in self.train])
        # an operating condition differing between the records keeps one c in the base (.basechoice: why)
        separable = self._law_separable(feats)
        self.base = Base("chain" if self.is_chain else "linear", model if self.is_chain else None, mass_kg, refs,
                         law=damping_law != "viscous" and separable and not self.covariates, law_features=feats)
        self.law_box = law_box(self.tdata, feats, refs)
        allF = np.concatenate([d.F - d.F.mean() for d in self.tdata])
        self.F_scale = float(np.std(allF)) or 1.0
        self.x_scale = float(max(d.A for d in self.tdata)) or 1.0
        self.scales = {"F": self.F_scale, "x": self.x_scale,
                       "omega": float(max(2 * math.pi * d.f_band for d in self.tdata)),
                       "v": float(max(np.quantile(np.abs(d.xd), 0.99) for d in self.tdata)) or 1.0,
                       "x_mid": refs["x_mid"], "tau": self._lag_range()}
        self.f_band = float(max(d.f_band for d in self.tdata))
        self.law, self.law_reason = law_choice(self.base.law, damping_law, len(self.train),
                                               self.covariates if separable else ())
        self.sigma_raw = float(np.sqrt(np.mean([d.sigma**2 for d in self.tdata])))
        self.F_mean = {d.test: float(np.mean(d.F)) for d in self.tdata}
        self._cache = ColumnCache()
        self.parallel_fits = sum(d.t.size for d in self.tdata) >= PARALLEL_SAMPLES

    # ------------------------------------------------------------------ set-up
    def _lag_range(self) -> float:
        """The largest lag searched [s]: half the longest useful period (1/low band edge) of the records, at most a
        quarter of the shortest record."""
        longest = max(1.0 / max(d.f_low, 1e-9) for d in self.tdata)
        dur = min(float(d.t[-1] - d.t[0]) for d in self.tdata)
        return float(min(0.5 * longest, 0.25 * dur))

    def _law_separable(self, feats: Sequence[str]) -> bool:
        """Whether the training records separate a damping law over their features: >= ``MIN_LAW_RECORDS`` of them
        with distinct (band centre, amplitude), and a feature that spreads (``feats``, :func:`.design.law_features`)."""
        return bool(feats) and len({(round(d.omega_c, 6), round(d.A_c, 6)) for d in self.train}) >= MIN_LAW_RECORDS

    def applicable(self) -> list[str]:
        """Library effects for this base: chain-only effects need the chain, linear-only ones a linear device;
        ``damping_law`` (the dashpot following record features) is an effect only when the base does not carry
        it already and >= ``MIN_LAW_RECORDS`` training records with distinct features separate it; with covariates,
        every force effect as ``effect@cov`` (its amplitudes following the operating condition)."""
        kind = self.base.kind
        out = [n for n in EFFECT_NAMES if kind in SPECS[n].bases]
        if self.base.law or not self._law_separable(self.base.law_features):
            out = [n for n in out if n != "damping_law"]
        # with operating conditions, a force effect comes with its amplitudes following each of them (it nests the
        # effect at one condition: slopes of 0)
        if not self.covariates:
            return out
        amp = ("force", "mass")
        return ([n for n in out if SPECS[n].kind not in amp]
                + [f"{n}@{c}" for n in out if SPECS[n].kind in amp for c in self.covariates])

    def covariate_terms(self) -> list[str]:
        """Covariate terms of the base open from the start: the dashpot (and the spring of a linear device)."""
        base = ["damping.c"] + (["spring.k"] if self.base.kind == "linear" else [])
        return [f"{a}@{c}" for a in base for c in self.covariates]

    def train_mask(self, test: str) -> np.ndarray:
        """Boolean mask of a record's training samples (the rest is held out)."""
        return self._mask[test]

    def n_cells(self, split: str = "train") -> int:
        """Independent noise cells of a split: its samples, ρ·n of them where a record's force is compared below a
        cut (:mod:`.bandlimit`: the filtered noise is correlated)."""
        return sum(int(d.rho * np.sum(self._mask[d.test] if split == "train" else ~self._mask[d.test]))
                   for d in self.tdata)

    # ------------------------------------------------------------------ linear parts
    def _blocks(self, names: Sequence[str], shapes: dict[str, float], subset: bool
                ) -> tuple[list[Blocks], list[tuple[np.ndarray, np.ndarray, np.ndarray]]]:
        """Per record: block statistics and (f, Φ, y) on the fit subset or on every sample."""
        stats, parts = [], []
        for d in self.tdata:
            idx, lead = self._fit[d.test] if subset else (None, None)
            f, Phi, y = build(self.base, names, shapes, d, idx, self._cache, lead)
            blk = d.block if idx is None else d.block[idx]
            stats.append(Blocks.from_columns(Phi, y - f, blk, d.n_blocks, 1.0 / d.sigma**2))
            parts.append((f, Phi, y))
        return stats, parts

    def columns(self, names: Sequence[str], params: dict[str, float]
                ) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """Per record, on every sample: the fixed force f [N], the amplitude columns Φ (in the order of
        :func:`.design.amplitude_names`; each in N per unit of its amplitude, the dashpot's ẋ in mm/s) and the
        compared force y [N] (low-passed where the record is compared below a cut, as in :meth:`evaluate`), for the
        shape parameters in ``params``."""
        return self._blocks(names, params, False)[1]

    def _train_mult(self) -> np.ndarray:
        """0/1 per (record, block) in stacking order: the training units."""
        tr = {(d.test, b) for d, b in self.train_units}
        return np.array([1.0 if (d.test, b) in tr else 0.0 for d in self.tdata for b in range(d.n_blocks)])

    def _solve(self, names: Sequence[str], bl: Blocks, mult: np.ndarray,
               fix: dict[str, float] | None = None) -> np.ndarray:
        """The bounded least-squares amplitudes; those in ``fix`` held at their values (eliminated).  A dashpot
        law over record features is kept passive on every record of the set
        (:func:`chainid.gap.timedomain.passivity.passive_solve`)."""
        G, h = bl.total(mult)
        amps = amplitude_names(self.base, names)
        lo, hi = amplitude_bounds(amps)
        a = solve_held(G, h, lo, hi, amps, fix)
        if all(k in amps for k in LAW_AMPS):
            return passive_solve(G, h, lo, hi, amps, self.base.refs, self.law_box, a, fix)
        return a

    # ------------------------------------------------------------------ fit
    def fit(self, names: Sequence[str], start: dict[str, float] | None = None,
            polish_only: bool = False, weights: np.ndarray | None = None,
            fix: dict[str, float] | None = None) -> Candidate:
        """Fit an effect set on the training blocks: shape parameters searched on the fit subset (amplitudes
        profiled out), then every amplitude on all training samples.  ``weights``: a multiplicity per block in
        stacking order (a resample), instead of 1 per training block.  ``fix``: parameters (shapes or
        amplitudes) held at these values [their units] (a profile's point).  A full fit (not a polish, not a
        resample) that adds a delay then scans the delay's profile around the fit
        (:func:`chainid.gap.core.delayscan.refine_delay`; Δ: the lag grid's spacing)."""
        c = self._fit_once(names, start, polish_only, weights, fix)
        if polish_only or weights is not None:
            return c
        return refine_delay(self, list(names), c, dict(start or {}), dict(fix or {}),
                            lambda lo, hi: (hi - lo) / max(lag_points(lo, hi, self.f_band) - 1, 1), regrid=True)

    def _fit_once(self, names: Sequence[str], start: dict[str, float] | None, polish_only: bool,
                  weights: np.ndarray | None, fix: dict[str, float] | None) -> Candidate:
        """One fit of :meth:`fit` (its grid search and polish, or its polish)."""
        names = list(names)
        keys = shape_names(self.base, names, self.scales)
        amps = amplitude_names(self.base, names)
        fix = dict(fix or {})
        unknown = sorted(set(fix) - {k for k, _, _ in keys} - set(amps))
        if unknown:
            raise ValueError(f"fix: {unknown} are not fitted parameters of {'+'.join(names) or 'the baseline'} "
                             f"(valid: {[k for k, _, _ in keys] + amps})")
        keys = [k for k in keys if k[0] not in fix]
        fsh = {k: v for k, v in fix.items() if k not in amps}
        fam = {k: v for k, v in fix.items() if k in amps}
        mult = self._train_mult() if weights is None else np.asarray(weights, float)

        def profile(shapes: dict[str, float]) -> tuple[Blocks, np.ndarray]:
            bl = Blocks.stack(self._blocks(names, shapes | fsh, True)[0])
            return bl, self._solve(names, bl, mult, fam)

        def cost(shapes: dict[str, float]) -> float:
            bl, a = profile(shapes)
            return float(np.sum(sse_at(bl, a) * mult))

        def resid(shapes: dict[str, float]) -> np.ndarray:
            stats, parts = self._blocks(names, shapes | fsh, True)
            a = self._solve(names, Blocks.stack(stats), mult, fam)
            out = []
            off = 0
            for d, (f, Phi, y) in zip(self.tdata, parts):
                w = np.sqrt(mult[off + d.block[self._fit[d.test][0]]])  # the block's multiplicity per sample
                out.append((y - f - Phi @ a) * w / d.sigma)
                off += d.n_blocks
            return np.concatenate(out)

        shapes, at_bound = search(keys, cost, resid, dict(start or {}), f_band=self.f_band, polish_only=polish_only)
        shapes = dict(shapes) | fsh
        bl = Blocks.stack(self._blocks(names, shapes, False)[0])
        a = self._solve(names, bl, mult, fam)
        params = dict(shapes) | dict(zip(amps, (float(v) for v in a)))
        params |= self.references(names)
        c = Candidate("+".join(names), params, len(keys) + len(amps), at_bound=at_bound)
        return c

    def param_bounds(self, names: Sequence[str]) -> dict[str, tuple[float, float]]:
        """The fitted parameters of an effect set (shapes, then amplitudes) and their bounds [their units]."""
        amps = amplitude_names(self.base, list(names))
        lo, hi = amplitude_bounds(amps)
        return ({k: (a, b) for k, a, b in shape_names(self.base, list(names), self.scales)}
                | {k: (float(a), float(b)) for k, a, b in zip(amps, lo, hi)})

    def train_chi2(self, names: Sequence[str], params: dict[str, float]) -> tuple[float, int, int]:
        """χ² of the training samples at ``params`` (Σ r²/σ_F², each record's own σ_F), the independent noise cells
        (:meth:`n_cells`) and the fitted values.  Where a record is compared below a cut (:mod:`.bandlimit`) its
        noise has variance ρ·σ_F² over correlated samples about 1/ρ apart: Σ r²/σ_F² is then Σ r²/(ρ·σ_F²) counted
        once per independent cell, and its expectation at the noise is the cells, ρ·n."""
        names = list(names)
        bl = Blocks.stack(self._blocks(names, params, False)[0])
        amps = amplitude_names(self.base, names)
        a = np.array([params[k] for k in amps])
        chi = float(np.sum(sse_at(bl, a) * self._train_mult()))
        return chi, self.n_cells("train"), len(shape_names(self.base, names, self.scales)) + len(amps)

    def references(self, names: Sequence[str]) -> dict[str, float]:
        """Fixed references an effect set's parameters are stated against (not fitted: no interval is stated for
        them); keys as in a fit's ``params``."""
        out = {}
        if "hardening" in names:
            out["hardening.x_ref"] = self.base.refs["x_mid"]
        if self.base.law or "damping_law" in names:
            out["damping_law.w_ref"] = self.base.refs["w_ref"]
            out["damping_law.A_ref"] = self.base.refs["A_ref"]
            out |= {f"damping_law.{k}": v for k, v in self.law_box.items()}  # the box the law was identified on
        for t in names:
            if "@" in t:
                cov = split_name(t)[2]
                out[f"covariate.{cov}.ref"] = self.base.refs[f"cov:{cov}"]
        return out

    # ------------------------------------------------------------------ evaluation
    def evaluate(self, names: Sequence[str], params: dict[str, float]) -> dict[str, Any]:
        """Every sample's residual, per-unit errors (fitted, leave-one-block-out, held out) and variances."""
        names = list(names)
        stats, parts = self._blocks(names, params, False)
        bl = Blocks.stack(stats)
        mult = self._train_mult()
        amps = amplitude_names(self.base, names)
        a = np.array([params[k] for k in amps])
        res, force, var, sse, sse_loo = {}, {}, {}, {}, {}
        loo_a = []
        off = 0
        for d, st, (f, Phi, y) in zip(self.tdata, stats, parts):
            r = y - f - Phi @ a
            res[d.test] = r
            force[d.test] = d.F - r
            for b in range(d.n_blocks):
                m = d.block == b
                key = (d.test, b)
                var[key] = float(np.sum((d.F[m] - self.F_mean[d.test]) ** 2))
                sse[key] = float(np.sum(r[m] ** 2))
                if mult[off + b] > 0:
                    mm = mult.copy()
                    mm[off + b] = 0.0
                    ab = self._solve(names, bl, mm)
                    loo_a.append(ab)
                    sse_loo[key] = float(sse_at(Blocks(st.G[b:b + 1], st.h[b:b + 1], st.s[b:b + 1], st.w[b:b + 1],
                                                       st.n[b:b + 1]), ab)[0]) * d.sigma**2
            off += d.n_blocks
        sd = {}
        if len(loo_a) >= 2:
            sd = dict(zip(amps, (float(s) for s in jackknife_sd(np.array(loo_a)))))
        return {"res": res, "force": force, "var": var, "sse": sse, "sse_loo": sse_loo, "amplitudes": amps,
                "sd": sd, "blocks": bl, "time": {"res": res, "force": force, "c": params.get("damping.c", 0.0)}}

    def noise_floor(self, d: TimeData, params: dict[str, float]) -> float:
        """The residual variance [N²] a right model leaves on record ``d``: its force noise σ_F².  (The kinematics'
        own errors through the fitted base, :meth:`kinematic_floor`, are reported beside it, not counted: a fitted
        mass or dashpot that stands in for a missing effect would raise the floor to meet the misfit.)  Where the
        force is compared below a cut (:mod:`.bandlimit`), the share ρ of σ_F² that passes the filter."""
        return d.rho * d.sigma**2

    def kinematic_floor(self, d: TimeData, params: dict[str, float]) -> float:
        """σ_F² plus the kinematics' predicted errors through the fitted model [N²]: (c·e_v)² + (m·e_a·1e-3)² +
        (k·e_x)² (:mod:`chainid.gap.core.kinematics`), and for sliding friction the variance of its sign where the
        direction is uncertain, F_s²·mean(1 − s²) with s = erf(ẋ̂/(√2·e_v)) the expected sign
        (:func:`chainid.model.effects.forms.sliding_sign`) and F_s the breakaway force (friction F_c, Stribeck
        F_c + dF_s) — what even the true model would leave on these kinematics."""
        kin = d.kin
        if kin is None:
            return self.noise_floor(d, params)
        F_s = (abs(params.get("friction.F_c", 0.0))
               + abs(params.get("stribeck.F_c", 0.0) + params.get("stribeck.dF_s", 0.0)))
        sign_var = 0.0
        if F_s > 0.0 and d.xd.size:
            s = sliding_sign(d.xd, False, kin.v_spread(d.t))
            sign_var = F_s**2 * float(np.mean(1.0 - s**2))
        c = self.record_c(d, params)
        m = params.get("mass.m", self.base.mass_kg or 0.0) + (self.model.mass_kg if self.is_chain else 0.0)
        m += params.get("fixture_mass.m_f", 0.0)
        k = params.get("spring.k", 0.0)
        if self.is_chain:
            k = float(np.asarray(self.model.stiffness(np.array([max(d.x0, 1e-6)])), float)[0])
        return (self.noise_floor(d, params) + (c * kin.err_v) ** 2 + (m * 1e-3 * kin.err_a) ** 2
                + (k * kin.err_x) ** 2 + sign_var)

    def record_c(self, d: TimeData, params: dict[str, float]) -> float:
        """Record ``d``'s dashpot [N·s/mm]: one c, or where the damping follows the records' features the law
        c + b_w·(ω_r − w_ref) + b_A·(A_r − A_ref) at the record's band centre and amplitude (:func:`feature_c`)."""
        refs = self.base.refs
        return feature_c(params.get("damping.c", 0.0), params.get("damping_law.b_w", 0.0),
                         params.get("damping_law.b_A", 0.0), d.omega_c, d.A_c, refs["w_ref"], refs["A_ref"])

    def floor_rel_sd(self, split: str = "hold") -> float:
        """Relative standard deviation of a split's noise floor from the estimate of each record's force noise:
        σ̂² = (1.4826·MAD(Δ²F))²/6 has a relative sd of ``SIGMA2_REL_SD``/√n over n samples of white noise."""
        units = self.train_units if split == "train" else self.hold_units
        num = den = 0.0
        per: dict[str, int] = {}
        for d, b in units:
            per[d.test] = per.get(d.test, 0) + int(np.sum(d.block == b))
        for d in self.tdata:
            if d.test in per:
                w = per[d.test] * self.noise_floor(d, {})
                num += w**2 * SIGMA2_REL_SD**2 / d.t.size
                den += w
        return math.sqrt(num) / den if den > 0 else 0.0

    def noise_db(self, ev: dict[str, Any], split: str = "hold") -> tuple[float, float, float]:
        """Mean squared residual per sample of a split, its noise floor [N²] and their ratio in dB (``train`` uses
        the leave-one-block-out errors)."""
        params = ev.get("params", {})
        units = self.train_units if split == "train" else self.hold_units
        r2 = f2 = 0.0
        n = 0
        for d, b in units:
            m = d.block == b
            cnt = int(m.sum())
            r2 += ev["sse_loo"][(d.test, b)] if split == "train" else ev["sse"][(d.test, b)]
            f2 += self.noise_floor(d, params) * cnt
            n += cnt
        if n == 0:
            return float("nan"), float("nan"), float("nan")
        r2, f2 = r2 / n, f2 / n
        return r2, f2, 10 * math.log10(max(r2, 1e-300) / max(f2, 1e-300))

    def score(self, cand: Candidate, names: Sequence[str], base_hold: float) -> Candidate:
        """Score a fitted candidate: fitted, leave-one-block-out and held-out NRMSE, BIC, dB over the floor."""
        ev = self.evaluate(names, cand.params)
        ev["params"] = cand.params
        tr = [(d.test, b) for d, b in self.train_units]
        ho = [(d.test, b) for d, b in self.hold_units]
        f = lambda a, b: math.sqrt(a / b) if b > 0 else float("nan")  # noqa: E731
        den_tr = sum(ev["var"][k] for k in tr)
        cand.nrmse_train = f(sum(ev["sse"][k] for k in tr), den_tr)
        cand.nrmse_loto = f(sum(ev["sse_loo"][k] for k in tr), den_tr)
        cand.nrmse_holdout = f(sum(ev["sse"][k] for k in ho), sum(ev["var"][k] for k in ho))
        cand.shrinkage = 1.0 - cand.nrmse_holdout / base_hold if base_hold > 0 else float("nan")
        cand.loto_num = {f"{t}#{b}": ev["sse_loo"][(t, b)] for t, b in tr}
        sig = {d.test: d.sigma for d in self.tdata}
        cand.chi2_train = sum(ev["sse"][k] / sig[k[0]] ** 2 for k in tr)
        cand.bic = cand.chi2_train + cand.n_params * math.log(max(self.n_cells("train"), 2))
        cand.db_holdout = self.noise_db(ev, "hold")[2]
        cand.db_train = self.noise_db(ev, "train")[2]
        cand.per_test = {}
        for d in self.tdata:
            den = float(np.sum((d.F - self.F_mean[d.test]) ** 2))
            cand.per_test[d.test] = math.sqrt(float(np.sum(ev["res"][d.test] ** 2)) / den) if den > 0 else math.nan
        law = self.base.law or "damping_law" in names
        cand.law = "feature" if law else "viscous"
        cand.law_params = [cand.params.get(k, 0.0) for k in (("damping.c", "damping_law.b_w", "damping_law.b_A")
                                                             if law else ("damping.c",))]
        cand.param_sd = {k: v for k, v in ev["sd"].items()}
        cand._ev = ev  # type: ignore[attr-defined]
        return cand

    def state_table(self, ev: dict[str, Any]) -> dict[str, Any]:
        """The state of every sample (x, ẋ, ẍ, travel since reversal, direction, x a quarter band-edge period
        earlier, the model force, the covariates) and the residual of evaluation ``ev``, split into training and
        held-out rows, for the model-free check (:mod:`chainid.gap.core.openworld`)."""
        from chainid.gap.timedomain.data import travel_since_reversal

        rows: dict[str, list[Any]] = {"Xt": [], "rt": [], "Xh": [], "rh": [], "uh": []}
        for d in self.tdata:
            lag = np.interp(d.t - 0.25 / max(d.f_band, 1e-9), d.t, d.x)
            cols = [d.x, d.xd, d.xdd, travel_since_reversal(d.x, d.xd), np.sign(d.xd), lag, ev["force"][d.test]]
            cols += [np.full(d.t.size, d.covariates.get(c, np.nan)) for c in self.covariates]
            X = np.column_stack(cols)
            m = self._mask[d.test]
            rows["Xt"].append(X[m])
            rows["rt"].append(ev["res"][d.test][m])
            rows["Xh"].append(X[~m])
            rows["rh"].append(ev["res"][d.test][~m])
            rows["uh"].append(np.array([f"{d.test}#{b}" for b in d.block[~m]]))
        cat = lambda k: np.concatenate(rows[k]) if rows[k] else np.zeros(0)  # noqa: E731
        return {"X_train": cat("Xt"), "r_train": cat("rt"), "X_hold": cat("Xh"), "r_hold": cat("rh"),
                "unit_hold": cat("uh"), "names": ["x", "xd", "xdd", "travel", "direction", "x_lag", "load"]
                + list(self.covariates)}

    # ------------------------------------------------------------------ models
    def model_for(self, p: dict[str, float]) -> Any:
        """The base spring of a fitted parameter set: the chain model, or a linear spring k [N/mm] through the
        training records' mean force at their mean displacement, with the fitted mass."""
        if self.is_chain:
            return self.model
        from chainid.model.base import LinearModel

        k = max(float(p.get("spring.k", 0.0)), 0.0)
        tr = [d for d in self.tdata if self._mask[d.test].any()]
        xm = float(np.mean([d.x0 for d in tr]))
        Fm = float(np.mean([np.mean(d.F) for d in tr]))
        m = self.base.mass_kg if self.base.mass_kg is not None else max(float(p.get("mass.m", 0.0)), 0.0)
        return LinearModel(k, xm - Fm / k if k > 0 else xm, mass=m)
