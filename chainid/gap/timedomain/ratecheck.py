"""Whether a chosen hysteresis is rate-independent, as its form says: its loop refitted on slow and fast blocks.

Dahl hysteresis (and Bouc–Wen, its shaped form) is rate-independent: dz/dx = (F_h·sgn(ẋ) − z)/x_h depends on the
path in x, not on the speed along it, so F_h and x_h are the same on slow and on fast motion.  A mechanism that
is not, fitted as one, shows it there.  The plainest is a viscoelastic relaxation (a Maxwell element, a spring
k_m in series with a dashpot of time constant τ, outside the library): its force q obeys
dq/dx = (k_m·τ·|ẋ| − q)/(τ·|ẋ|) for ẋ ≠ 0, a Dahl loop whose F_h = k_m·τ·|ẋ| and x_h = τ·|ẋ| grow in proportion
to the speed (rate exponent 1); at speeds where τ·|ẋ| outgrows the stroke it stiffens into a spring and the loop
shrinks instead.

The check: the training blocks are split at their median RMS speed (Section: the time route's blocks, each
record cut in contiguous blocks); the candidate that added the effect is refitted on each half (shapes polished
from its fit, amplitudes exact: :meth:`TimeProblem.fit` with the halves as block weights), and for each of the
effect's scale parameters θ (a force and a travel) the log ratio L = ln(θ_fast/θ_slow) and the rate exponent
p = L / ln(v_fast/v_slow) are read.  The effect is **rate-dependent** when, for one of them,

* the halves' speeds differ enough to resolve it: v_fast/v_slow ≥ :data:`MIN_SPEED_RATIO`;
* the change is material: |p| ≥ :data:`MIN_EXPONENT`, half way from the rate-independent form (0) to a loop
  that scales with the speed (1);
* and significant: |L| ≥ :data:`Z` times the root mean square of L over :data:`N_RANDOM` random halves of the
  same training blocks (what splitting alone moves θ by; computed only when the first two hold).

A rate-dependent step is not kept: the chain is cut before it (the effect stands in for a mechanism the library
does not have) and the finding ``rate_dependence`` says why.  The harmonic route has no such check (a harmonic
test's speed and amplitude go together).

Units: N and mm for the parameters, mm/s for the speeds.
"""

from __future__ import annotations

import math
from typing import Any, Sequence

import numpy as np

from chainid.gap.core.steprule import Z as STEP_Z

__all__ = ["RATE_PARAMS", "MIN_SPEED_RATIO", "MIN_EXPONENT", "Z", "N_RANDOM", "block_speeds", "rate_exponent",
           "rate_test", "rate_cut"]

#: the rate-independent loop effects and their scale parameters (a force [N] and a travel [mm])
RATE_PARAMS = {"hysteresis": ("F_h", "x_h"), "bouc_wen": ("F_y", "x_y")}
#: slowest ratio of the fast half's speed to the slow half's at which the rate exponent is read
MIN_SPEED_RATIO = 1.5
#: smallest |rate exponent| that counts: half way from rate-independent (0) to a loop scaling with speed (1)
MIN_EXPONENT = 0.5
#: the speed split's log ratio against the random halves' RMS log ratio (the step rule's z, 2)
Z = STEP_Z
#: random halves for the reference spread
N_RANDOM = 10


def block_speeds(prob: Any) -> np.ndarray:
    """RMS speed [mm/s] of every block in the problem's stacking order (0 for an empty block)."""
    out = []
    for d in prob.tdata:
        for b in range(d.n_blocks):
            v = d.xd[d.block == b]
            out.append(math.sqrt(float(np.mean(v * v))) if v.size else 0.0)
    return np.asarray(out, float)


def _refits(prob: Any, cand: Any, keys: Sequence[str], a: np.ndarray, b: np.ndarray
            ) -> tuple[dict[str, float], dict[str, float]]:
    """The values of ``keys`` with ``cand`` refitted on block weights ``a`` and on ``b``."""
    pa = prob.fit(cand.names, start=cand.params, polish_only=True, weights=a).params
    pb = prob.fit(cand.names, start=cand.params, polish_only=True, weights=b).params
    return {k: float(pa.get(k, float("nan"))) for k in keys}, {k: float(pb.get(k, float("nan"))) for k in keys}


def _log_ratio(a: float, b: float) -> float:
    """ln(b/a), NaN unless both are > 0."""
    return math.log(b / a) if a > 0 and b > 0 else float("nan")


def _split(train: np.ndarray, first: np.ndarray, second: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Block weights of two halves of the training blocks (indices ``first`` and ``second``)."""
    a, b = np.zeros_like(train), np.zeros_like(train)
    a[first], b[second] = train[first], train[second]
    return a, b


def rate_test(prob: Any, cand: Any, effect: str) -> dict[str, Any] | None:
    """The rate check of ``effect`` in the fitted candidate ``cand`` (see the module docstring): a dict with the
    halves' geometric-mean speeds [mm/s], each parameter's values on them, its rate exponent p and z, and
    ``dependent``; None when the training blocks cannot resolve it (fewer than 4 moving ones, or a speed ratio
    below :data:`MIN_SPEED_RATIO`)."""
    train = prob._train_mult()
    v = block_speeds(prob)
    idx = np.flatnonzero((train > 0) & (v > 0))
    if idx.size < 4:
        return None
    lnv, h = np.log(np.where(v > 0, v, 1.0)), idx.size // 2
    order = idx[np.argsort(v[idx], kind="stable")]
    ell0 = float(np.mean(lnv[order[h:]]) - np.mean(lnv[order[:h]]))
    if ell0 < math.log(MIN_SPEED_RATIO):
        return None
    keys = [f"{effect}.{p}" for p in RATE_PARAMS[effect]]
    on_slow, on_fast = _refits(prob, cand, keys, *_split(train, order[:h], order[h:]))
    L0 = {k: _log_ratio(on_slow[k], on_fast[k]) for k in keys}
    p = {k: L0[k] / ell0 for k in keys}
    z = {k: float("nan") for k in keys}
    if any(math.isfinite(p[k]) and abs(p[k]) >= MIN_EXPONENT for k in keys):
        rng = np.random.default_rng(0)
        ell, L = [ell0], {k: [L0[k]] for k in keys}
        for _ in range(N_RANDOM):
            perm = rng.permutation(idx)
            ra, rb = _refits(prob, cand, keys, *_split(train, perm[:h], perm[h:]))
            ell.append(float(np.mean(lnv[perm[h:]]) - np.mean(lnv[perm[:h]])))
            for k in keys:
                L[k].append(_log_ratio(ra[k], rb[k]))
        for k in keys:
            p[k], z[k] = rate_exponent(np.asarray(ell), np.asarray(L[k]))
    dependent = [k for k in keys if abs(p[k]) >= MIN_EXPONENT and z[k] >= Z]
    v_slow, v_fast = math.exp(float(np.mean(lnv[order[:h]]))), math.exp(float(np.mean(lnv[order[h:]])))
    return {"effect": effect, "v_slow_mm_s": v_slow, "v_fast_mm_s": v_fast, "on_slow": on_slow, "on_fast": on_fast,
            "log_ratio": L0, "exponent": p, "z": z, "dependent": dependent}


def rate_exponent(ell: np.ndarray, L: np.ndarray) -> tuple[float, float]:
    """The rate exponent p of L = p·ℓ over the splits (least squares through 0: each split's log ratio of a
    parameter against its log ratio of speeds) and its z = |p|/se, se from the scatter about the line (NaN with
    fewer than 3 finite splits)."""
    ok = np.isfinite(L)
    ell, L = ell[ok], L[ok]
    sxx = float(np.sum(ell * ell))
    if L.size < 3 or sxx <= 0:
        return float("nan"), float("nan")
    p = float(np.sum(ell * L) / sxx)
    se = math.sqrt(float(np.sum((L - p * ell) ** 2)) / (L.size - 1) / sxx)
    return p, (abs(p) / se if se > 0 else math.inf)


def _finding(step: int, effect: str, t: dict[str, Any]) -> dict[str, Any]:
    """The ``where`` finding of a rate-dependent step."""
    k = max(t["dependent"], key=lambda q: t["z"][q])
    ratio = t["v_fast_mm_s"] / t["v_slow_mm_s"]
    text = (f"{effect} (step {step}) is not rate-independent as its form says: refitted on the slower and faster "
            f"halves of the training blocks (RMS speed {t['v_slow_mm_s']:.3g} vs {t['v_fast_mm_s']:.3g} mm/s, "
            f"×{ratio:.2f}), {k} goes from {t['on_slow'][k]:.4g} to {t['on_fast'][k]:.4g} (∝ v^"
            f"{t['exponent'][k]:.2f}, z {t['z'][k]:.1f} over random halves): a rate-dependent mechanism outside the "
            "library stands in for it (a viscoelastic relaxation: its loop grows with τ·|ẋ|, then stiffens into a "
            "spring once τ·|ẋ| outgrows the stroke); not kept")
    return {"kind": "rate_dependence", "finding": text, "step": step, "effect": effect, "parameter": k,
            "exponent": t["exponent"][k], "z": t["z"][k], "speed_ratio": ratio, "score": t["z"][k],
            "exponents": t["exponent"], "z_all": t["z"]}


def rate_cut(prob: Any, path: Sequence[Any]) -> tuple[int | None, dict[str, Any] | None]:
    """The first step of ``path`` (step 0 the baseline) that adds a rate-dependent loop effect, and its finding;
    (None, None) when every loop effect in the chain passes or cannot be judged."""
    for i in range(1, len(path)):
        added = [n for n in path[i].names if n not in path[i - 1].names]
        for effect in added:
            if effect not in RATE_PARAMS:
                continue
            t = rate_test(prob, path[i], effect)
            if t is not None and t["dependent"]:
                return i, _finding(i, effect, t)
    return None, None
