# ---
# jupyter:
#   jupytext:
#     text_representation:
#       extension: .py
#       format_name: percent
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% [markdown]
# # 2. Changing a model assumption and regenerating the kernels
#
# Every model assumption is an `Assumptions` object in `derive/chain.py`; each one becomes its own
# generated module `generated/stiffness_<name>.py`.  The normal workflow is: add or change an entry of
# `VARIANTS`, run `chainid generate`, commit the new `generated/` file (`chainid generate --check`
# fails until you do).  Here we print a new variant into a scratch folder instead of the package.

# %%
import importlib.util
import shutil
import sys
import tempfile
from pathlib import Path

import sympy as sp

from chainid.chain.spec import default_chain
from chainid.model import kernels
from chainid.derive import chain, emit

# %%
# A new assumption: contact on the inner bend and a shear form factor of 32/27 (a thin-walled estimate)
mine = chain.Assumptions("my_variant", contact="inner", shear_factor=sp.Rational(32, 27),
                         description="inner bend contact, shear factor 32/27")
src = emit.module_source(mine)
print("\n".join(src.splitlines()[:6]))

# %%
folder = Path(tempfile.mkdtemp(prefix="chainid_nb02_"))
path = folder / "stiffness_my_variant.py"
path.write_text(src)
spec = importlib.util.spec_from_file_location("stiffness_my_variant", path)
mod = importlib.util.module_from_spec(spec)
sys.modules["stiffness_my_variant"] = mod
spec.loader.exec_module(mod)

# %%
c = default_chain()
coef_new = mod.coefficients(c.d, c.pitch, c.width, float(c.n), c.E, c.nu)
coef_paper = kernels.coefficients(c)
k_new = mod.stiffness(2.2, *coef_new)
k_paper = kernels.stiffness(2.2, c)
print(f"k_e(2.2 mm): paper {k_paper:.1f} N/mm, my_variant {k_new:.1f} N/mm ({100 * (k_new / k_paper - 1):+.1f} %)")
assert k_new > k_paper  # the inner-bend contact is more conformal, hence stiffer

# %% [markdown]
# The shipped variants and their effect on k_e at 2.2 mm:

# %%
for v in kernels.VARIANTS:
    print(f"{v:>18}: k_e(2.2) = {kernels.stiffness(2.2, c, v):8.1f} N/mm")

# %% [markdown]
# The scratch folder holding the emitted variant is removed (the module stays loaded for this session).

# %%
shutil.rmtree(folder, ignore_errors=True)
