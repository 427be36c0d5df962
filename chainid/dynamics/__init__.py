"""Multi-mass chain dynamics on the generated kernels (conveyor start-up, polygon effect, load steps).

Units mm, N, s, kg throughout.  See :mod:`.model` (the lumped chain, springs, damping), :mod:`.drives`
(drive laws), :mod:`.integrators` (explicit / implicit numba integration), :mod:`.modes` (natural frequencies
about the pre-tensioned state), :mod:`.energy`, :mod:`.sweeps` (parameter sweeps on chainid.parallel) and
:mod:`.plots`.
"""
from .drives import DRIVE_LAWS, Drive, drive_motion
from .simulation import SCHEMES, SimResult, SimulationError, simulate, stable_step
from .model import FAR_ENDS, LUMPINGS, ChainLine, LoadStep, viscous_equivalent

__all__ = ["ChainLine", "LoadStep", "Drive", "DRIVE_LAWS", "FAR_ENDS", "LUMPINGS", "SCHEMES", "SimResult",
           "SimulationError", "simulate", "stable_step", "viscous_equivalent", "drive_motion"]
