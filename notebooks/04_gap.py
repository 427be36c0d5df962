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
# # 4. Diagnosing the sim-to-real gap: where, which effect, how much
#
# The paper's model is F = m·ẍ + F_k(x) + c_e(ω, A)·ẋ.  Real chains and test rigs add effects it
# does not have: sliding friction at the link contacts, hysteresis, play, a compliant machine, a lag
# between the force and displacement channels…  `chainid.gap.diagnose` answers three questions:
#
# 1. **Where** does the baseline miss?  Per test, per harmonic of the residual, loading vs unloading
#    branch, over the (x, ẋ) plane, and in how the dissipated energy scales with A and ω.
# 2. **Which** unmodelled effects explain it, in order?  Forward selection: every effect of a named
#    library is fitted on top of what is already explained (all parameters refitted, the damping law
#    re-identified), scored leave-one-test-out on the training tests, and kept while it helps
#    significantly and the residual is above the noise floor.
# 3. **How much** does the held-out error shrink at each step, and is what is left stationary?
#
# Here we hide an effect in simulated records of the built-in chain, diagnose it blind, and then look
# at a real measured friction damper.

# %%
from pathlib import Path

import numpy as np

import chainid
from chainid.gap import diagnose, parse_effect
from chainid.model.effects import EFFECT_NAMES
from chainid.gap.core.summary import summary
from chainid.model.laws import PolynomialLaw
from chainid.model.base import ChainModel
from chainid.records.simulate import grid_plan, simulate

print("effect library:", ", ".join(EFFECT_NAMES))

# %% [markdown]
# ## A test series with a hidden effect
# Eleven harmonic tests around the paper's operating point (x₀ ≈ 2 mm), ω from 1 to 4 rad/s, A from 0.1
# to 0.3 mm, force noise σ = 20 N.  The hidden effect is Dahl-type hysteresis (a rate-independent
# friction force of up to F_h = 300 N that builds up over x_h = 0.03 mm after each reversal).

# %%
model = ChainModel()  # built-in 14x50 chain, n = 16 links
law = PolynomialLaw([0.5, 1.0, 100.0, 20.0, 50.0])  # c_e(ω, A) of Eq. 21 [N·s/mm], ω rad/s, A mm
# ω × A grid at x₀ = 2 mm, then two off-grid tests (ω rad/s, x₀ mm, A mm); ids "1" … "11"
plan = grid_plan((1.0, 2.0, 4.0), (0.1, 0.2, 0.3), 2.0, extra=[(3.0, 2.2, 0.15), (1.5, 1.8, 0.25)])
hidden = "hysteresis:F_h=300,x_h=0.03"
records = simulate(plan, model, law, n_cycles=8, samples_per_cycle=128, noise_F=20.0, seed=1,
                   force_fn=parse_effect(hidden, model))
print(len(records), "tests,", sum(r.t.size for r in records), "samples")

# %% [markdown]
# Diagnose blind: tests 3, 7 and 11 are held out whole (samples within a test are correlated, so
# random samples would flatter the model).

# %%
result = diagnose(records, ["3", "7", "11"], model, max_combo=1)
print(summary(result))

# %%
best = result["ranking"][0]
print("verdict:", result["verdict"], "| hidden:", hidden)
print("recovered:", {k: round(v, 4) for k, v in best["params"].items()})
assert result["verdict"] == "hysteresis"
assert abs(best["params"]["hysteresis.F_h"] / 300.0 - 1) < 0.15

# %% [markdown]
# The figures: measured / baseline / augmented loops of the held-out tests, the baseline residual
# along the cycle, the residual over (x, ẋ) (two values at one x = memory), and the per-test error
# before and after over (ω, A).

# %%
from IPython.display import Image, display

from chainid.gap.plots import make_plots

for p in make_plots(result, Path("gap_figures")):
    display(Image(filename=str(p)))

# %% [markdown]
# ## Compound causes: a base model that is itself off, plus friction
# Real chains are rarely what the derivation says: the model's large-load stiffness is about 0.75× the
# catalogue EA of studless chain (`chainid chains --compare`).  Here the "real" chain is 21 % softer in its
# linear (bar) term than the model (EA × 0.79), *and* it has Coulomb friction F_c = 150 N.  Scored against
# the uncorrected model, friction alone shrinks nothing (the stiffness error swamps it); the diagnosis
# therefore selects forward, each step fitted on top of what is already explained, and stops at the
# noise floor.  The result is the explanation chain — a waterfall.

# %%
real_chain = ChainModel(ea_scale=0.79)
compound = simulate(plan, real_chain, law, n_cycles=8, samples_per_cycle=128, noise_F=20.0, seed=1,
                    force_fn=parse_effect("friction:F_c=150", real_chain))
chain_result = diagnose(compound, ["3", "7", "11"], model)
print(chain_result["chain_text"])
for step in chain_result["steps"]:
    print(f"{step['effect']:>16}: held-out NRMSE {step['nrmse_holdout']:.4f}, {step['db_over_noise']:5.1f} dB over noise")
assert chain_result["verdict"] == "stiffness_level+friction"
assert abs(chain_result["steps"][-1]["params"]["friction.F_c"] / 150.0 - 1) < 0.10

# %%
from chainid.gap.core.plot_steps import waterfall_figure

waterfall_figure(chain_result)

# %% [markdown]
# ## A control: nothing hidden
# With no effect the held-out residual is at the noise floor and the verdict is `none`:
# the diagnosis does not invent an effect.

# %%
clean = simulate(plan, model, law, n_cycles=8, samples_per_cycle=128, noise_F=20.0, seed=2)
control = diagnose(clean, ["3", "7", "11"], model, max_combo=1, uncertainty=False)
print("verdict:", control["verdict"], "| baseline held-out NRMSE", round(control["baseline"]["nrmse_holdout"], 5))
assert control["verdict"] == "none"

# %% [markdown]
# ## Real measured loops: a friction damper with backlash
# `../shared/realdata/friction-damper/` (CC BY-SA 4.0, see its SOURCE.md) holds measured loops of a
# friction damper.  It is not a chain, so the baseline is a linear spring (`--model linear`, i.e.
# `model=None`) plus the identified damping law.  The data are not shipped with chainid; this cell
# runs only in a source checkout next to `../shared`.  It ranks the single effects (`max_combo=1`, about
# 10 s: 150 000 samples at 1 kHz); the whole chain, a pair on these loops, is `benchmarks/real_devices.py`'s
# (`benchmarks/RESULTS_real.md`), a few minutes.

# %%
real = Path(chainid.__file__).resolve().parents[2] / "shared" / "realdata" / "friction-damper" / "brfd_ds2_tension30lb.csv"
if real.is_file():
    from chainid.records.files import read_records

    recs = read_records(real, allow_compression=True)
    res = diagnose(recs, ["f0.5_a1.0", "f1.0_a0.5", "f0.25_a1.5"], None, uncertainty=False, max_combo=1)
    rank = {c["effect"]: c for c in res["ranking"]}
    print("best single effect:", res["verdict"], "| held-out NRMSE", round(res["baseline"]["nrmse_holdout"], 3), "->",
          round(res["ranking"][0]["nrmse_holdout"], 3))
    print("friction alone shrinks the held-out gap by", f"{100 * rank['friction']['shrinkage']:.0f} %")
else:
    print("real data not present:", real)
