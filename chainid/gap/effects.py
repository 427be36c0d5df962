"""Deprecated import path: ``chainid.gap.effects`` moved to :mod:`chainid.model.effects` (the effects are model
parts, not diagnosis parts); this re-export goes in the next release."""
import warnings as _warnings

from chainid.model.effects import *  # noqa: F401,F403
from chainid.model.effects import __all__  # noqa: F401

_warnings.warn("chainid.gap.effects is deprecated; import chainid.model.effects instead", DeprecationWarning,
               stacklevel=2)
