# GENERATED FILE - DO NOT EDIT.  Written by `chainid generate`.
# derivation source hash: 6ae63232cad9069f
"""Generated numba kernels, one module per model variant (see derive/)."""

VARIANTS = ('inner_bend', 'inner_bend_shear', 'paper', 'shear')
