# GENERATED FILE - DO NOT EDIT.  Written by `chainid generate`.
# derivation source hash: fd917c5a6be47f9b
"""Generated numba kernels, one module per model variant (see derive/)."""

VARIANTS = ('inner_bend', 'inner_bend_shear', 'paper', 'shear')
