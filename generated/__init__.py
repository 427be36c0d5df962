# GENERATED FILE - DO NOT EDIT.  Written by `chainid generate`.
# derivation source hash: 57811e3a2443dd06
"""Generated numba kernels, one module per model variant (see derive/)."""

VARIANTS = ('inner_bend', 'inner_bend_shear', 'paper', 'shear')
