"""Stand-in models for tests: closed-form springs with the interface the code under test uses
(``name``, ``mass_kg``, ``force(x)`` [N], ``stiffness(x)`` [N/mm]; x in mm)."""
from __future__ import annotations

import numpy as np


class LinearSpring:
    """F = k·x [N] with a constant tangent k [N/mm] and the paper chain's mass 3.2 kg."""

    name = "stand-in linear"
    mass_kg = 3.2

    def __init__(self, k: float = 10000.0):
        self.k = float(k)

    def force(self, x):
        return self.k * np.asarray(x, float)

    def stiffness(self, x):
        return np.full(np.shape(x), self.k)
