# GENERATED FILE - DO NOT EDIT.  Written by `chainid generate`.
# derivation source hash: b8c5f78c1b5fa634
"""Generated numba kernels, one module per model variant (see derive/)."""

VARIANTS = ('inner_bend', 'inner_bend_shear', 'paper', 'shear')
