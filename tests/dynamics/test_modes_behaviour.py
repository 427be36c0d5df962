"""Natural modes of the chain line (chainid.dynamics.modes) against closed forms of uniform spring–mass chains and
an independent scipy eigen-solution of the stiffness matrix assembled here from Eq. 16 (tests/paper_forms.py).

A uniform chain is made of equal segments whose contact term is scaled away (hertz_scale 1e-12: the tangent is
1/c_lin,j to ~1e-11), so every segment has k = 1/c_lin,j = 5/CL(20) N/mm for 20 links in 5 segments of 4, and
every free node the mass m = 4 kg/m·0.2 m = 0.8 kg.  With ü in mm/s², ω² = 1e3·k/m·λ.  Units mm, N, s, kg."""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.linalg import eigh

import paper_forms
from chainid.dynamics import ChainLine
from chainid.dynamics.modes import modes, tangent_tridiagonal

N, M_SEG = 5, 0.8
K_SEG = 1.0 / (paper_forms.coefficients(n=20)[0] / N)
UNIFORM = dict(n_links=20, n_masses=N, pretension_N=1_000.0, hertz_scale=1e-12)


def _scale(phi):
    """Columns scaled to max |φ| = 1 with that entry positive (the documented normalisation)."""
    i = np.argmax(np.abs(phi), axis=0)
    return phi / phi[i, np.arange(phi.shape[1])][None, :]


def test_fixed_free_uniform_chain_has_the_closed_form_frequencies_and_shapes():
    """Drive lumping with a tensioner end (no take-up stiffness) and a tail mass equal to one segment's: n = 5 equal
    masses, node 0 held, node 5 free: ω_j = 2·√(1e3·k/m)·sin((2j − 1)π/(2(2n + 1))) and the shapes
    φ_i = sin((2j − 1)π·i/(2n + 1)), i = 1..n (closed form of the fixed–free chain).
    Bugs caught: the 1e3 unit factor, the free node set, the mass of the tail node."""
    line = ChainLine(**UNIFORM, lumping="drive", tail_mass_kg=M_SEG)
    md = modes(line)
    j = np.arange(1, N + 1)
    w0 = math.sqrt(1e3 * K_SEG / M_SEG)
    np.testing.assert_allclose(md.omega, 2.0 * w0 * np.sin((2 * j - 1) * math.pi / (2 * (2 * N + 1))), rtol=1e-8)
    i = np.arange(1, N + 1)[:, None]
    want = _scale(np.sin((2 * j[None, :] - 1) * math.pi * i / (2 * N + 1)))
    np.testing.assert_allclose(md.shapes, want, atol=1e-8)


def test_fixed_fixed_uniform_chain_has_the_closed_form_frequencies():
    """Half lumping with a fixed far end: the n − 1 = 4 inner nodes carry m each and both ends are held:
    ω_j = 2·√(1e3·k/m)·sin(jπ/(2n)), j = 1..4, shapes φ_i = ±sin(jπi/n)/sin(2π/5) (n = 5); a take-up stiffness
    of a fixed end is ignored.  Bugs caught: the last free node N − 1 → N, the take-up spring added to a fixed
    end's last node."""
    line = ChainLine(**UNIFORM, far_end="fixed", tensioner_stiffness=5_000.0)
    md = modes(line)
    j = np.arange(1, N)
    w0 = math.sqrt(1e3 * K_SEG / M_SEG)
    np.testing.assert_allclose(md.omega, 2.0 * w0 * np.sin(j * math.pi / (2 * N)), rtol=1e-8)
    i = np.arange(1, N)[:, None]
    want = np.sin(j[None, :] * math.pi * i / N) / np.sin(2 * math.pi / 5)  # max |φ| = sin(2π/5) for every j
    sign = np.sign(np.sum(md.shapes * want, axis=0))  # a tie of ±1 entries: the sign is the solver's choice
    np.testing.assert_allclose(md.shapes * sign, want, atol=1e-8)
    assert md.nodes.tolist() == [1, 2, 3, 4]


def _hand_system(n_links, n_masses, F, k_take_up, tail, fixed):
    """(K [N/mm], M [kg]) of the free nodes from Eq. 16 per segment (c_lin ∝ n_s, c_h ∝ contacts) by hand."""
    CL, CH = paper_forms.coefficients(n=n_links)
    ns = np.full(n_masses, n_links // n_masses)
    contacts = ns.astype(float)
    contacts[-1] -= 1
    k = 1.0 / (CL * ns / n_links + (2 / 3) * CH * contacts / (n_links - 1) * F ** (-1 / 3))
    ms = 4.0 * ns * 50.0 * 1e-3
    m = np.zeros(n_masses + 1)
    m[:-1] += ms / 2
    m[1:] += ms / 2
    m[-1] += tail
    nf = n_masses - 1 if fixed else n_masses
    K = np.zeros((nf, nf))
    for s in range(n_masses):  # segment s joins nodes s and s + 1 (free node a = node − 1)
        for a in (s - 1, s):
            if 0 <= a < nf:
                K[a, a] += k[s]
        if 0 <= s - 1 and s < nf:
            K[s - 1, s] -= k[s]
            K[s, s - 1] -= k[s]
    if not fixed:
        K[-1, -1] += k_take_up
    return K, m[1:nf + 1]


@pytest.mark.parametrize("fixed", [False, True])
def test_frequencies_of_a_pretensioned_line_with_a_take_up_spring_match_scipy(fixed):
    """20 links in 4 segments at 2 kN, a 3 kg tail and a take-up spring of 5000 N/mm (a third of a segment's
    tangent): ω² are the generalised eigenvalues of 1e3·K v = λ M v with K, M assembled here (scipy.linalg.eigh);
    with a fixed end the take-up spring and node 4 drop out; the shapes are scipy's eigenvectors scaled to max |φ| = 1
    (unequal masses: φ = M^(−1/2)·y).  Bugs caught: the take-up spring dropped or put on node 1, the off-diagonal
    taken from the wrong segment or scaled by one mass twice, the mass of the wrong node, φ = y."""
    line = ChainLine(n_links=20, n_masses=4, pretension_N=2_000.0, tensioner_stiffness=5_000.0, tail_mass_kg=3.0,
                     far_end="fixed" if fixed else "tensioner")
    K, M = _hand_system(20, 4, 2_000.0, 5_000.0, 3.0, fixed)
    lam, vec = eigh(1e3 * K, np.diag(M))
    md = modes(line)
    np.testing.assert_allclose(md.omega, np.sqrt(lam), rtol=1e-7)
    np.testing.assert_allclose(md.shapes, _scale(vec), atol=1e-6)
    Mt, d, e, nodes = tangent_tridiagonal(line)
    np.testing.assert_allclose(Mt, M, rtol=1e-12)
    np.testing.assert_allclose(d, np.diag(K), rtol=1e-7)
    np.testing.assert_allclose(e, np.diag(K, 1), rtol=1e-7)


def test_n_modes_keeps_the_lowest_modes_and_their_shapes():
    """n_modes = 2 of the fixed–free uniform chain: the two lowest of the closed form (j = 1, 2) and the same shape
    columns as the full solution.  Bug caught: the selected index range shifted (modes 2 and 3)."""
    line = ChainLine(**UNIFORM, lumping="drive", tail_mass_kg=M_SEG)
    full, two = modes(line), modes(line, n_modes=2)
    w0 = math.sqrt(1e3 * K_SEG / M_SEG)
    np.testing.assert_allclose(two.omega, 2 * w0 * np.sin(np.array([1, 3]) * math.pi / 22), rtol=1e-8)
    np.testing.assert_allclose(two.shapes, full.shapes[:, :2], atol=1e-10)
    assert two.frequency_hz == pytest.approx(two.omega / (2 * math.pi), rel=1e-15)


def test_free_node_positions_follow_unequal_segments():
    """11 links in 4 segments (3, 3, 3, 2 links of 50 mm): the free nodes 1..4 sit at 150, 300, 450, 550 mm from the
    drive; with a fixed end nodes 1..3 at 150, 300, 450 mm.  Bug caught: positions not offset by the drive node's
    0 (each one segment early)."""
    line = ChainLine(n_links=11, n_masses=4, pretension_N=1_000.0)
    assert modes(line).positions.tolist() == [150.0, 300.0, 450.0, 550.0]
    fixed = modes(ChainLine(n_links=11, n_masses=4, pretension_N=1_000.0, far_end="fixed"))
    assert fixed.positions.tolist() == [150.0, 300.0, 450.0] and fixed.shapes.shape == (3, 3)
