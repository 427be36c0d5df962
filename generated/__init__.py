# GENERATED FILE - DO NOT EDIT.  Written by `chainid generate`.
# derivation source hash: 35ebc0a8c8c8aa81
"""Generated numba kernels, one module per model variant (see derive/)."""

VARIANTS = ('inner_bend', 'inner_bend_shear', 'paper', 'shear')
