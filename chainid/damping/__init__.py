"""Damping identification from harmonic records (the paper's Eq. 21–28): per-test c_e and energy
(:mod:`.identify`), the audit of the paper's Table 1 and Eq. 26–28 (:mod:`.audit`) and of Eq. 28 on the user's records
(:mod:`.audit_data`) and their figures
(:mod:`.plots`). Units mm, N, s, rad/s.
"""
from __future__ import annotations

from chainid.infra.lazy import exports

#: Public name -> module of this package that defines it (imported on first use, so that importing the
#: package stays cheap).
_LAZY = {
    "load_table1": "audit",
    "EQ28_PAPER": "audit",
    "EQ26": "audit",
    "EQ27": "audit",
    "VALIDATION": "audit",
    "OMEGA_COLUMN_TO_RAD_S": "audit",
    "eq28": "audit",
    "format_audit": "audit",
    "sig_round": "audit",
    "audit_records": "audit_data",
    "audit_results": "audit_data",
    "format_audit_data": "audit_data",
    "HarmonicFit": "identify",
    "fit_harmonic": "identify",
    "TestResult": "identify",
    "loop_energy": "identify",
    "identify_test": "identify",
    "identify_records": "identify",
    "Identification": "identify",
    "plot_loop": "plots",
    "plot_damping_surface": "plots",
    "plot_all": "plots",
    "plot_names": "plots",
}

__all__ = sorted(_LAZY)
__getattr__, __dir__ = exports(__name__, _LAZY, globals())
