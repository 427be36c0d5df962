"""A fitted effect set and its scores, shared by both routes and the selection.

* :class:`Candidate` — the effect set's parameters (in each effect's units), NRMSE scores (fitted, leave-one-out,
  held out), shrinkage, BIC, per-test errors and the parameters pinned at a bound;
* :func:`jackknife_sd` — the jack-knife standard deviation of leave-one-out estimates;
* :data:`MIN_TRAIN` — the fewest training units a diagnosis runs with;
* :class:`Problem` — what the selection needs of a route's problem (fit, score, noise floor).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Protocol, Sequence

import numpy as np

__all__ = ["MIN_TRAIN", "Candidate", "Problem", "jackknife_sd"]

#: fewest training tests the diagnosis runs with (a 1-coefficient law + leave-one-out needs >= 2; 3 gives a spread)
MIN_TRAIN = 3


#: a leave-one-out spread at or under this fraction of the estimate is the refits not moving it, not a certainty
UNRESOLVED = 1e-9


def jackknife_sd(values: np.ndarray) -> np.ndarray:
    """Jack-knife standard deviation per column of leave-one-out estimates ``values`` (n rows, n >= 2):
    √((n−1)/n · Σ(θ_(i) − θ̄)²) (Efron & Stein; units of the estimates).

    A column whose spread is at or under :data:`UNRESOLVED` · |θ̄| (e.g. every refit, polished from the full fit,
    leaves a parameter where the cost is flat in it) gets NaN, "not resolved": a spread of 0 would claim a
    certainty the refits cannot give.  Serialised as None."""
    v = np.asarray(values, float)
    n = v.shape[0]
    mean = v.mean(axis=0)
    sd = np.sqrt((n - 1) / n * np.sum((v - mean) ** 2, axis=0))
    return np.where(sd <= UNRESOLVED * np.abs(mean), np.nan, sd)


@dataclass
class Candidate:
    """A fitted effect set with its scores (NRMSE dimensionless, params in the effect's units)."""

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
    loto_num: dict[str, float] = field(default_factory=dict)
    db_holdout: float = float("nan")
    db_train: float = float("nan")
    #: the damping law the training tests' c_e were tied to in the fit ("" : each test's own c_e)
    tied_law: str = ""

    @property
    def names(self) -> list[str]:
        return [n for n in self.name.split("+") if n] if self.name not in ("", "baseline") else []

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
            "db_over_noise": f(self.db_holdout),
        }


class Problem(Protocol):
    """What the forward selection (:mod:`chainid.gap.core.selection`) needs of a route's diagnosis problem."""

    is_chain: bool

    def applicable(self) -> list[str]:  # pragma: no cover - protocol
        """Library effects that apply to the problem's base model."""

    def fit(self, names: Sequence[str], start: dict[str, float] | None = None,
            polish_only: bool = False) -> Candidate:  # pragma: no cover - protocol
        """Fit an effect set on the training units."""

    def score(self, cand: Candidate, names: Sequence[str], base_hold: float) -> Candidate:  # pragma: no cover
        """Score a fitted candidate (leave-one-out, held out, BIC)."""

    def noise_db(self, ev: dict[str, Any], split: str = "hold") -> tuple[float, float, float]:  # pragma: no cover
        """Mean squared residual per noise cell, its noise floor [N²] and their ratio [dB]."""

    def n_cells(self, split: str = "train") -> int:  # pragma: no cover - protocol
        """Independent noise cells of a split."""
