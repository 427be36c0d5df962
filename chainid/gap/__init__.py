"""Sim-to-real gap diagnosis: where the model misses, which unmodelled effects cause it (in order), how much each
shrinks the held-out error, and what is left.

Architecture (each sub-package uses only those below it; checked by the import-linter contract "chainid.gap floors"):

* :mod:`.benchmark` — ``chainid benchmark-gap``, the blind benchmark on simulated data with withheld effects;
* :mod:`.diagnose` — the entry point: checks, preparation, and the route each record takes;
* :mod:`.transfer`, :mod:`.modelio`, :mod:`.plots` — run a diagnosis' model on any record: another excitation,
  the model file and ``predict``, the figures;
* :mod:`.timedomain` — the time-domain route (any excitation; also mixed sets with harmonic tests);
* :mod:`.harmonic` — the harmonic route (steady tests folded into phase bins, c_e(ω, A) per test);
* :mod:`.core` — shared by both routes: candidates, forward selection and its step rule, verdict, noise and
  kinematics, stationarity, interpretation, summary.

Public API
----------
diagnose(records, holdout, model=None, ...) -> dict   (JSON contract of ``chainid diagnose``; any excitation: records
                                                      that are not steady harmonic tests go to the time-domain route,
                                                      ``holdout_blocks=K``, ``validate=other_records`` → ``transfer``)
parse_effect(spec, model) -> force_fn                  (``chainid simulate --effect NAME[:p=v,...]``)
EFFECT_NAMES                                           (the effect library, :mod:`chainid.model.effects`)
core.summary.summary(result) -> str, core.summary.write_json(result, path)
plots.make_plots(result, outdir) -> list of paths
benchmark.grid.run_benchmark(small=False, json_path=None)   (``chainid benchmark-gap``)
"""

from chainid.gap.diagnose import diagnose
from chainid.model.effects import EFFECT_NAMES, parse_effect

__all__ = ["diagnose", "parse_effect", "EFFECT_NAMES"]
