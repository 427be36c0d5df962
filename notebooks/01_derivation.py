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
# # 1. The link stiffness, derived and checked against the paper
#
# The paper (Eq. 2–16) models one round link as a straight segment AB and a quarter bend BC, finds the
# redundant moment M₁ by Menabrea (∂U/∂M₁ = 0), the elongation by Castigliano, and adds the Hertz
# approach of two crossed links.  `chainid.derive` does each step in SymPy; here we walk through them.
# Units: mm, N, MPa.

# %%
import sympy as sp

from chainid.derive import chain, hertz, link, paper, section
from chainid.derive.symbols import F_k

# %% [markdown]
# ## Internal forces (Eq. 2–3) and the redundant moment (Eq. 6–7)

# %%
link.internal_forces_curved()

# %%
M1 = link.menabrea_moment()
M1

# %% [markdown]
# The paper's first form of Eq. 7 agrees; its definition of k₀ below Eq. 7 is twice M₁/F_k:

# %%
sp.simplify(paper.eq7_M1() - M1), sp.simplify(paper.eq7_k0() / (M1 / F_k))

# %% [markdown]
# ## Elongation (Eq. 9–10): the whole link stretches 2ΔL

# %%
sp.simplify(link.link_elongation() - 2 * link.side_elongation())

# %% [markdown]
# ## Hertz contact (Eq. 11–14)
# Two identical links crossed at 90° have B − A = 0: the contact is circular.

# %%
sp.simplify(hertz.curvature_difference().subs(hertz.link_radii("outer")).subs(hertz.omega_c, sp.pi / 2))

# %%
delta = hertz.approach("outer")
delta, sp.simplify(delta - paper.eq14_delta())

# %% [markdown]
# ## The chain (Eq. 15–16) for the built-in 14×50 chain

# %%
import chainid

print(f"x(11117 N) = {chainid.displacement(11117.0):.4f} mm")
print(f"k_e(2.2 mm) = {chainid.stiffness(2.2):.1f} N/mm")
assert 1.5 < chainid.displacement(11117.0) < 3.0

# %% [markdown]
# The full equation-by-equation table is `chainid verify` (or `chainid.derive.verify.run_checks()`).
