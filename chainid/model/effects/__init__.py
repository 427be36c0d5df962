"""The effect library: named, physically parameterised, bounded additions to the base model (paper Eq. 1).

* :mod:`.library` — every effect declared once: parameters, units, physical ranges, fit bounds, kind;
* :mod:`.forms` — each effect's force as unit columns times amplitudes, and the memory operators it uses;
* :mod:`.compose` — several effects on one base model (stiffness side first);
* :mod:`.hooks` — ``chainid simulate --effect NAME[:p=v,...]``.

Units: x mm, ẋ mm/s, ẍ mm/s², F N, t s, ω rad/s, m kg (m·ẍ·1e-3 = N).
"""

from chainid.model.effects.compose import changed_model, effect_force, modify_model, undamped_force
from chainid.model.effects.forms import (bouc_wen_operator, columns, coulomb_sign, dahl_operator,
                                         is_chain, play_operator, series_compliance_force, sliding_sign,
                                         stick_slip)
from chainid.model.effects.hooks import check_params, compose_hooks, parse_effect, parse_spec
from chainid.model.effects.library import (DEFAULTS, EFFECT_NAMES, SPECS, STIFFNESS_SIDE, Effect, EffectSpec, Param,
                                           Scales, applies_to, identifiable, make_effect, pinned,
                                           valid_range)

__all__ = ["EFFECT_NAMES", "STIFFNESS_SIDE", "DEFAULTS", "SPECS", "Effect", "EffectSpec", "Param", "Scales",
           "make_effect", "valid_range", "applies_to", "pinned", "identifiable", "parse_effect", "parse_spec", "check_params", "compose_hooks",
           "modify_model",
           "undamped_force", "changed_model", "columns", "effect_force", "play_operator", "dahl_operator", "bouc_wen_operator",
           "coulomb_sign", "sliding_sign", "stick_slip", "series_compliance_force", "is_chain"]
