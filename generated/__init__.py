# GENERATED FILE - DO NOT EDIT.  Written by `chainid generate`.
# derivation source hash: d75e7fae3b4c59ac
"""Generated numba kernels, one module per model variant (see derive/)."""

VARIANTS = ('inner_bend', 'inner_bend_shear', 'paper', 'shear')
