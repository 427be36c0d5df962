"""One test's samples: the :class:`Record` every reader returns and every analysis takes.

Units: t [s], x [mm] (elongation), F [N] (tension positive).  A record may carry extra per-sample channels
(pressure, coil current, ... in the units the reader gave them) and per-test covariates (operating conditions:
set pressure [bar], coil current [A], pretension [N], temperature, ...).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:  # pragma: no cover
    from chainid.signal.harmonic import HarmonicEstimate

__all__ = ["Record"]


@dataclass
class Record:
    """One test: samples of time, elongation and force.

    Attributes
    ----------
    test : str
        Test id.
    t : ndarray
        Time [s], strictly increasing.
    x : ndarray
        Elongation [mm].
    F : ndarray
        Axial force (tension positive) [N].
    estimate : HarmonicEstimate or None
        Harmonic estimate and steady window found when the record was
        validated by :func:`read_records` (reused by :func:`analyse_record`).
    channels : dict
        Extra per-sample channels, name -> 1-D float array as long as ``t`` (units as read: see
        :class:`chainid.records.spec.ReaderSpec`); default none.
    covariates : dict
        Operating conditions of the test, name -> float (the unit is part of the name's meaning, e.g.
        ``p_bar``, ``I_A``); default none.
    """

    test: str
    t: np.ndarray
    x: np.ndarray
    F: np.ndarray
    estimate: "HarmonicEstimate | None" = field(default=None, repr=False, compare=False)
    channels: dict[str, np.ndarray] = field(default_factory=dict, repr=False, compare=False)
    covariates: dict[str, float] = field(default_factory=dict, compare=False)

    def __post_init__(self) -> None:
        self.test = str(self.test)
        self.t = np.asarray(self.t, dtype=float)
        self.x = np.asarray(self.x, dtype=float)
        self.F = np.asarray(self.F, dtype=float)
        if not (self.t.ndim == self.x.ndim == self.F.ndim == 1):
            raise ValueError(f"test {self.test!r}: t, x and F must be one-dimensional arrays")
        if not (self.t.size == self.x.size == self.F.size):
            raise ValueError(
                f"test {self.test!r}: t, x and F must have the same length "
                f"(got {self.t.size}, {self.x.size}, {self.F.size})"
            )
        chans = {}
        for name, a in dict(self.channels or {}).items():
            v = np.asarray(a, dtype=float)
            if v.shape != self.t.shape:
                raise ValueError(f"test {self.test!r}: channel {name!r} has shape {v.shape}; expected "
                                 f"{self.t.shape} like t")
            chans[str(name)] = v
        self.channels = chans
        covs = {}
        for name, v in dict(self.covariates or {}).items():
            try:
                f = float(v)
            except (TypeError, ValueError):
                raise ValueError(f"test {self.test!r}: covariate {name!r} = {v!r} is not a number") from None
            covs[str(name)] = f
        self.covariates = covs

    def window(self, t_start: float, t_end: float) -> "Record":
        """The samples with ``t_start <= t < t_end`` [s] as a new :class:`Record`."""
        m = (self.t >= t_start) & (self.t < t_end)
        return Record(self.test, self.t[m], self.x[m], self.F[m], channels={k: v[m] for k, v in self.channels.items()},
                      covariates=dict(self.covariates))
