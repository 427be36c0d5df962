# GENERATED FILE - DO NOT EDIT.  Written by `chainid generate`.
# derivation source hash: aefe9e993c6876f3
"""Generated numba kernels, one module per model variant (see derive/)."""

VARIANTS = ('inner_bend', 'inner_bend_shear', 'paper', 'shear')
