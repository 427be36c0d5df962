"""Array-level signal analysis of one sampled channel pair: the harmonic fit x = x0 + A sin(ωt + θ)
(:mod:`.harmonic`) and the steady-cycle window of a harmonic test (:mod:`.steady`). Units s, mm, rad/s.
"""
from __future__ import annotations

from chainid.infra.lazy import exports

#: Public name -> module of this package that defines it (imported on first use, so that importing the
#: package stays cheap).
_LAZY = {
    "HarmonicEstimate": "harmonic",
    "estimate_harmonic": "harmonic",
    "SteadyWindow": "steady",
    "select_steady": "steady",
    "steady_tolerance": "steady",
    "TOL_FLOOR": "steady",
    "TOL_MAX": "steady",
    "MIN_KEPT": "steady",
}

__all__ = sorted(_LAZY)
__getattr__, __dir__ = exports(__name__, _LAZY, globals())
