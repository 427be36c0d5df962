"""The chain itself: its geometry and material (:class:`ChainSpec`, chain TOML files) and the standard sizes
(:mod:`.presets`: DIN 22252, studless and stud-link mooring chain). Units mm, MPa, kg/m.
"""
from __future__ import annotations

from chainid.infra.lazy import exports

#: Public name -> module of this package that defines it (imported on first use, so that importing the
#: package stays cheap).
_LAZY = {
    "FAMILIES": "catalogue",
    "is_preset_name": "catalogue",
    "canonical_grade": "catalogue",
    "suggest_preset": "catalogue",
    "Preset": "presets",
    "resolve": "presets",
    "listed": "presets",
    "match": "presets",
    "ChainSpec": "spec",
    "default_chain": "spec",
    "load_chain": "spec",
    "PAPER_CHAIN": "spec",
    "steel_mass_per_m": "spec",
}

__all__ = sorted(_LAZY)
__getattr__, __dir__ = exports(__name__, _LAZY, globals())
