"""Whether a chosen hysteresis is rate-independent, as its form says: its loop refitted on slow and fast blocks.

Dahl hysteresis (and Bouc–Wen, its shaped form) is rate-independent: dz/dt = |ẋ|·(F_h·sgn(ẋ) − z)/x_h, so z
follows the path in x, not the speed along it, and F_h and x_h are the same on slow and on fast motion.  A
mechanism that is not, fitted as one, shows it there.  The plainest is a viscoelastic relaxation (a Maxwell
element: a spring k_m in series with a dashpot of time constant τ, outside the library): dq/dt = k_m·ẋ − q/τ =
|ẋ|·(k_m·τ·|ẋ|·sgn(ẋ) − q)/(τ·|ẋ|), a Dahl loop whose F_h = k_m·τ·|ẋ| and x_h = τ·|ẋ| grow in proportion to the
speed (rate exponent 1).  Where τ·|ẋ| outgrows the stroke the branch acts as a spring k_m, and a loop fitted to
it changes with the speed in either direction; a velocity-weakening friction makes a loop that shrinks with it.

The check, on the **kept chain's last fit** (the effect beside every other effect of the chain, so a later
velocity-dependent step such as Stribeck friction takes its own part):

* the training blocks that move (RMS speed v > 0) are split at their median speed, at least :data:`MIN_BLOCKS`
  of them; the halves' geometric-mean speeds must differ by ×:data:`MIN_SPEED_RATIO` at least;
* the fit is refitted on each half (shapes polished from it, amplitudes exact: :meth:`TimeProblem.fit` with the
  halves as block weights); for each of the effect's scale parameters θ (a force [N] and a travel [mm]) the log
  ratio L = ln(θ_fast/θ_slow) is read (not read where either refit sits at a bound of θ's range);
* when one of them changes by a rate exponent L/ℓ_v of at least :data:`MIN_EXPONENT` (ℓ_v the halves' log speed
  ratio), up to :data:`N_RANDOM` distinct random halves of the same blocks are refitted as well, and L is
  regressed on (ℓ_v, ℓ_s) over all the splits, through zero (ℓ_s the halves' log ratio of RMS stroke, so that a
  loop following the amplitude is not read as following the speed): the rate exponent p is the slope on ℓ_v and
  z = |p|/se(p), se from the scatter about the plane (n − 2 degrees of freedom);
* the effect is **rate-dependent** when |p| ≥ :data:`MIN_EXPONENT` (half way from the rate-independent form, 0, to
  a loop scaling with the speed, 1) and z ≥ :data:`Z` (the step rule's).  Splits whose speed and stroke ratios
  go together (|correlation| > :data:`MAX_CORRELATION`) cannot separate them: not judged.

A rate-dependent effect is not kept: the chain is cut before the step that added it (it stands in for a
mechanism the library does not have) and the finding ``rate_dependence`` says why.  The harmonic route has no
such check (a harmonic test's speed and amplitude go together).

Units: N and mm for the parameters, mm/s for the speeds, mm for the strokes.
"""

from __future__ import annotations

import math
from typing import Any, Sequence

import numpy as np

from chainid.gap.core.steprule import Z as STEP_Z

__all__ = ["RATE_PARAMS", "MIN_BLOCKS", "MIN_SPEED_RATIO", "MIN_EXPONENT", "Z", "N_RANDOM", "MAX_CORRELATION",
           "block_stats", "rate_exponent", "rate_test", "rate_cut"]

#: the rate-independent loop effects and their scale parameters (a force [N] and a travel [mm])
RATE_PARAMS = {"hysteresis": ("F_h", "x_h"), "bouc_wen": ("F_y", "x_y")}
#: fewest moving training blocks to split (four halves of four blocks leave three distinct partitions)
MIN_BLOCKS = 8
#: slowest ratio of the fast half's speed to the slow half's at which the rate exponent is read
MIN_SPEED_RATIO = 1.5
#: smallest |rate exponent| that counts: half way from rate-independent (0) to a loop scaling with speed (1)
MIN_EXPONENT = 0.5
#: z of the rate exponent (the step rule's z, 2)
Z = STEP_Z
#: random halves beside the speed split
N_RANDOM = 10
#: above this |correlation| of the splits' speed and stroke ratios the two cannot be told apart
MAX_CORRELATION = 0.95


def block_stats(prob: Any) -> tuple[np.ndarray, np.ndarray]:
    """RMS speed [mm/s] and RMS stroke (x about the block's mean) [mm] of every block, in the problem's stacking
    order (0 for an empty block)."""
    v, s = [], []
    for d in prob.tdata:
        for b in range(d.n_blocks):
            m = d.block == b
            xd, x = d.xd[m], d.x[m]
            v.append(math.sqrt(float(np.mean(xd * xd))) if xd.size else 0.0)
            s.append(float(np.std(x)) if x.size else 0.0)
    return np.asarray(v, float), np.asarray(s, float)


def _refits(prob: Any, cand: Any, keys: Sequence[str], a: np.ndarray, b: np.ndarray
            ) -> tuple[dict[str, float], dict[str, float]]:
    """The values of ``keys`` with ``cand`` refitted on block weights ``a`` and on ``b`` (NaN where a refit sits at
    a bound of that parameter's range)."""
    out = []
    for w in (a, b):
        c = prob.fit(cand.names, start=cand.params, polish_only=True, weights=w)
        out.append({k: float("nan") if k in c.at_bound else float(c.params.get(k, float("nan"))) for k in keys})
    return out[0], out[1]


def _log_ratio(a: float, b: float) -> float:
    """ln(b/a), NaN unless both are > 0."""
    return math.log(b / a) if a > 0 and b > 0 else float("nan")


def _split(train: np.ndarray, first: np.ndarray, second: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Block weights of two halves of the training blocks (indices ``first`` and ``second``)."""
    a, b = np.zeros_like(train), np.zeros_like(train)
    a[first], b[second] = train[first], train[second]
    return a, b


def _random_halves(idx: np.ndarray, speed_half: np.ndarray, n: int) -> list[np.ndarray]:
    """Up to ``n`` distinct random halves of the blocks ``idx`` (as their first halves), none the speed split
    ``speed_half`` or its mirror; a fixed seed, so the check is reproducible."""
    rng = np.random.default_rng(0)
    h, first = idx.size // 2, int(idx.min())
    everything = frozenset(idx.tolist())

    def key(half: np.ndarray) -> frozenset:  # a partition, whichever half is named: the side holding idx.min()
        f = frozenset(half.tolist())
        return f if first in f else everything - f

    seen, out = {key(speed_half)}, []
    for _ in range(50 * n):
        half = rng.permutation(idx)[:h]
        k = key(half)
        if k not in seen:
            seen.add(k)
            out.append(np.sort(half))
        if len(out) == n:
            break
    return out


def rate_exponent(ell_v: np.ndarray, ell_s: np.ndarray, L: np.ndarray) -> tuple[float, float]:
    """The rate exponent p and its z = |p|/se(p) from L = p·ℓ_v + q·ℓ_s over the splits, least squares through 0.

    Parameters
    ----------
    ell_v, ell_s : each split's log ratio of the halves' speeds and of their strokes
    L : each split's log ratio of the parameter (NaN: not read; left out)

    Returns
    -------
    (p, z); NaN for both with fewer than 4 finite splits or when ℓ_v and ℓ_s correlate beyond
    :data:`MAX_CORRELATION` (z is inf when the splits lie exactly on the plane).
    """
    ok = np.isfinite(L)
    X = np.column_stack([ell_v[ok], ell_s[ok]])
    y = L[ok]
    if y.size < 4:
        return float("nan"), float("nan")
    G = X.T @ X
    if G[0, 0] <= 0 or G[1, 1] <= 0 or abs(G[0, 1]) / math.sqrt(G[0, 0] * G[1, 1]) > MAX_CORRELATION:
        return float("nan"), float("nan")
    beta = np.linalg.solve(G, X.T @ y)
    rss = float(np.sum((y - X @ beta) ** 2))
    se = math.sqrt(rss / (y.size - 2) * float(np.linalg.inv(G)[0, 0]))
    p = float(beta[0])
    return p, (abs(p) / se if se > 0 else math.inf)


def rate_test(prob: Any, cand: Any, effect: str) -> dict[str, Any] | None:
    """The rate check of ``effect`` in the fitted candidate ``cand`` (the module docstring).

    Parameters
    ----------
    prob : the time-domain problem (:class:`chainid.gap.timedomain.problem.TimeProblem`)
    cand : a fitted candidate holding ``effect``
    effect : a key of :data:`RATE_PARAMS`

    Returns
    -------
    dict or None
        The halves' geometric-mean speeds [mm/s] (``v_slow_mm_s``, ``v_fast_mm_s``), each parameter's values on
        them (``on_slow``, ``on_fast``), their log ratio, the rate exponent p and its z per parameter, and
        ``dependent`` (the parameters that pass both tests); None when the blocks cannot resolve a rate (fewer
        than :data:`MIN_BLOCKS` moving training blocks, or speeds within ×:data:`MIN_SPEED_RATIO`).
    """
    train = prob._train_mult()
    v, st = block_stats(prob)
    idx = np.flatnonzero((train > 0) & (v > 0) & (st > 0))
    if idx.size < MIN_BLOCKS:
        return None
    lnv, lns, h = np.log(np.where(v > 0, v, 1.0)), np.log(np.where(st > 0, st, 1.0)), idx.size // 2
    order = idx[np.argsort(v[idx], kind="stable")]
    ell = lambda a, b: (float(np.mean(lnv[b]) - np.mean(lnv[a])), float(np.mean(lns[b]) - np.mean(lns[a])))  # noqa
    ell_v0, ell_s0 = ell(order[:h], order[h:])
    if ell_v0 < math.log(MIN_SPEED_RATIO):
        return None
    keys = [f"{effect}.{p}" for p in RATE_PARAMS[effect]]
    on_slow, on_fast = _refits(prob, cand, keys, *_split(train, order[:h], order[h:]))
    L0 = {k: _log_ratio(on_slow[k], on_fast[k]) for k in keys}
    p = {k: L0[k] / ell_v0 for k in keys}  # the speed split's own, until the regression
    z = {k: float("nan") for k in keys}
    if any(math.isfinite(p[k]) and abs(p[k]) >= MIN_EXPONENT for k in keys):
        ev, es, L = [ell_v0], [ell_s0], {k: [L0[k]] for k in keys}
        for half in _random_halves(idx, order[:h], N_RANDOM):
            rest = np.setdiff1d(idx, half)
            ra, rb = _refits(prob, cand, keys, *_split(train, half, rest))
            a_v, a_s = ell(half, rest)
            ev.append(a_v)
            es.append(a_s)
            for k in keys:
                L[k].append(_log_ratio(ra[k], rb[k]))
        for k in keys:
            p[k], z[k] = rate_exponent(np.asarray(ev), np.asarray(es), np.asarray(L[k]))
    dependent = [k for k in keys if math.isfinite(L0[k]) and abs(p[k]) >= MIN_EXPONENT and z[k] >= Z]
    v_slow, v_fast = math.exp(float(np.mean(lnv[order[:h]]))), math.exp(float(np.mean(lnv[order[h:]])))
    return {"effect": effect, "v_slow_mm_s": v_slow, "v_fast_mm_s": v_fast, "on_slow": on_slow, "on_fast": on_fast,
            "log_ratio": L0, "exponent": p, "z": z, "dependent": dependent}


def _json_z(z: dict[str, float]) -> dict[str, float | None]:
    """z values as JSON holds them: NaN (not computed) as None, inf (no scatter) as 1e6."""
    return {k: None if math.isnan(v) else min(v, 1e6) for k, v in z.items()}


def _finding(step: int, effect: str, name: str, t: dict[str, Any]) -> dict[str, Any]:
    """The ``where`` finding of a rate-dependent effect added at ``step`` (``name``: as the chain names it, with
    an operating condition's ``@cov`` where its amplitude follows one)."""
    k = max(t["dependent"], key=lambda q: t["z"][q])
    ratio, p, zf = t["v_fast_mm_s"] / t["v_slow_mm_s"], t["exponent"][k], _json_z(t["z"])
    why = ("the loop grows with the speed, as a viscoelastic relaxation's does (F_h, x_h ∝ τ·|ẋ|)" if p > 0 else
           "the loop shrinks with the speed (a velocity-weakening friction, or a relaxation acting as a spring "
           "where τ·|ẋ| outgrows the stroke)")
    text = (f"{effect} (step {step}) is not rate-independent as its form says: refitted on the slower and faster "
            f"halves of the training blocks (RMS speed {t['v_slow_mm_s']:.3g} vs {t['v_fast_mm_s']:.3g} mm/s, "
            f"×{ratio:.2f}), {k} goes from {t['on_slow'][k]:.4g} to {t['on_fast'][k]:.4g}; over these and "
            f"{N_RANDOM} random halves its rate exponent is {p:.2f} (z {zf[k]:.1f}, the stroke's part "
            f"apart): {why}; a mechanism outside the library stands in for it, so it is not kept")
    return {"kind": "rate_dependence", "finding": text, "step": step, "effect": effect, "name": name, "parameter": k,
            "exponent": p, "z": zf[k], "speed_ratio": ratio, "score": zf[k], "exponents": t["exponent"], "z_all": zf}


def _checks(prob: Any, path: Sequence[Any]) -> list[tuple[dict[str, Any], dict[str, Any] | None]]:
    """Every loop effect of the chain's last fit (``path[-1]``) checked there: (its row for the JSON's
    ``rate_checks`` — the step that added it, whether the blocks could judge it, and where they could, its rate
    exponents, z values and the halves' speed ratio: a loop kept was checked, and this is what the check read —,
    the raw :func:`rate_test` or None)."""
    if len(path) < 2:
        return []
    final, out = path[-1], []
    for name in final.names:
        effect = name.split("@", 1)[0]  # an effect whose amplitude follows an operating condition: its own form
        if effect not in RATE_PARAMS:
            continue
        t = rate_test(prob, final, effect)
        step = next(i for i in range(1, len(path)) if name in path[i].names)
        row: dict[str, Any] = {"effect": effect, "name": name, "step": step, "judged": t is not None}
        if t is not None:
            row |= {"exponent": t["exponent"], "z": _json_z(t["z"]),
                    "speed_ratio": t["v_fast_mm_s"] / t["v_slow_mm_s"], "dependent": t["dependent"]}
        out.append((row, t))
    return out


def rate_cut(prob: Any, path: Sequence[Any]) -> tuple[int | None, dict[str, Any] | None, list[dict[str, Any]]]:
    """The step of ``path`` (step 0 the baseline) before which the chain is cut, its finding, and every check's
    row (the JSON's ``rate_checks``): the earliest step that added a rate-dependent loop effect; (None, None, rows)
    when every one passes or cannot be judged."""
    checks = _checks(prob, path)
    hits = [(row, t) for row, t in checks if row.get("dependent")]
    if not hits:
        return None, None, [row for row, _ in checks]
    row, t = min(hits, key=lambda h: h[0]["step"])
    return row["step"], _finding(row["step"], row["effect"], row["name"], t), [r for r, _ in checks]
