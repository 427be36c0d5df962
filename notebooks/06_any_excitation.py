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
# # 6. The gap on any excitation: transient, random and seismic records, and transfer
#
# Notebook 4 diagnosed steady harmonic tests on phase bins.  Machines in service are measured under
# start-ups, load steps, random and seismic motion.  `chainid diagnose` now analyses any record that is
# not a steady harmonic test in the **time domain**:
#
# * the model force F = m·ẍ + F_k(x) + effects + c·ẋ is evaluated on the raw samples, with *causal*
#   memory operators (friction with stick, Dahl hysteresis, play) run forward from a relaxed state;
# * the noise floor comes from the record itself (robust scale of the force's second difference);
# * held out: whole tests (`--holdout IDS`) or the last of K contiguous time blocks (`--holdout-blocks K`);
# * the same forward selection and step rule, scored leave-one-block-out;
# * *where*: residual against x, ẋ, travel since the last reversal and load; its spectrum above the
#   excitation band; ringing while sliding (stick-slip chatter, reported, never named); drift;
# * `--validate OTHER.csv`: the chain fitted on one excitation is scored on another.

# %%
import os
import sys
from pathlib import Path

import numpy as np

import chainid
from chainid.gap import diagnose
from chainid.model.effects import dahl_operator
from chainid.gap.core.summary import summary
from chainid.model import ChainModel

# %% [markdown]
# ## Band-limited random excitation of a chain with hidden hysteresis
# Three records of the built-in chain at x₀ = 2 mm: flat displacement spectrum below 2 Hz, 0.08 mm RMS,
# 200 Hz sampling, 20 s each; hidden Dahl hysteresis F_h = 80 N, x_h = 0.02 mm; viscous c = 30 N·s/mm;
# force noise σ = 5 N.

# %%
model = ChainModel()
rng = np.random.default_rng(0)
fs, n = 200.0, 4000
t = np.arange(n) / fs
records = []
from chainid.records import Record

for i in range(3):
    f = np.arange(1, 41) / 20.0  # 0.05 … 2 Hz
    ph = rng.uniform(0, 2 * np.pi, f.size)
    x = np.sin(2 * np.pi * f[:, None] * t + ph[:, None]).sum(0)
    xd = (2 * np.pi * f[:, None] * np.cos(2 * np.pi * f[:, None] * t + ph[:, None])).sum(0)
    s = 0.08 / x.std()
    x, xd = 2.0 + s * x, s * xd
    F = model.force(x) + 30.0 * xd + dahl_operator(x, 80.0, 0.02, periodic=False)
    records.append(Record(f"r{i}", t, x, F + rng.normal(0, 5.0, n)))
res = diagnose(records, ["r2"], model, quiet=True)
print(summary(res))

# %% [markdown]
# The verdict names the hidden effect with its parameters; the noise σ was estimated from the records
# themselves (`res["noise"]`):

# %%
print(res["noise"]["method"])
for k, v in res["noise"]["tests"].items():
    print(k, f"sigma {v['sigma_N']:.2f} N (simulated 5 N), band {v['band_Hz']:.2f} Hz")

# %% [markdown]
# ## The real friction damper under an earthquake displacement
# `../shared/realdata/friction-damper/brfd_ds2_earthquake_imperialvalley.csv`: two records of a banded
# rotary friction damper (ARTS-Laboratory, "Dataset-Friction-Damper-with-Backlash", CC BY-SA 4.0; see
# SOURCE.md there) driven by the Imperial Valley DBE and MCE structural displacement, 28 698 samples each.
# Linear base model; the last of 4 time blocks of each record held out.  Skipped when the data are absent.

# %%
# the shared data: $CHAINID_SHARED, else `shared` next to the repository of this checkout
SHARED = Path(os.environ.get("CHAINID_SHARED") or Path(chainid.__file__).resolve().parents[2] / "shared")
D = SHARED / "realdata" / "friction-damper"
EQ = D / "brfd_ds2_earthquake_imperialvalley.csv"
if EQ.exists():
    from chainid.records import read_records

    eq = read_records(EQ, validate=False)
    r_eq = diagnose(eq, [], None, holdout_blocks=4, quiet=True)
    print(summary(r_eq))
else:
    print("real data not found:", EQ)

# %% [markdown]
# ## Transfer: the harmonic tests' chain on the earthquake records
# The heavy part (the harmonic diagnosis of 10 real tests, ~40 s) runs when `CHAINID_NOTEBOOK_FULL=1`;
# the numbers are in the README ("The gap on any excitation") with the command that produced them.

# %%
HARM = D / "brfd_ds2_tension30lb.csv"
if HARM.exists() and EQ.exists() and os.environ.get("CHAINID_NOTEBOOK_FULL") == "1":
    harm = read_records(HARM, validate=False)
    r_h = diagnose(harm, ["f0.5_a1.0"], None, quiet=True, validate=eq)
    print(r_h["verdict"], "→", r_h["transfer"]["verdict_text"])
    for row in r_h["transfer"]["tests"]:
        print(row)
else:
    print("set CHAINID_NOTEBOOK_FULL=1 to run the harmonic → earthquake transfer")
