"""Stand-ins for tests: closed-form springs with the interface the code under test uses
(``name``, ``mass_kg``, ``force(x)`` [N], ``stiffness(x)`` [N/mm]; x in mm), and hand-made diagnosis inputs."""
from __future__ import annotations

import math
from types import SimpleNamespace

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


def localise_viscous_excess(C: float = 30.0):
    """Three harmonic tests (ω = 10/20/30 rad/s, A = 0.2/0.3/0.4 mm, x = 2 + A sin ψ, 64 phase bins of 10 samples,
    σ = 1 N) whose baseline residual is a pure viscous excess r = C·cos ψ [N]; returns (tests, the findings of
    ``chainid.gap.harmonic.where.localise`` on them)."""
    from chainid.gap.harmonic.where import localise

    B = 64
    psi = (np.arange(B) + 0.5) * 2 * math.pi / B
    data = [SimpleNamespace(test=f"T{i}", sigma=1.0, counts=np.full(B, 10.0), omega=w, A=A, x0=2.0,
                            Fbar=1000.0 + 500.0 * np.sin(psi) + C * np.cos(psi))
            for i, (w, A) in enumerate([(10.0, 0.2), (20.0, 0.3), (30.0, 0.4)])]
    base = {"res": {d.test: C * np.cos(psi) for d in data}, "per_test": {d.test: 0.1 for d in data},
            "c_e": {d.test: 1.0 for d in data}, "F": {d.test: np.zeros(B) for d in data}}
    prob = SimpleNamespace(data=data, hold=data[:1], train=data[1:], sigma_raw=1.0)
    return data, localise(prob, base)
