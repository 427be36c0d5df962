"""Deprecated import path: ``chainid.parallel`` moved to :mod:`chainid.infra.parallel`; this re-export goes in the next release."""
import warnings as _warnings

from chainid.infra.parallel import *  # noqa: F401,F403
from chainid.infra.parallel import __all__  # noqa: F401

_warnings.warn("chainid.parallel is deprecated; import chainid.infra.parallel instead", DeprecationWarning, stacklevel=2)
