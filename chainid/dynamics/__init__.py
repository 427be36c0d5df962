"""Multi-mass chain dynamics on the generated kernels (conveyor start-up, polygon effect, load steps).

Units mm, N, s, kg throughout.  See :mod:`.model` (the lumped chain, springs, damping), :mod:`.drives`
(drive laws), :mod:`.integrators` (explicit / implicit numba integration), :mod:`.modes` (natural frequencies
about the pre-tensioned state), :mod:`.energy`, :mod:`.sweeps` (parameter sweeps on chainid.infra.parallel) and
:mod:`.plots`.
"""
from chainid.dynamics.drives import DRIVE_LAWS, Drive, drive_motion
from chainid.dynamics.simulation import SCHEMES, SimResult, SimulationError, simulate, stable_step
from chainid.dynamics.model import FAR_ENDS, LUMPINGS, ChainLine, LoadStep, viscous_equivalent

__all__ = ["ChainLine", "LoadStep", "Drive", "DRIVE_LAWS", "FAR_ENDS", "LUMPINGS", "SCHEMES", "SimResult",
           "SimulationError", "simulate", "stable_step", "viscous_equivalent", "drive_motion"]
