"""Compatibility names: the selection's parts now live in :mod:`.prepare`, :mod:`.laws`, :mod:`.problem` and
:mod:`.forward` (one job per module)."""

from .laws import ALT_LAWS, LAWS  # noqa: F401
from .prepare import TestData, prepare_test  # noqa: F401
from .problem import MIN_TRAIN, Candidate, Problem, damping_separable  # noqa: F401
