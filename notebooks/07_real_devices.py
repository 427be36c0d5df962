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
# # 7. Real devices nobody here built: a pneumatic seal at four pressures
#
# The diagnosis is built on chains, but a resonant shaker, a seal or an MR damper is the same question: a base
# model (here the linear device m·ẍ + c·ẋ + k·x, its mass fitted), the force it misses, and which effect of the
# library closes the gap **on tests it was not fitted on**.  Real hardware differs from simulators:
#
# * the rig's files are not `test,t,x,F`: a reader profile (`examples/readers/*.toml`) maps them, and the operating
#   condition of each test (supply pressure, coil current, tension) becomes a **covariate**;
# * an effect's amplitude may follow the operating condition: `hysteresis.F_h@p_bar` is the hysteresis force
#   growing linearly with the pressure, one law for all the tests;
# * what is left is stated against the records' own noise floor, and a model-free learner says how much of it
#   any model of the state could still explain.
#
# The data: the pneumatic-seal set of `../shared/realdata/pneumatic-seal` (see its SOURCE.md for the origin and
# the licence); set `CHAINID_SHARED` when it lives elsewhere.  This notebook diagnoses one seal (NAP310) at 1, 3,
# 5 and 7 bar, the 5 bar test held out.  `python benchmarks/real_devices.py` runs every shared set (three seals,
# the MR damper over five coil currents, the friction damper's loops and its earthquake record) and tabulates the
# verdicts.

# %%
import json
import os
import shutil
import tempfile
from pathlib import Path

import chainid
from chainid.cli import main

# the repository (its example reader profiles): $CHAINID_REPO, else the checkout chainid was installed from, else
# a folder above this notebook's; the shared data: $CHAINID_SHARED, else `shared` next to the repository
roots = [Path(os.environ["CHAINID_REPO"])] if os.environ.get("CHAINID_REPO") else []
roots += [Path(chainid.__file__).resolve().parents[1], Path.cwd(), *Path.cwd().parents]
repo = next((p for p in roots if (p / "examples" / "readers").is_dir()), None)
shared = Path(os.environ.get("CHAINID_SHARED") or (repo.parent / "shared" if repo else "/nonexistent"))
real = shared / "realdata" / "pneumatic-seal"
have_data = repo is not None and real.is_dir()
print("shared data:", real if have_data else "absent (set CHAINID_SHARED); the cells below skip their work")
work = Path(tempfile.mkdtemp(prefix="chainid_nb07_"))

# %% [markdown]
# ## 1. Read the rig's files
# One command reads the twelve raw files (three seals × four pressures) with the example reader profile: the
# position, the force, and the mean pressure of each test as the covariates `p_bar` (nominal, from the file name)
# and `p_mean_bar` (measured).

# %%
csv = work / "seal.csv"
if have_data:
    assert main(["convert", str(real / "*.csv"), "--reader", str(repo / "examples/readers/pneumatic_seal.toml"),
                 "--to", str(csv)]) == 0
    print((work / "seal.covariates.csv").read_text()[:300])

# %% [markdown]
# ## 2. Diagnose one seal, the 5 bar test held out
# `--model linear` is the linear device; `--covariates` lets every effect's amplitude follow the pressure.  The
# summary says where the base misses, which effects in order close the gap (each scored leave-one-test-out on
# the training tests, then on the held-out test), what is left against the noise, and the model-free check.

# %%
js, model_file = work / "nap310.json", work / "nap310.toml"
if have_data:
    main(["diagnose", str(csv), "--covariates", str(work / "seal.covariates.csv"), "--tests", "NAP310*",
          "--model", "linear", "--holdout", "NAP310_5bar", "--resamples", "0", "--json", str(js),
          "--save-model", str(model_file), "--quiet"])
    res = json.loads(js.read_text())
    print("verdict:", res["verdict"], "| mechanism:", res["mechanism"])
    print(f"held-out NRMSE {res['baseline']['nrmse_holdout']:.3f} -> {res['left_nrmse_holdout']:.3f}; "
          f"fit left {res['fit_holdout_pct']:.1f} %; residual {res['residual']['db_over_noise']:.1f} dB over the noise")
    for c in res["covariate_dependence"]:
        print("operating condition:", c["text"])
    print("model-free check:", res["open_world"]["message"])

# %% [markdown]
# The seal's friction force grows with the pressure on its lip: the diagnosis finds the hysteresis (friction with
# a smooth pre-sliding branch) and its amplitude's slope in N per bar from the four tests together.  Physically,
# the amplitude must stay positive at the lowest pressure tested; check it from the law:

# %%
if have_data:
    law = next(c for c in res["covariate_dependence"] if c["covariate"] == "p_bar")
    for p in (1.0, 3.0, 5.0, 7.0):
        print(f"p = {p:.0f} bar: {law['param']} = {law['value_at_ref'] + law['slope'] * (p - law['ref']):.2f} N")

# %% [markdown]
# ## 3. The model file runs elsewhere
# The model the diagnosis found is a file: `chainid predict` scores it on any records (here all four pressures),
# the base alone beside it.

# %%
if have_data:
    pj = work / "predict.json"
    main(["predict", str(model_file), str(csv), "--covariates", str(work / "seal.covariates.csv"),
          "--tests", "NAP310*", "--json", str(pj), "--quiet"])
    pred = json.loads(pj.read_text())
    print(json.dumps({k: v for k, v in pred.items() if k in ("nrmse_baseline", "nrmse_model", "pooled")}, indent=1)[:800])

# %% [markdown]
# ## 4. What is left
# `residual.db_over_noise` is what the chain leaves over the records' own noise floor (σ from the second
# differences of the force); the model-free check fits a learner on the state (x, ẋ, travel since reversal, the
# covariates) to the training residual and scores it on the held-out test: its share is how much of what is left
# any model of the state could still explain.  A large share says an effect outside the library; a share near
# zero with a residual over the floor says a change in time or noise the floor underestimates.

# %%
if have_data:
    ow = res["open_world"]
    print(f"left: {res['residual']['db_over_noise']:.1f} dB over the noise floor; "
          f"model-free share {ow['predictable_share']}; significant: {ow['significant']}")
    for w in res["warnings"][:4]:
        print("warning:", w)

# %% [markdown]
# The scratch folder this notebook made (the converted records, the model file, the JSON) is removed; copy what
# you want to keep out of `work` before this cell.

# %%
shutil.rmtree(work, ignore_errors=True)
