"""Start points of the bounded least-squares fit of an effect set (unit box u ∈ [0, 1]^k).

A coarse grid over the parameters of the effect(s) being added (log-spaced toward
small values: most effects are small corrections), the parameters of effects
already fitted kept at their start values.  Kept apart from the fitting
(:mod:`chainid.gap.harmonic.problem`) so the search can be changed in one place.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

GRID1 = (0.0, 0.003, 0.01, 0.03, 0.1, 0.3, 0.6)
GRID2 = (0.0, 0.003, 0.03, 0.2)
#: start points of a delay over its range (± half the shortest period): spacing 1/40 of a period at ω_max
DELAY_GRID = 40


def starts(keys: Sequence[str], names: Sequence[str], ug: np.ndarray, fixed: np.ndarray,
           lo: np.ndarray, hi: np.ndarray) -> list[np.ndarray]:
    """Candidate start vectors in the unit box.

    Parameters
    ----------
    keys : parameter keys ``effect.param`` (``spring.k``/``spring.x_ref`` first for a linear baseline)
    names : effect names of the set
    ug : default start (unit box), with the fixed entries already set
    fixed : which entries come from a previous fit (not gridded)
    lo, hi : physical bounds of each parameter

    Returns
    -------
    list of ndarray
        The default start ``ug`` first, then (u the unit-box value of a free parameter):

        * one free parameter: u ∈ ``GRID1`` (0, 0.003, 0.01, 0.03, 0.1, 0.3, 0.6), u = 0.5 − (0.01, 0.05, 0.2);
          a range straddling 0 (at z = −lo/(hi − lo)): z ∓ 0.002, 0.01, 0.05, 0.15; a delay (``.tau``): the
          ``DELAY_GRID`` midpoints (i + ½)/40; a scale or delay: ug × (0.5, 0.7, 0.85, 1.2, 1.5, 2, 3);
        * two or more free: the first two over ``GRID2`` × ``GRID2`` (0, 0.003, 0.03, 0.2), the others at ug;
          a new friction (F_c, µ where the base fits it, x_s), by name, also (0.001, 0.003, 0.01, 0.03, 0.2) × 0
          × (0.001, 0.003, 0.01, 0.03, 0.1, 0.4) (a stick travel of a few µm is a basin of its own: from a longer
          one the fit slides to pure Coulomb sliding, whose cost is flat in x_s, with a low F_c); a contact law
          (0.05, 0.18, 0.4) × (0.2, 0.39, 0.6);
          a hysteresis (0.01, 0.05, 0.2) × (0.005, 0.01, 0.02);
        * a linear baseline (``spring.k`` first): every start above again with k × 0.1, then with k × 0.01;

        each clipped to the unit box.
    """
    free = [i for i, k in enumerate(keys) if not fixed[i] and not k.startswith("spring.")]
    out = [ug.copy()]

    def put(vals: Sequence[float]) -> np.ndarray:
        u = ug.copy()
        for i, v in zip(free, vals):
            u[i] = v
        return u

    def put_named(vals: dict[str, float]) -> np.ndarray:
        u = ug.copy()
        for i in free:
            u[i] = vals.get(keys[i], u[i])
        return u

    new_effects = {keys[i].split(".", 1)[0] for i in free}
    if len(free) == 1:
        i = free[0]
        out += [put([g]) for g in GRID1] + [put([0.5 - g]) for g in (0.01, 0.05, 0.2)]
        if lo[i] < 0 < hi[i]:
            z = -lo[i] / (hi[i] - lo[i])
            out += [put([z + s * g]) for g in (0.002, 0.01, 0.05, 0.15) for s in (-1, 1)]
        if keys[i].endswith(".tau"):  # a global start for a delay: a grid over ± half the shortest period
            out += [put([u]) for u in (np.arange(DELAY_GRID) + 0.5) / DELAY_GRID]
        if keys[i].endswith(".scale") or keys[i].endswith(".tau"):  # around the neutral value
            z = float(ug[i])
            out += [put([z * f]) for f in (0.5, 0.7, 0.85, 1.2, 1.5, 2.0, 3.0)]
    elif len(free) >= 2:
        for a in GRID2:
            for b in GRID2:
                out.append(put([a, b] + [ug[i] for i in free[2:]]))
        if new_effects == {"friction"}:  # by name: a linear base does not fit µ
            out += [put_named({"friction.F_c": a, "friction.mu": 0.0, "friction.x_s": c})
                    for a in (0.001, 0.003, 0.01, 0.03, 0.2) for c in (0.001, 0.003, 0.01, 0.03, 0.1, 0.4)]
        if new_effects == {"contact_law"}:
            out += [put([a, b]) for a in (0.05, 0.18, 0.4) for b in (0.2, 0.39, 0.6)]
        if new_effects == {"hysteresis"}:
            out += [put([a, b]) for a in (0.01, 0.05, 0.2) for b in (0.005, 0.01, 0.02)]
    if keys and keys[0] == "spring.k":  # the spring may soften a lot once an effect carries the force
        out += [np.concatenate([[u[0] * f, u[1]], u[2:]]) for f in (0.1, 0.01) for u in list(out)]
    return [np.clip(u, 0, 1) for u in out]
