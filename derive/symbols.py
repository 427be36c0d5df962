"""Symbols of the derivation, named as in the paper (Eq. 2–16).

All lengths in mm, forces in N, moduli in MPa.
"""
import sympy as sp

# Load and internal forces (Eq. 2–3)
F_k = sp.Symbol("F_k", positive=True)        # axial tension on one link, N
N = sp.Symbol("N", positive=True)            # axial force in one side of the link, N
M_1 = sp.Symbol("M_1", real=True)            # redundant moment at the symmetry section A, N·mm
theta = sp.Symbol("theta", nonnegative=True) # subtended angle along the bend, rad
s = sp.Symbol("s", nonnegative=True)         # arc length along the straight segment, mm

# Geometry (Fig. 3)
d = sp.Symbol("d", positive=True)            # bar diameter, mm
R = sp.Symbol("R", positive=True)            # bend radius of the centre line, mm
L = sp.Symbol("L", positive=True)            # half straight length, mm
pitch = sp.Symbol("p", positive=True)        # inner length, mm
width = sp.Symbol("b", positive=True)        # inner width, mm
n = sp.Symbol("n", positive=True, integer=True)  # links between fixtures

# Material
E = sp.Symbol("E", positive=True)            # Young's modulus, MPa
mu = sp.Symbol("mu", positive=True)          # Poisson's ratio (the paper's μ)
G = sp.Symbol("G", positive=True)            # shear modulus, MPa

# Section (Eq. 5)
A_S = sp.Symbol("A_S", positive=True)        # cross-section area, mm²
J_1 = sp.Symbol("J_1", positive=True)        # second moment of area, straight bar, mm⁴
J_2 = sp.Symbol("J_2", positive=True)        # second moment about the curved bar's neutral axis, mm⁴
alpha = sp.Symbol("alpha", positive=True)    # neutral-axis offset of the curved bar, mm
kappa = sp.Symbol("kappa", positive=True)    # shear energy form factor (paper: 1; solid circle: 10/9)

# Hertz contact (Eq. 11–14)
rho_1, rho_2 = sp.symbols("rho_1 rho_2", positive=True)          # convex radii (bar section), mm
rho_1p, rho_2p = sp.symbols("rho_1' rho_2'", negative=True)      # radii along the bend (concave < 0), mm
rho = sp.Symbol("rho", positive=True)        # half curvature sum A + B, 1/mm
k_1, k_2 = sp.symbols("k_1 k_2", positive=True)  # (1 - μ²)/(π E), 1/MPa
e = sp.Symbol("e", positive=True)            # contact radius, mm
r = sp.Symbol("r", nonnegative=True)         # radial coordinate in the contact, mm
phi = sp.Symbol("phi", real=True)            # polar angle in the contact
omega_c = sp.Symbol("omega_c", real=True)    # angle between the principal planes of the two links
delta = sp.Symbol("delta", positive=True)    # mutual approach of two links, mm

# Chain (Eq. 15)
x = sp.Symbol("x", positive=True)            # chain elongation, mm
u = sp.Symbol("u", positive=True)            # F_k**(1/3), N**(1/3)
c_lin = sp.Symbol("c_lin", positive=True)    # linear compliance of the chain, mm/N
c_hertz = sp.Symbol("c_hertz", nonnegative=True)  # Hertz coefficient, mm/N**(2/3)
