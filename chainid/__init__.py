"""chainid — axial dynamics of round link chains.

Stiffness from the SymPy derivation (``chainid verify``), fast numba kernels
(``chainid.generated``), damping identification and sim-to-real gap
diagnosis.  Units: mm, N, s, MPa, kg.

Stable API::

    chainid.force(x, chain=None)         # F_k [N] at elongation x [mm]
    chainid.displacement(F, chain=None)  # x [mm] at tension F [N]
    chainid.stiffness(x, chain=None)     # tangent k_e [N/mm]
"""
from pathlib import Path as _Path

# In a source checkout (the repository root on sys.path, e.g. `python -c` run there), derive/ and
# generated/ sit beside chainid/ rather than inside it; let chainid.derive and chainid.generated
# resolve to them.  Installed copies (pip install .) have them inside the package already.
_root = _Path(__file__).resolve().parent.parent
if not (_Path(__file__).resolve().parent / "generated").is_dir() and (_root / "generated" / "__init__.py").is_file():
    __path__.append(str(_root))  # type: ignore[name-defined]  # noqa: F821

from chainid.model.kernels import displacement, force, stiffness  # noqa: E402
from chainid.chain.spec import ChainSpec, default_chain, load_chain  # noqa: E402

__version__ = "0.1.0"
__all__ = ["ChainSpec", "default_chain", "load_chain", "force", "displacement", "stiffness", "__version__"]
