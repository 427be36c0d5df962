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
# # 5. Multi-mass chain dynamics on the generated kernels
#
# The paper identifies the chain spring F_k(x) (and its tangent k_e) and a damping c_e(ω, A) so that they
# can go into dynamic models of chain drives.  `chainid.dynamics` is that downstream model: a chain of
# `n_links` links lumped into N masses, every segment the generated spring of its links (no compression),
# a viscous-equivalent damper, a prescribed drive (start-up ramp, sinusoid, sprocket polygon effect), a
# fixed or tensioner far end, moving resistance and load steps.  Units: mm, N, s, kg.
#
# Two studies: a 200 m scraper-conveyor chain starting up, and the tension ripple of the polygon effect.

# %%
import math

import matplotlib.pyplot as plt
import numpy as np

from chainid.dynamics import ChainLine, Drive, simulate
from chainid.dynamics.modes import modes
from chainid.dynamics.plots import plot_drive_tension, plot_heatmap, plot_modes
from chainid.dynamics.sweeps import as_table, sweep

# %% [markdown]
# ## Conveyor start-up
#
# 200 m of the 14×50 chain (4000 links, 4 kg/m) in 400 masses, 5 kN take-up (tensioner) force, 20 kN of
# moving resistance (scraper and load friction), a 2 s start-up to 1 m/s.  Damping: the Table 1 values of
# c_e were measured at 0.05–0.5 Hz on a 16-link specimen; a time-domain model needs one viscous equivalent
# at a stated operating point (see the README).  Here, for illustration, c_e = 5 N·s/mm for the specimen.

# %%
line = ChainLine(n_links=4000, n_masses=400, pretension_N=5000.0, resistance_N=20000.0, damping=5.0)
drive = Drive("ramp", v=1000.0, t_ramp=2.0)
res = simulate(line, drive, 10.0, peak_force=60000.0)
print(res.summary())

# %%
plot_heatmap(res, "Conveyor start-up: tension along the 200 m chain");

# %% [markdown]
# The tension front runs from the drive into the chain while the resistance is overcome node by node;
# once the whole strand moves, the chain oscillates about the steady tension (take-up + resistance) in its
# first mode.

# %%
plot_drive_tension(res);

# %%
md = modes(line, n_modes=4)
print("natural frequencies about the pretension [Hz]:", np.round(md.frequency_hz, 3))
plot_modes(md);

# %% [markdown]
# Energy balance of the run (N·mm): the work of the drive and of the external forces equals the change
# of kinetic and elastic energy plus the damper dissipation.

# %%
res.energy_balance()

# %% [markdown]
# ## Sprocket polygon effect: tension ripple against drive speed
#
# A pocket wheel of 5 pockets wraps the round link chain as a polygon of z = 10 sides of one pitch: the
# chain speed varies as v̄·(π/z)/sin(π/z)·cos φ, with the period p/v̄ of one pitch (derivation in
# `chainid.dynamics.drives`).  A 50 m chain (1000 links, 100 masses), 10 kN take-up, 5 kN resistance; the
# peak-to-peak drive-end tension over the last quarter of a 3 s run, for several mean speeds.  The sweep
# runs on `chainid.infra.parallel.run_cases` (here `scheduler="serial"` to keep the notebook light; the default
# is a dask LocalCluster).

# %%
line50 = ChainLine(n_links=1000, n_masses=100, pretension_N=10000.0, resistance_N=5000.0, damping=5.0)
poly = Drive("polygon", v=500.0, t_ramp=1.0, z=10)
speeds = np.array([250.0, 500.0, 750.0, 1000.0, 1250.0, 1500.0])
rows = sweep(line50, poly, 3.0, speeds=speeds, scheduler="serial", progress=False, peak_force=40000.0)
tab = as_table(rows)
md50 = modes(line50, n_modes=3)
f_poly = speeds / line50.chain.pitch  # Hz: one pitch per period
for v, f, r in zip(speeds, f_poly, tab[:, 5]):
    print(f"v = {v:6.0f} mm/s  polygon frequency {f:5.1f} Hz  ripple {r:8.1f} N")
print("first natural frequencies [Hz]:", np.round(md50.frequency_hz, 2))

# %%
fig, ax = plt.subplots(figsize=(7, 3.5))
ax.plot(speeds / 1000, tab[:, 5] / 1000, "o-")
ax.set_xlabel("mean chain speed [m/s]")
ax.set_ylabel("drive-end tension ripple [kN]")
ax.set_title("Polygon effect (z = 10): tension ripple vs speed")
ax.grid(True, alpha=0.3)
fig.tight_layout()

# %% [markdown]
# The ripple grows with speed overall: the polygon's speed variation is a fixed fraction of v̄
# (1 − cos(π/z) ≈ 5 % for z = 10) at the frequency v̄/p, and the chain answers it through its impedance
# √(k_e·ℓ_s·ρ_l); it is amplified where v̄/p comes near a natural frequency of the chain (printed above),
# which is what a drive designer has to keep away from.
