"""The model of the paper's Eq. 1, F = m·ẍ + F_k(x) + c_e(ω, A)·ẋ, and what extends it: the generated kernels
behind a numpy API (:mod:`.kernels`), base models (chain, linear spring; :mod:`.base`), the damping laws c_e(ω, A)
(:mod:`.laws`), the Eq. 1 prediction (:mod:`.predict`), the effect library (:mod:`.effects`), the model against
catalogue practice (:mod:`.practice`), the causal state operators (:mod:`.operators`), time-domain damping
(:mod:`.timedamping`), the augmented model (:mod:`.augmented`), its file (:mod:`.modelfile`) with its typed schema
(:mod:`.schema`) and the physical ranges of its numbers (:mod:`.ranges`), and the rule for a negative dashpot
(:mod:`.passivity`). Units mm, N, s, MPa, kg.
"""
from __future__ import annotations

from chainid.infra.lazy import exports

#: Public name -> module of this package that defines it (imported on first use, so that importing the
#: package stays cheap).
_LAZY = {
    "StiffnessModel": "base",
    "ChainModel": "base",
    "LinearModel": "base",
    "model_for": "base",
    "EFFECT_NAMES": "effects",
    "STIFFNESS_SIDE": "effects",
    "Effect": "effects",
    "make_effect": "effects",
    "parse_effect": "effects",
    "parse_spec": "effects",
    "modify_model": "effects",
    "play_operator": "effects",
    "dahl_operator": "effects",
    "coulomb_sign": "effects",
    "stick_slip": "effects",
    "series_compliance_force": "effects",
    "undamped_force": "effects",
    "play": "operators",
    "jenkins": "operators",
    "dahl": "operators",
    "iwan": "operators",
    "iwan_for_loss": "operators",
    "play_step": "operators",
    "jenkins_step": "operators",
    "dahl_step": "operators",
    "iwan_step": "operators",
    "AugmentedModel": "augmented",
    "Damping": "timedamping",
    "dominant": "timedamping",
    "load_model": "modelfile",
    "save_model": "modelfile",
    "check_model_dict": "schema",
    "ModelFileWarning": "schema",
    "EFFECT_RANGES": "ranges",
    "Range": "ranges",
    "range_table": "ranges",
    "OperatingPoint": "passivity",
    "check_passive": "passivity",
    "VARIANTS": "kernels",
    "variant_module": "kernels",
    "coefficients": "kernels",
    "force": "kernels",
    "displacement": "kernels",
    "stiffness": "kernels",
    "damping_residual": "kernels",
    "resolve_chain": "kernels",
    "as_real_array": "kernels",
    "DampingLaw": "laws",
    "PolynomialLaw": "laws",
    "ViscousLaw": "laws",
    "HystereticLaw": "laws",
    "CoulombLaw": "laws",
    "CombinedLaw": "laws",
    "LawFit": "laws",
    "fit_law": "laws",
    "rank_laws": "laws",
    "default_laws": "laws",
    "law_from_dict": "laws",
    "leverages": "laws",
    "MIN_TESTS": "laws",
    "PAPER_TEST_LOAD_N": "practice",
    "FIRST_YIELD_FACTOR": "practice",
    "catalogue_ea_N": "practice",
    "grade": "practice",
    "breaking_load_N": "practice",
    "proof_load_N": "practice",
    "working_load_N": "practice",
    "sigma_max_MPa": "practice",
    "contact_limit_load_N": "practice",
    "model_ea_N": "practice",
    "tangent_ea_N": "practice",
    "chain_practice": "practice",
    "comparison_table": "practice",
    "explain_ratio": "practice",
    "load_warnings": "practice",
    "practice_section": "practice",
    "format_practice": "practice",
    "inertia_force_N": "predict",
    "predict_force": "predict",
}

__all__ = sorted(_LAZY)
__getattr__, __dir__ = exports(__name__, _LAZY, globals())
