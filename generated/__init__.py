# GENERATED FILE - DO NOT EDIT.  Written by `chainid generate`.
# derivation source hash: 00e57ba22c41b58e
"""Generated numba kernels, one module per model variant (see derive/)."""

VARIANTS = ('inner_bend', 'inner_bend_shear', 'paper', 'shear')
