# GENERATED FILE - DO NOT EDIT.  Written by `chainid generate`.
# derivation source hash: a46d068e7c4b88a7
"""Generated numba kernels, one module per model variant (see derive/)."""

VARIANTS = ('inner_bend', 'inner_bend_shear', 'paper', 'shear')
