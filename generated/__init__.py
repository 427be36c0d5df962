# GENERATED FILE - DO NOT EDIT.  Written by `chainid generate`.
# derivation source hash: 29e4ad3dec994e53
"""Generated numba kernels, one module per model variant (see derive/)."""

VARIANTS = ('inner_bend', 'inner_bend_shear', 'paper', 'shear')
