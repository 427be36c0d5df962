"""Natural modes (chainid.dynamics.modes): normalised shapes at the free nodes, a line without a free node."""
from __future__ import annotations

import math

import numpy as np
import pytest

from chainid.dynamics import ChainLine


def test_modes_of_a_line_without_a_free_node_are_empty():
    """One segment with a fixed far end has no free node: every array of the modes is empty (the documented
    "empty arrays when no node is free"), for any n_modes."""
    from chainid.dynamics.modes import modes

    line = ChainLine(n_links=10, n_masses=1, pretension_N=1_000.0, far_end="fixed")
    for n in (None, 3):
        md = modes(line, n_modes=n)
        assert md.omega.shape == (0,) and md.frequency_hz.shape == (0,) and md.shapes.shape == (0, 0)
        assert md.nodes.shape == (0,) and md.positions.shape == (0,)


def test_mode_shapes_normalised_positive_at_their_largest_and_placed_at_the_free_nodes():
    """modes(): each shape solves 1e3·K φ = ω² M φ (the dense tangent system), is scaled to max |φ| = 1 with that
    largest entry +1; the free nodes of a tensioner line of 4 segments of 5 links are 1..4 at 250, 500, 750,
    1000 mm (50 mm pitch; a fixed end drops node 4); f = ω/2π; n_modes beyond the free nodes gives them all;
    n_modes must be an int >= 1."""
    from chainid.dynamics.modes import modes, tangent_system

    line = ChainLine(n_links=20, n_masses=4, pretension_N=2_000.0, tensioner_stiffness=50.0)
    md = modes(line)
    M, K, nodes = tangent_system(line)
    for j in range(4):
        phi, w = md.shapes[:, j], md.omega[j]
        np.testing.assert_allclose(1e3 * K @ phi, w * w * M * phi, rtol=1e-9, atol=1e-9 * w * w * M.max())
        assert np.max(np.abs(phi)) == pytest.approx(1.0, rel=1e-15) and phi[np.argmax(np.abs(phi))] == 1.0
    assert md.nodes.tolist() == [1, 2, 3, 4] and md.positions.tolist() == [250.0, 500.0, 750.0, 1000.0]
    np.testing.assert_allclose(md.frequency_hz, md.omega / (2 * math.pi), rtol=1e-15)
    assert np.all(np.diff(md.omega) > 0)
    assert modes(line, n_modes=9).omega.size == 4 and modes(line, n_modes=2).shapes.shape == (4, 2)
    fixed = modes(ChainLine(n_links=20, n_masses=4, pretension_N=2_000.0, far_end="fixed"))
    assert fixed.nodes.tolist() == [1, 2, 3] and fixed.positions.tolist() == [250.0, 500.0, 750.0]
    for bad in (0, 2.0, True):
        with pytest.raises(ValueError, match=rf"^n_modes = {bad!r} is invalid: valid range None or an int >= 1$"):
            modes(line, n_modes=bad)


def test_an_unloaded_chain_has_no_stiffness_and_zero_frequencies():
    """Without pretension every segment sits at F = 0, where the Hertz contact's tangent dF/dx = 0 (x ∝ F^(2/3)):
    the tangent stiffness is 0 and every natural frequency of the 4 free nodes is exactly 0 rad/s (no clipping
    away from 0).  Bug caught: the clip of the eigenvalues at 0 moved."""
    from chainid.dynamics.modes import modes

    line = ChainLine(n_links=20, n_masses=4)
    assert line.static_tangent().tolist() == [0.0] * 4
    md = modes(line)
    assert md.omega.tolist() == [0.0] * 4 and md.frequency_hz.tolist() == [0.0] * 4
