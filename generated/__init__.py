# GENERATED FILE - DO NOT EDIT.  Written by `chainid generate`.
# derivation source hash: 019f9a63c9409ee7
"""Generated numba kernels, one module per model variant (see derive/)."""

VARIANTS = ('inner_bend', 'inner_bend_shear', 'paper', 'shear')
