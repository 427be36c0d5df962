"""chainid — axial dynamics of round link chains.

Stiffness from the SymPy derivation (``chainid verify``), fast numba kernels
(``chainid.generated``), damping identification and sim-to-real gap
diagnosis.  Units: mm, N, s, MPa, kg.

Stable API::

    chainid.force(x, chain=None)         # F_k [N] at elongation x [mm]
    chainid.displacement(F, chain=None)  # x [mm] at tension F [N]
    chainid.stiffness(x, chain=None)     # tangent k_e [N/mm]
"""
from .kernels import displacement, force, stiffness
from .spec import ChainSpec, default_chain, load_chain

__version__ = "0.1.0"
__all__ = ["ChainSpec", "default_chain", "load_chain", "force", "displacement", "stiffness", "__version__"]
