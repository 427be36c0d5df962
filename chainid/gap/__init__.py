"""Sim-to-real gap diagnosis (issue 4): where the model misses, which unmodelled effect, how much it shrinks.

Public API
----------
diagnose(records, holdout, model=None, ...) -> dict   (JSON contract of ``chainid diagnose``)
effects.parse_effect(spec, model) -> force_fn          (``chainid simulate --effect NAME[:p=v,...]``)
effects.EFFECT_NAMES, effects.make_effect(name, ...)    (the effect library)
report.summary(result) -> str, report.to_json(result), report.write_json(result, path)
plots.make_plots(result, outdir) -> list of paths
benchmark.run_benchmark(small=False, json_path=None)   (``chainid benchmark-gap``)
"""

from chainid.gap.diagnose import diagnose
from chainid.model.effects import EFFECT_NAMES, parse_effect

__all__ = ["diagnose", "parse_effect", "EFFECT_NAMES"]
