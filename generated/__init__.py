# GENERATED FILE - DO NOT EDIT.  Written by `chainid generate`.
# derivation source hash: 9da5adbac9c5967a
"""Generated numba kernels, one module per model variant (see derive/)."""

VARIANTS = ('inner_bend', 'inner_bend_shear', 'paper', 'shear')
