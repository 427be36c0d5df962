"""Model-file texts for the tests: the paper's 16-link specimen as an augmented model file (chain base, no
effects, no damping section), to which a test appends its damping or effects.  Units: mm, N, s, kg, MPa."""
from __future__ import annotations

SPECIMEN = """format_version = 1
kind = "chainid-augmented-model"
mass_kg = 3.2
delay_s = 0.0
[units]
length = "mm"
force = "N"
time = "s"
mass = "kg"
[base]
model = "chain"
variant = "paper"
[base.chain]
d = 14.0
pitch = 50.0
width = 17.0
n = 16
E = 210000.0
nu = 0.3
mass_per_m = 4.0
"""
