"""Test records: the :class:`Record` (t s, x mm, F N), reading and writing them (:mod:`.files`), their
validation and per-test harmonic analysis (:mod:`.validate`), the paper's Table 1 (:mod:`.table1`) and synthetic
records from a model (:mod:`.simulate`; non-harmonic displacement programs — random, sweep, start-up
with load steps, earthquake-like — in :mod:`.excitation`); records as rigs write them: a :class:`ReaderSpec` (:mod:`.spec`,
columns, units by pint in :mod:`.units`, layout), :func:`read_any` (:mod:`.reader`; text in :mod:`.textcanon`
and :mod:`.textread`, other formats in :mod:`.formats`, the mapping in :mod:`.table`), the fast writer
(:mod:`.writer`) and the unit-slip warnings (:mod:`.plausible`); DAQ text as written (:mod:`.textlayout`: header
blocks, metadata; ragged rows), computed columns (:mod:`.derive`), segments and offsets (:mod:`.segments`),
covariates (:mod:`.covariates`), test selection (:mod:`.select`), bounded user patterns (:mod:`.patterns`).
"""
from __future__ import annotations

from chainid.infra.lazy import exports

#: Public name -> module of this package that defines it (imported on first use, so that importing the
#: package stays cheap).
_LAZY = {
    "Record": "files",
    "HarmonicEstimate": "files",
    "SteadyWindow": "files",
    "read_records": "files",
    "write_records": "files",
    "validate_record": "files",
    "estimate_harmonic": "files",
    "select_steady": "files",
    "analyse_record": "files",
    "try_analyse": "files",
    "check_data": "files",
    "read_side_file": "files",
    "write_side_file": "files",
    "REQUIRED_COLUMNS": "files",
    "TestSpec": "simulate",
    "ForceHook": "simulate",
    "PAPER_RAMP_RATE": "simulate",
    "OMEGA_COLUMN_TO_RAD_S": "simulate",
    "paper_plan": "simulate",
    "read_plan": "simulate",
    "write_plan": "simulate",
    "model_force": "simulate",
    "simulate_test": "simulate",
    "DEFAULT_MAX_MEMORY": "simulate",
    "n_samples": "simulate",
    "estimate_memory": "simulate",
    "load_table1": "table1",
    "ReaderSpec": "spec",
    "load_profile": "spec",
    "spec_from_options": "spec",
    "read_any": "reader",
    "expand_paths": "reader",
    "write_canonical": "writer",
    "read_canonical_csv": "textcanon",
    "read_csv_strict": "textcanon",
    "plausibility_warnings": "plausible",
    "not_a_chain": "plausible",
    "ReadLog": "reader",
    "read_covariates": "covariates",
    "write_covariates": "covariates",
    "covariates_path": "covariates",
    "Motion": "excitation",
    "band_random": "excitation",
    "sweep": "excitation",
    "startup_steps": "excitation",
    "earthquake": "excitation",
    "with_envelope": "excitation",
    "simulate_motion": "excitation",
}

__all__ = sorted(_LAZY)
__getattr__, __dir__ = exports(__name__, _LAZY, globals())
