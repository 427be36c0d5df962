"""One test's samples: the :class:`Record` every reader returns and every analysis takes.

Units: t [s], x [mm] (elongation), F [N] (tension positive).
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
    """

    test: str
    t: np.ndarray
    x: np.ndarray
    F: np.ndarray
    estimate: "HarmonicEstimate | None" = field(default=None, repr=False, compare=False)

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

    def window(self, t_start: float, t_end: float) -> "Record":
        """The samples with ``t_start <= t < t_end`` [s] as a new :class:`Record`."""
        m = (self.t >= t_start) & (self.t < t_end)
        return Record(self.test, self.t[m], self.x[m], self.F[m])
