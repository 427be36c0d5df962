"""Deprecated import path: ``chainid.simulate`` moved to :mod:`chainid.records.simulate`; this re-export goes in the next release."""
import warnings as _warnings

from chainid.records.simulate import *  # noqa: F401,F403
from chainid.records.simulate import __all__  # noqa: F401

_warnings.warn("chainid.simulate is deprecated; import chainid.records.simulate instead", DeprecationWarning, stacklevel=2)
