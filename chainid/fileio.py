"""Deprecated import path: ``chainid.fileio`` moved to :mod:`chainid.infra.fileio`; this re-export goes in the next release."""
import warnings as _warnings

from chainid.infra.fileio import *  # noqa: F401,F403
from chainid.infra.fileio import __all__  # noqa: F401

_warnings.warn("chainid.fileio is deprecated; import chainid.infra.fileio instead", DeprecationWarning, stacklevel=2)
